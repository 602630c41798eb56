//! Outputs: PNG images, the rainbow mip-level image, PSNR and difference
//! heat-maps, JSON + Markdown reports, the machine line of a measurement.

use std::fs;
use std::io::BufWriter;
use std::path::Path;

/// Writes an RGB8 PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[[u8; 3]]) -> Result<(), String> {
    let f = fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut enc = png::Encoder::new(BufWriter::new(f), width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc
        .write_header()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let data: Vec<u8> = rgb.iter().flatten().copied().collect();
    w.write_image_data(&data)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Reads an 8-bit RGB or RGBA PNG as RGB8.
pub fn read_png(path: &Path) -> Result<(u32, u32, Vec<[u8; 3]>), String> {
    let f = fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let dec = png::Decoder::new(std::io::BufReader::new(f));
    let mut r = dec
        .read_info()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let mut buf = vec![0; r.output_buffer_size().unwrap_or(0)];
    let info = r
        .next_frame(&mut buf)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let ch = match (info.color_type, info.bit_depth) {
        (png::ColorType::Rgb, png::BitDepth::Eight) => 3,
        (png::ColorType::Rgba, png::BitDepth::Eight) => 4,
        other => {
            return Err(format!(
                "{}: unsupported PNG format {other:?}",
                path.display()
            ));
        }
    };
    let px = buf[..info.buffer_size()]
        .chunks_exact(ch)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Ok((info.width, info.height, px))
}

/// The mip-level palette (level 0 red, 1 orange, 2 yellow, 3 green, 4 cyan,
/// 5 blue, 6 violet, 7 magenta, 8+ grey to white), as in the ray-cone
/// paper's figures; fractional levels blend linearly.
pub const PALETTE: [[u8; 3]; 10] = [
    [230, 25, 25],
    [245, 140, 20],
    [240, 230, 30],
    [40, 200, 40],
    [30, 210, 220],
    [40, 70, 230],
    [140, 50, 220],
    [230, 40, 200],
    [170, 170, 170],
    [255, 255, 255],
];

/// Colour of a (clamped, ≥ 0) level; NaN (no textured hit) is black.
#[must_use]
pub fn level_color(level: f32) -> [u8; 3] {
    if level.is_nan() {
        return [0, 0, 0];
    }
    let l = level.clamp(0.0, (PALETTE.len() - 1) as f32);
    let i = l.floor() as usize;
    let f = l - i as f32;
    let a = PALETTE[i];
    let b = PALETTE[(i + 1).min(PALETTE.len() - 1)];
    std::array::from_fn(|k| {
        (f32::from(a[k]) + f * (f32::from(b[k]) - f32::from(a[k]))).round() as u8
    })
}

/// The mip-level image: palette colour of each pixel's lod clamped at 0.
#[must_use]
pub fn level_image(lod: &[f32]) -> Vec<[u8; 3]> {
    lod.iter()
        .map(|&l| level_color(if l.is_nan() { l } else { l.max(0.0) }))
        .collect()
}

/// PSNR in dB of two RGB8 images (peak 255); infinite if identical.
#[must_use]
pub fn psnr(a: &[[u8; 3]], b: &[[u8; 3]]) -> f64 {
    let n = a.len().min(b.len()) * 3;
    if n == 0 {
        return f64::INFINITY;
    }
    let se: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| (f64::from(x[k]) - f64::from(y[k])).powi(2)))
        .sum();
    let mse = se / n as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

/// Largest per-channel absolute difference.
#[must_use]
pub fn max_diff(a: &[[u8; 3]], b: &[[u8; 3]]) -> u8 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| x[k].abs_diff(y[k])))
        .max()
        .unwrap_or(0)
}

/// Heat-map of the per-pixel max channel difference: black (0) → red →
/// yellow → white (≥ `full` levels).
#[must_use]
pub fn heat_map(a: &[[u8; 3]], b: &[[u8; 3]], full: u8) -> Vec<[u8; 3]> {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (0..3).map(|k| x[k].abs_diff(y[k])).max().unwrap_or(0);
            let t = (f32::from(d) / f32::from(full.max(1))).min(1.0) * 3.0;
            let c = |s: f32| (s.clamp(0.0, 1.0) * 255.0).round() as u8;
            [c(t), c(t - 1.0), c(t - 2.0)]
        })
        .collect()
}

