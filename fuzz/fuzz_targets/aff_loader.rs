//! The AFF scene loader with includes and PPM textures, all in memory
//! (`aff::load_from_memory`: the file system is never read). The input is
//! up to five files separated by the line `%%FILE`: `top.aff`, `a.aff`,
//! `b.aff`, `t.ppm`, `u.ppm` (the seeds include each other and name the
//! textures). Besides "never panics, no overflow, no leak, no runaway
//! allocation" it checks what the loader documents: an error names a
//! file (and the include chain), a scene keeps only finite triangles with
//! valid material and texture indices, and its triangle count is
//! `triangles_read − skipped_degenerate − hidden − skipped_non_finite`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raymip_host::scene::aff::{self, DEFAULT_TIME};

const NAMES: [&str; 5] = ["top.aff", "a.aff", "b.aff", "t.ppm", "u.ppm"];
const SEP: &[u8] = b"\n%%FILE\n";

fuzz_target!(|data: &[u8]| {
    let mut files: Vec<(&str, &[u8])> = Vec::new();
    let mut rest = data;
    for name in NAMES {
        match rest.windows(SEP.len()).position(|w| w == SEP) {
            Some(i) => {
                files.push((name, &rest[..i]));
                rest = &rest[i + SEP.len()..];
            }
            None => {
                files.push((name, rest));
                break;
            }
        }
    }
    match aff::load_from_memory(&files, "top.aff", DEFAULT_TIME) {
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.contains("mem"), "error names no file: {msg}");
        }
        Ok(s) => {
            let st = &s.stats;
            assert_eq!(
                s.triangles.len(),
                st.triangles_read - st.skipped_degenerate - st.hidden - st.skipped_non_finite
            );
            for t in &s.triangles {
                assert!(t.p.iter().all(|v| v.is_finite()), "{t:?}");
                assert!((t.material as usize) < s.materials.len().max(1), "{t:?}");
                if let Some(x) = t.texture {
                    assert!((x as usize) < s.textures.len(), "{t:?}");
                }
            }
            for t in &s.textures {
                let n = t.image.width as usize * t.image.height as usize;
                assert_eq!(t.image.pixels.len(), n);
            }
        }
    }
});
