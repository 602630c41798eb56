//! Outputs: PNG images, the rainbow mip-level image, PSNR and difference
//! heat-maps, JSON + Markdown reports, the machine line of a measurement.

use std::fmt;
use std::fs;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use crate::error::FileError;

/// What went wrong writing or reading an output file.
#[derive(Debug)]
pub enum OutputError {
    /// The file could not be opened, created, read or written.
    File(FileError),
    /// The PNG encoder failed on the file.
    PngEncode {
        /// The file.
        path: PathBuf,
        /// The encoder's error.
        source: png::EncodingError,
    },
    /// The file is not a readable PNG.
    PngDecode {
        /// The file.
        path: PathBuf,
        /// The decoder's error.
        source: png::DecodingError,
    },
    /// The PNG is not 8-bit RGB or RGBA.
    PngFormat {
        /// The file.
        path: PathBuf,
        /// Its colour type.
        color: png::ColorType,
        /// Its bit depth.
        depth: png::BitDepth,
    },
    /// A value could not be serialised as JSON.
    Json {
        /// The file it was meant for.
        path: PathBuf,
        /// Serde's error.
        source: serde_json::Error,
    },
    /// The file lacks the `<!-- NAME:begin -->` / `<!-- NAME:end -->` lines.
    MissingMarkers {
        /// The file.
        path: PathBuf,
        /// The block's `NAME`.
        name: String,
    },
    /// The end marker comes before the begin marker.
    MarkersOutOfOrder {
        /// The file.
        path: PathBuf,
        /// The block's `NAME`.
        name: String,
    },
}

impl fmt::Display for OutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::File(e) => e.fmt(f),
            Self::PngEncode { path, source } => {
                write!(f, "{}: cannot encode PNG: {source}", path.display())
            }
            Self::PngDecode { path, source } => {
                write!(f, "{}: not a readable PNG: {source}", path.display())
            }
            Self::PngFormat { path, color, depth } => write!(
                f,
                "{}: unsupported PNG format {color:?} {depth:?} (expected 8-bit RGB or RGBA)",
                path.display()
            ),
            Self::Json { path, source } => {
                write!(f, "{}: cannot serialise JSON: {source}", path.display())
            }
            Self::MissingMarkers { path, name } => write!(
                f,
                "{}: markers <!-- {name}:begin --> / <!-- {name}:end --> not found",
                path.display()
            ),
            Self::MarkersOutOfOrder { path, name } => write!(
                f,
                "{}: <!-- {name}:end --> before <!-- {name}:begin -->",
                path.display()
            ),
        }
    }
}

impl std::error::Error for OutputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::File(e) => Some(e),
            Self::PngEncode { source, .. } => Some(source),
            Self::PngDecode { source, .. } => Some(source),
            Self::Json { source, .. } => Some(source),
            Self::PngFormat { .. }
            | Self::MissingMarkers { .. }
            | Self::MarkersOutOfOrder { .. } => None,
        }
    }
}

impl From<FileError> for OutputError {
    fn from(e: FileError) -> Self {
        Self::File(e)
    }
}

/// Writes an RGB8 PNG.
///
/// # Errors
/// When the file cannot be created or the encoder fails.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[[u8; 3]]) -> Result<(), OutputError> {
    let encode = |source| OutputError::PngEncode {
        path: path.to_path_buf(),
        source,
    };
    let f = fs::File::create(path).map_err(|e| FileError::write(path, e))?;
    let mut enc = png::Encoder::new(BufWriter::new(f), width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(encode)?;
    let data: Vec<u8> = rgb.iter().flatten().copied().collect();
    w.write_image_data(&data).map_err(encode)
}

