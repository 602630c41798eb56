//! The CLI commands and their output: `render`, `compare`, `table1`,
//! `sample`, `stress` and the demo's `gen-data`, as library functions (the binaries
//! in `src/bin/` only parse arguments and dispatch).

use std::path::Path;

pub mod compare;
pub mod demo_data;
pub mod instances;
pub mod output;
pub mod pcpi_vectors;
pub mod render;
pub mod sample;
pub mod stress;
pub mod table1;
pub mod tradeoff;

pub use compare::cmd_compare;
pub use render::cmd_render;
pub use table1::cmd_table1;

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size `{s}`: expected WxH, e.g. 800x480"))?;
    let p = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|&n| n > 0 && n <= 16384)
            .ok_or_else(|| format!("size `{s}`: `{t}` is not a number in 1..=16384"))
    };
    Ok((p(w)?, p(h)?))
}

pub(crate) fn scene_label(spec: &str) -> String {
    spec.strip_prefix("builtin:").map_or_else(
        || {
            Path::new(spec)
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        },
        str::to_string,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_scene;

    #[test]
    fn sizes_and_scene_errors() {
        assert_eq!(parse_size("800x480"), Ok((800, 480)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        for bad in ["800", "0x10", "ax4", "10x", "99999x2"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        let e = load_scene("builtin:nope", 0.0).unwrap_err();
        assert!(e.contains("nope") && e.contains("hall"), "{e}");
        assert!(
            load_scene("/no/such/file.aff", 0.0)
                .unwrap_err()
                .contains("/no/such/file.aff")
        );
    }
}
