//! PNG images (8-bit RGB) and the rainbow mip-level image.

use std::fs;
use std::io::BufWriter;
use std::path::Path;

use super::OutputError;
use crate::error::FileError;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::FileOp;

    #[test]
    fn palette() {
        assert_eq!(level_color(0.0), PALETTE[0]);
        assert_eq!(level_color(3.0), PALETTE[3]);
        assert_eq!(level_color(f32::NAN), [0, 0, 0]);
        assert_eq!(level_color(99.0), PALETTE[PALETTE.len() - 1]);
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
        std::fs::remove_dir_all(&dir).ok();
    }
}