/// Reads an 8-bit RGB or RGBA PNG as RGB8.
///
/// # Errors
/// When the file cannot be opened, is not a PNG, or is not 8-bit RGB(A).
pub fn read_png(path: &Path) -> Result<(u32, u32, Vec<[u8; 3]>), OutputError> {
    let decode = |source| OutputError::PngDecode {
        path: path.to_path_buf(),
        source,
    };
    let f = fs::File::open(path).map_err(|e| FileError::read(path, e))?;
    let dec = png::Decoder::new(std::io::BufReader::new(f));
    let mut r = dec.read_info().map_err(decode)?;
    let mut buf = vec![0; r.output_buffer_size().unwrap_or(0)];
    let info = r.next_frame(&mut buf).map_err(decode)?;
    let ch = match (info.color_type, info.bit_depth) {
        (png::ColorType::Rgb, png::BitDepth::Eight) => 3,
        (png::ColorType::Rgba, png::BitDepth::Eight) => 4,
        (color, depth) => {
            return Err(OutputError::PngFormat {
                path: path.to_path_buf(),
                color,
                depth,
            });
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

/// Writes `value` (a `serde_json::Value` or any serialisable type) as
/// pretty JSON.
///
/// # Errors
/// When the value cannot be serialised or the file written.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<(), OutputError> {
    let s = serde_json::to_string_pretty(value).map_err(|source| OutputError::Json {
        path: path.to_path_buf(),
        source,
    })?;
    fs::write(path, s + "\n").map_err(|e| FileError::write(path, e).into())
}

/// Writes text.
///
/// # Errors
/// When the file cannot be written.
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    fs::write(path, text).map_err(|e| FileError::write(path, e).into())
}

/// Replaces the text between the lines `<!-- NAME:begin -->` and
/// `<!-- NAME:end -->` of the file `path` (a README) with `text`: how the
/// measurement commands write their tables.
///
/// # Errors
/// When the file cannot be read or written or lacks the markers.
pub fn write_between_markers(path: &Path, name: &str, text: &str) -> Result<(), OutputError> {
    let begin = format!("<!-- {name}:begin -->");
    let end = format!("<!-- {name}:end -->");
    let old = std::fs::read_to_string(path).map_err(|e| FileError::read(path, e))?;
    let (Some(b), Some(e)) = (old.find(&begin), old.find(&end)) else {
        return Err(OutputError::MissingMarkers {
            path: path.to_path_buf(),
            name: name.to_string(),
        });
    };
    if e < b {
        return Err(OutputError::MarkersOutOfOrder {
            path: path.to_path_buf(),
            name: name.to_string(),
        });
    }
    let new = format!("{}{begin}\n{text}{}", &old[..b], &old[e..]);
    std::fs::write(path, new).map_err(|e| FileError::write(path, e).into())
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
pub fn publish(table: &str, write: Option<&Path>, name: &str) -> Result<(), OutputError> {
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
    use crate::error::FileOp;

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
        let missing = dir.join("missing.png");
        let e = read_png(&missing).unwrap_err();
        assert!(
            matches!(&e, OutputError::File(f) if f.path == missing && f.op == FileOp::Read),
            "{e}"
        );
        assert!(e.to_string().contains("missing.png: cannot read"), "{e}");
        std::fs::write(&missing, b"not a png").unwrap();
        let e = read_png(&missing).unwrap_err();
        assert!(
            matches!(&e, OutputError::PngDecode { path, .. } if *path == missing),
            "{e}"
        );
        let readme = dir.join("README.md");
        std::fs::write(&readme, "no markers\n").unwrap();
        let e = write_between_markers(&readme, "stress", "x").unwrap_err();
        assert!(
            matches!(&e, OutputError::MissingMarkers { name, .. } if name == "stress"),
            "{e}"
        );
        assert!(
            e.to_string()
                .contains("README.md: markers <!-- stress:begin -->"),
            "{e}"
        );
        std::fs::write(&readme, "<!-- stress:end -->\n<!-- stress:begin -->\n").unwrap();
        let e = write_between_markers(&readme, "stress", "x").unwrap_err();
        assert!(matches!(&e, OutputError::MarkersOutOfOrder { .. }), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
