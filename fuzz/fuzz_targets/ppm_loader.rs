//! The PPM (P6) texture parser on arbitrary bytes. Besides "never panics,
//! no overflow, no runaway allocation": an image holds exactly
//! `width × height` pixels (both ≥ 1) and converts to as many RGBA8 texels
//! with alpha 255; an error names the file.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use raymip_host::scene::ppm::parse_ppm;

fuzz_target!(|data: &[u8]| {
    match parse_ppm(data, Path::new("fuzz.ppm")) {
        Err(e) => assert!(e.to_string().contains("fuzz.ppm"), "{e}"),
        Ok(img) => {
            assert!(img.width >= 1 && img.height >= 1);
            let n = img.width as usize * img.height as usize;
            assert_eq!(img.pixels.len(), n);
            let t = img.to_rgba8888();
            assert_eq!(t.len(), n);
            for (p, t) in img.pixels.iter().zip(&t) {
                let [r, g, b, a] = t.to_le_bytes();
                assert_eq!(([r, g, b], a), (*p, 255));
            }
        }
    }
});
