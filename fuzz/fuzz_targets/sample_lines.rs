//! The `sample` command's line parser and both samplers behind it
//! (`sample_lines`: the original fixed-point sampler; `sample_lines_state`:
//! the GPU-style sampler with options). The first bytes choose the options
//! (address modes, format, sRGB, bias and lod clamps as arbitrary f64, max
//! anisotropy), the rest is the input text. Besides "never panics": a run
//! either samples every line, writing one `r,g,b,a` line each, or stops at
//! the first bad line with an error naming that line, everything before it
//! written; options that the command rejects are errors, not panics.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use clap::ValueEnum;
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use raymip::texture::AddressMode;
use raymip_host::cli::sample::{
    AddressArg, FormatArg, OwnedPyramid, PrecisionArg, SampleArgs, SampleError, build_pyramid,
    sample_lines, sample_lines_state,
};
use raymip_host::scene::ppm::RgbImage;

/// A 6×4 texture with distinct texels, its full pyramid.
fn pyramid() -> &'static OwnedPyramid {
    static P: OnceLock<OwnedPyramid> = OnceLock::new();
    P.get_or_init(|| {
        let img = RgbImage {
            width: 6,
            height: 4,
            pixels: (0..24u8).map(|i| [i * 10, 255 - i * 7, i * 3]).collect(),
        };
        build_pyramid(&img, None, &PathBuf::from("fuzz.ppm")).unwrap()
    })
}

fn args(u: &mut Unstructured) -> Result<SampleArgs> {
    let opt_f64 = |u: &mut Unstructured| -> Result<Option<f64>> {
        Ok(if u.ratio(1, 3)? {
            Some(u.arbitrary()?)
        } else {
            None
        })
    };
    let n_addr = u.int_in_range(1..=2)?;
    let mut address = Vec::new();
    for _ in 0..n_addr {
        address.push(*u.choose(AddressArg::value_variants())?);
    }
    Ok(SampleArgs {
        texture: PathBuf::from("fuzz.ppm"),
        levels: None,
        address,
        border: if u.arbitrary()? {
            Some(u.arbitrary()?)
        } else {
            None
        },
        format: *u.choose(FormatArg::value_variants())?,
        srgb: u.arbitrary()?,
        linear_output: u.arbitrary()?,
        bias: if u.ratio(1, 2)? { u.arbitrary()? } else { 0.0 },
        min_lod: opt_f64(u)?,
        max_lod: opt_f64(u)?,
        max_aniso: u.arbitrary()?,
        precision: *u.choose(PrecisionArg::value_variants())?,
    })
}

fn check(input: &[u8], res: std::result::Result<usize, SampleError>, out: &[u8]) {
    let out = std::str::from_utf8(out).unwrap();
    let written = out.lines().count();
    for l in out.lines() {
        let v: Vec<u8> = l.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(v.len(), 4, "{l}");
    }
    let newlines = input.iter().filter(|&&b| b == b'\n').count();
    let lines = newlines + usize::from(!input.is_empty() && !input.ends_with(b"\n"));
    match res {
        Ok(n) => {
            assert_eq!(n, written);
            assert_eq!(n, lines, "{:?}", String::from_utf8_lossy(input));
        }
        Err(SampleError::Line { line, .. }) => {
            assert_eq!(written, line - 1);
            assert!(line <= lines.max(1));
        }
        Err(SampleError::Io(_)) => {} // invalid UTF-8 input
        Err(e) => panic!("unexpected error {e}"),
    }
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let Ok(a) = args(&mut u) else { return };
    let input = u.take_rest();
    let p = pyramid();
    if !a.uses_sampler_state() {
        let mut out = Vec::new();
        let addr = a.address[0].plain().unwrap_or(AddressMode::Wrap);
        let r = sample_lines(p, addr, input, &mut out, "<fuzz>");
        check(input, r, &out);
        return;
    }
    let Ok((state, format)) = a.state() else {
        return;
    };
    let mut out = Vec::new();
    let r = sample_lines_state(
        p,
        (state, format, a.precision.precision()),
        input,
        &mut out,
        "<fuzz>",
    );
    check(input, r, &out);
});
