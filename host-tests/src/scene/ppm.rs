//! Binary PPM (P6) reader and writer.
//!
//! Accepts any width and height (non-power-of-two too) and `maxval` in
//! `1..=65535`; samples are rescaled to 8 bits with rounding. Comments
//! (`#` to end of line) are allowed in the header. Every error names the
//! file and what was wrong; nothing panics on malformed input.

use std::fmt;
use std::path::{Path, PathBuf};

/// An 8-bit RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbImage {
    /// Width in pixels (≥ 1).
    pub width: u32,
    /// Height in pixels (≥ 1).
    pub height: u32,
    /// `width · height` pixels, row-major.
    pub pixels: Vec<[u8; 3]>,
}

impl RgbImage {
    /// Pixels packed as RGBA8888 `u32` (`r | g << 8 | b << 16 | a << 24`)
    /// with alpha 255, the layout of the firmware's texel memory.
    pub fn to_rgba8888(&self) -> Vec<u32> {
        self.pixels
            .iter()
            .map(|&[r, g, b]| u32::from(r) | u32::from(g) << 8 | u32::from(b) << 16 | 0xFF00_0000)
            .collect()
    }
}

/// What went wrong reading a PPM file.
#[derive(Debug)]
pub struct PpmError {
    /// The file (or `<memory>`).
    pub path: PathBuf,
    /// Line of the header where the problem was found (1-based), when known.
    pub line: Option<usize>,
    /// The problem.
    pub message: String,
}

impl fmt::Display for PpmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{}: {}", self.path.display(), l, self.message),
            None => write!(f, "{}: {}", self.path.display(), self.message),
        }
    }
}

impl std::error::Error for PpmError {}

/// Reads a P6 file.
pub fn read_ppm(path: &Path) -> Result<RgbImage, PpmError> {
    let bytes = std::fs::read(path).map_err(|e| PpmError {
        path: path.to_path_buf(),
        line: None,
        message: format!("cannot read: {e}"),
    })?;
    parse_ppm(&bytes, path)
}

/// Parses P6 bytes; `path` is used only in error messages.
pub fn parse_ppm(bytes: &[u8], path: &Path) -> Result<RgbImage, PpmError> {
    let mut pos = 0usize;
    let mut line = 1usize;
    let err = |line: usize, message: String| PpmError {
        path: path.to_path_buf(),
        line: Some(line),
        message,
    };
    // Next whitespace-separated header token, skipping comments.
    let token = |pos: &mut usize, line: &mut usize| -> Option<(String, usize)> {
        loop {
            match bytes.get(*pos)? {
                b'#' => {
                    while let Some(&c) = bytes.get(*pos) {
                        if c == b'\n' {
                            break;
                        }
                        *pos += 1;
                    }
                }
                c if c.is_ascii_whitespace() => {
                    if *c == b'\n' {
                        *line += 1;
                    }
                    *pos += 1;
                }
                _ => break,
            }
        }
        let start = *pos;
        while let Some(c) = bytes.get(*pos) {
            if c.is_ascii_whitespace() || *c == b'#' {
                break;
            }
            *pos += 1;
        }
        Some((
            String::from_utf8_lossy(&bytes[start..*pos]).into_owned(),
            *line,
        ))
    };
    let magic = token(&mut pos, &mut line).ok_or_else(|| err(1, "empty file".into()))?;
    if magic.0 != "P6" {
        return Err(err(
            magic.1,
            format!("not a binary PPM: magic {:?}, expected \"P6\"", magic.0),
        ));
    }
    let mut field = |name: &str, max: u32| -> Result<u32, PpmError> {
        let (t, l) = token(&mut pos, &mut line)
            .ok_or_else(|| err(line, format!("truncated header: missing {name}")))?;
        let v: u32 = t
            .parse()
            .map_err(|_| err(l, format!("bad {name} {t:?}: not a whole number")))?;
        if v == 0 || v > max {
            return Err(err(l, format!("{name} {v} out of range 1..={max}")));
        }
        Ok(v)
    };
    let width = field("width", 1 << 16)?;
    let height = field("height", 1 << 16)?;
    let maxval = field("maxval", 65535)?;
    // Exactly one whitespace byte separates maxval from the raster.
    match bytes.get(pos) {
        Some(c) if c.is_ascii_whitespace() => pos += 1,
        _ => return Err(err(line, "missing whitespace after maxval".into())),
    }
    let bps = if maxval < 256 { 1 } else { 2 };
    let n = width as usize * height as usize;
    let need = n * 3 * bps;
    let raster = bytes.get(pos..pos + need).ok_or_else(|| PpmError {
        path: path.to_path_buf(),
        line: None,
        message: format!(
            "truncated raster: {width}x{height} needs {need} bytes, file has {}",
            bytes.len().saturating_sub(pos)
        ),
    })?;
    let scale = |v: u32| -> u8 { ((v.min(maxval) * 255 + maxval / 2) / maxval) as u8 };
    let sample = |i: usize| -> u8 {
        if bps == 1 {
            scale(u32::from(raster[i]))
        } else {
            scale(u32::from(raster[2 * i]) << 8 | u32::from(raster[2 * i + 1]))
        }
    };
    let pixels = if maxval == 255 {
        // 8-bit samples need no rescaling (the common case; fast path).
        raster.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
    } else {
        (0..n)
            .map(|p| [sample(3 * p), sample(3 * p + 1), sample(3 * p + 2)])
            .collect()
    };
    Ok(RgbImage {
        width,
        height,
        pixels,
    })
}