/// Writes `value` as pretty JSON.
pub fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), String> {
    let s = serde_json::to_string_pretty(value).map_err(|e| e.to_string())?;
    fs::write(path, s + "\n").map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes text.
pub fn write_text(path: &Path, text: &str) -> Result<(), String> {
    fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Replaces the text between the lines `<!-- NAME:begin -->` and
/// `<!-- NAME:end -->` of the file `path` (a README) with `text`: how the
/// measurement commands write their tables.
///
/// # Errors
/// When the file cannot be read or written or lacks the markers.
pub fn write_between_markers(path: &Path, name: &str, text: &str) -> Result<(), String> {
    let begin = format!("<!-- {name}:begin -->");
    let end = format!("<!-- {name}:end -->");
    let old = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let (Some(b), Some(e)) = (old.find(&begin), old.find(&end)) else {
        return Err(format!(
            "{}: markers {begin} / {end} not found",
            path.display()
        ));
    };
    if e < b {
        return Err(format!("{}: {end} before {begin}", path.display()));
    }
    let new = format!("{}{begin}\n{text}{}", &old[..b], &old[e..]);
    std::fs::write(path, new).map_err(|e| format!("{}: {e}", path.display()))
}

/// The file named after `--write` in a measurement command's arguments.
#[must_use]
pub fn write_option(args: &[String]) -> Option<&Path> {
    args.iter()
        .position(|a| a == "--write")
        .and_then(|i| args.get(i + 1))
        .map(Path::new)
}

/// Prints the Markdown `table` of a measurement and, when `write` names a
/// file (`--write FILE`), replaces its `NAME` block with it
/// ([`write_between_markers`]).
///
/// # Errors
/// As [`write_between_markers`].
pub fn publish(table: &str, write: Option<&Path>, name: &str) -> Result<(), String> {
    print!("{table}");
    if let Some(path) = write {
        write_between_markers(path, name, table)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// The CPU model from `/proc/cpuinfo` ("unknown CPU" where there is none).
#[must_use]
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

/// One line naming the machine, compiler and date of a measurement.
#[must_use]
pub fn machine_line() -> String {
    let cpu = cpu_model();
    let run = |cmd: &str, args: &[&str]| {
        std::process::Command::new(cmd)
            .args(args)
            .output()
            .ok()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| format!("{cmd}: unavailable"))
    };
    format!(
        "{cpu}, {} hardware threads (shared with other jobs), {}, {}",
        std::thread::available_parallelism().map_or(0, usize::from),
        run("rustc", &["-V"]),
        run("date", &["-u", "+%Y-%m-%d %H:%M UTC"]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn psnr_of_known_error() {
        // Every channel off by 1: MSE 1 → 20·log10(255) dB.
        let a = vec![[10u8, 20, 30]; 50];
        let b = vec![[11u8, 19, 31]; 50];
        assert!((psnr(&a, &b) - 20.0 * 255f64.log10()).abs() < 1e-9);
        assert!(psnr(&a, &a).is_infinite());
        assert_eq!(max_diff(&a, &b), 1);
        // Off by 16 in one channel of every pixel: MSE 256/3.
        let c = vec![[26u8, 20, 30]; 50];
        let want = 10.0 * (255.0f64 * 255.0 / (256.0 / 3.0)).log10();
        assert!((psnr(&a, &c) - want).abs() < 1e-9);
    }

    #[test]
    fn palette_and_heat_map() {
        assert_eq!(level_color(0.0), PALETTE[0]);
        assert_eq!(level_color(3.0), PALETTE[3]);
        assert_eq!(level_color(f32::NAN), [0, 0, 0]);
        assert_eq!(level_color(99.0), PALETTE[PALETTE.len() - 1]);
        let a = [[0u8; 3], [0; 3]];
        let b = [[0u8; 3], [200; 3]];
        assert_eq!(heat_map(&a, &b, 16), vec![[0, 0, 0], [255, 255, 255]]);
    }

    #[test]
    fn png_round_trip() {
        let dir = std::env::temp_dir().join(format!("raymip-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.png");
        let px: Vec<[u8; 3]> = (0..12u8).map(|i| [i, i * 2, 255 - i]).collect();
        write_png(&p, 4, 3, &px).unwrap();
        assert_eq!(read_png(&p).unwrap(), (4, 3, px));
        assert!(
            read_png(&dir.join("missing.png"))
                .unwrap_err()
                .contains("missing.png")
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