/// Writes `img` as P6.
pub fn write_ppm(path: &Path, img: &RgbImage) -> std::io::Result<()> {
    let mut out = format!("P6\n{} {}\n255\n", img.width, img.height).into_bytes();
    out.extend(img.pixels.iter().flatten());
    std::fs::write(path, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(bytes: &[u8]) -> Result<RgbImage, PpmError> {
        parse_ppm(bytes, Path::new("t.ppm"))
    }

    #[test]
    fn reads_small_image_with_comment() {
        let mut b = b"P6\n# made by hand\n2 1\n255\n".to_vec();
        b.extend([1, 2, 3, 250, 251, 252]);
        let img = p(&b).unwrap();
        assert_eq!((img.width, img.height), (2, 1));
        assert_eq!(img.pixels, vec![[1, 2, 3], [250, 251, 252]]);
        assert_eq!(img.to_rgba8888()[0], 0xFF03_0201);
    }

    #[test]
    fn rescales_maxval() {
        let mut b = b"P6 1 1 15\n".to_vec();
        b.extend([15, 0, 7]);
        assert_eq!(p(&b).unwrap().pixels, vec![[255, 0, 119]]);
        let mut b = b"P6 1 1 65535\n".to_vec();
        b.extend([0xFF, 0xFF, 0, 0, 0x80, 0x00]);
        assert_eq!(p(&b).unwrap().pixels, vec![[255, 0, 128]]);
    }

    #[test]
    fn malformed_inputs_are_errors_with_location() {
        let cases: &[(&[u8], &str)] = &[
            (b"", "empty"),
            (b"P3\n1 1\n255\n", "magic"),
            (b"P6\n1\n", "missing height"),
            (b"P6\nx 1 255\n", "bad width"),
            (b"P6\n0 1 255\n", "out of range"),
            (b"P6\n1 1 255\n\x01\x02", "truncated raster"),
            (b"P6\n1 1 70000\n", "maxval"),
        ];
        for (bytes, what) in cases {
            let e = p(bytes).unwrap_err().to_string();
            assert!(e.starts_with("t.ppm"), "{e}");
            assert!(e.contains(what), "expected {what:?} in {e:?}");
        }
    }

    #[test]
    fn missing_file_names_the_path() {
        let e = read_ppm(Path::new("/nonexistent/x.ppm"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/nonexistent/x.ppm") && e.contains("cannot read"),
            "{e}"
        );
    }

    #[test]
    fn write_then_read_round_trips() {
        let img = RgbImage {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| [i, 2 * i, 255 - i]).collect(),
        };
        let dir = std::env::temp_dir().join(format!("raymip-ppm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("rt.ppm");
        write_ppm(&f, &img).unwrap();
        assert_eq!(read_ppm(&f).unwrap(), img);
        std::fs::remove_dir_all(&dir).ok();
    }
}
