//! The `sample` command: library function with in-memory input/output and
//! the `raymip-host` binary end to end. Expected colours are worked out by
//! hand from the test texture.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

use raymip::texture::AddressMode;
use raymip_host::cli::sample::{SampleError, build_pyramid, sample_lines};
use raymip_host::scene::ppm::{RgbImage, write_ppm};

/// 2×2 texture: red, green / blue, white. Level 1 (1×1) is the average
/// (128, 128, 128) per channel: (255+0+0+255+2)>>2 = 128.
fn image() -> RgbImage {
    RgbImage {
        width: 2,
        height: 2,
        pixels: vec![[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]],
    }
}

fn run_lib(input: &str, address: AddressMode) -> (Result<usize, SampleError>, String) {
    let p = build_pyramid(&image(), None, &PathBuf::from("test.ppm")).unwrap();
    let mut out = Vec::new();
    let r = sample_lines(&p, address, input.as_bytes(), &mut out, "<stdin>");
    (r, String::from_utf8(out).unwrap())
}

#[test]
fn modes_and_levels() {
    let input = "0.25,0.25,0,2\n0.75,0.25,0,0\n0.25,0.75,0,1\n0.75,0.75,0,3\n\
                 0.5,0.25,0,0\n0,0.25,0,0\n0.25,0.25,1,0\n0.25,0.25,0.5,3\n0.25,0.25,0.5,0\n\
                 1e6,-1e6,0,2\n0.25, 0.25 ,9,2\r\n";
    let (r, out) = run_lib(input, AddressMode::Wrap);
    assert_eq!(r.unwrap(), 11);
    let want = [
        "255,0,0,255",     // texel centre (0,0), nearest
        "0,255,0,255",     // texel centre (1,0), trilinear at lod 0
        "0,0,255,255",     // texel centre (0,1), bilinear
        "255,255,255,255", // texel centre (1,1), nearest texel, linear level
        "128,128,0,255",   // halfway red–green: 127.5 → 128
        "128,128,0,255",   // u = 0: wrap seam, halfway green–red
        "128,128,128,255", // lod 1: the 1×1 level
        "192,64,64,255",   // red and gray 128, half each: 191.5 → 192, 64
        "192,64,64,255",   // same through trilinear
        "255,0,0,255",     // ±1e6 wraps to (0, 0) → texel (0,0)
        "128,128,128,255", // lod 9 clamps to the top level
    ];
    assert_eq!(out.lines().collect::<Vec<_>>(), want);
}

#[test]
fn clamp_addressing() {
    let (r, out) = run_lib("0,0.25,0,0\n-5,7,0,1\n", AddressMode::ClampToEdge);
    assert_eq!(r.unwrap(), 2);
    assert_eq!(out, "255,0,0,255\n0,0,255,255\n"); // (-1, 2) clamps to texel (0, 1)
}

#[test]
fn malformed_lines_name_the_line() {
    for (input, line, what) in [
        ("0.5,0.5,0,0\n0.5,0.5,0\n", 2, "expected 4"),
        ("0.5,0.5,0,0\n0.5,0.5,0,0\nx,0.5,0,0\n", 3, "u:"),
        ("0.5,0.5,0,7\n", 1, "mode"),
        ("0.5,0.5,0,0\n\n0.5,0.5,0,0\n", 2, "expected 4"),
        ("0.5,NaN,0,0\n", 1, "not finite"),
        ("0.5,0.5,inf,0\n", 1, "not finite"),
        ("0.5,0.5,0,0,1\n", 1, "found 5"),
        ("0.5,0.5,0,-1\n", 1, "mode"),
    ] {
        let (r, out) = run_lib(input, AddressMode::Wrap);
        let e = r.unwrap_err();
        assert!(
            matches!(&e, SampleError::Line { input, line: l, .. } if input == "<stdin>" && *l == line),
            "{e:?}"
        );
        let msg = e.to_string();
        assert!(msg.starts_with(&format!("<stdin>:{line}: ")), "{msg}");
        assert!(msg.contains(what), "{msg}");
        // Everything before the bad line was written, nothing after.
        assert_eq!(out.lines().count(), line - 1);
    }
}

fn temp_ppm(name: &str, img: &RgbImage) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("raymip-sample-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    write_ppm(&p, img).unwrap();
    p
}

fn run_bin(args: &[&str], stdin: &str) -> (bool, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_raymip-host"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // A run that rejects its options exits before reading its input: the
    // pipe is then closed, which is not a failure of the test.
    if let Err(e) = child.stdin.take().unwrap().write_all(stdin.as_bytes()) {
        assert_eq!(e.kind(), std::io::ErrorKind::BrokenPipe, "{e}");
    }
    let o = child.wait_with_output().unwrap();
    (
        o.status.success(),
        String::from_utf8(o.stdout).unwrap(),
        String::from_utf8(o.stderr).unwrap(),
    )
}

#[test]
fn binary_end_to_end() {
    let tex = temp_ppm("tex.ppm", &image());
    let t = tex.to_str().unwrap();
    let (ok, out, err) = run_bin(&["sample", "--texture", t], "0.25,0.25,0,2\n0.5,0.25,0,0\n");
    assert!(ok, "{err}");
    assert_eq!(out, "255,0,0,255\n128,128,0,255\n");
    // One level only: lod 1 stays at level 0.
    let (ok, out, _) = run_bin(
        &[
            "sample",
            "--texture",
            t,
            "--levels",
            "1",
            "--address",
            "clamp",
        ],
        "0.25,0.25,1,2\n0,0.25,0,0\n",
    );
    assert!(ok);
    assert_eq!(out, "255,0,0,255\n255,0,0,255\n");
    // Malformed line: non-zero exit, the line named, earlier output kept.
    let (ok, out, err) = run_bin(&["sample", "--texture", t], "0.25,0.25,0,2\n0.1;0.2;0;0\n");
    assert!(!ok);
    assert_eq!(out, "255,0,0,255\n");
    assert!(err.contains("<stdin>:2:"), "{err}");
    // Bad level count and missing file: clear errors.
    let (ok, _, err) = run_bin(&["sample", "--texture", t, "--levels", "3"], "");
    assert!(!ok && err.contains("--levels 3"), "{err}");
    let (ok, _, err) = run_bin(&["sample", "--texture", "/nonexistent/x.ppm"], "");
    assert!(!ok && err.contains("/nonexistent/x.ppm"), "{err}");
    let (ok, _, err) = run_bin(&["sample", "--texture", t, "--address", "spiral"], "");
    assert!(!ok && err.contains("spiral"), "{err}");
}

#[test]
fn npot_texture_through_binary() {
    // 3×1 texture: level 1 (1×1) is the exact box (30+60+90)/3 = 60.
    let img = RgbImage {
        width: 3,
        height: 1,
        pixels: vec![[30, 0, 0], [60, 0, 0], [90, 0, 0]],
    };
    let tex = temp_ppm("npot.ppm", &img);
    let (ok, out, err) = run_bin(
        &["sample", "--texture", tex.to_str().unwrap()],
        "0.5,0.5,1,0\n0.5,0.5,0,2\n",
    );
    assert!(ok, "{err}");
    assert_eq!(out, "60,0,0,255\n60,0,0,255\n");
}

/// GPU-sampler options through the binary, hand-worked on the 2×2 texture
/// (red, green / blue, white; level 1 = gray 128).
#[test]
fn sampler_state_options_through_binary() {
    let tex = temp_ppm("state.ppm", &image());
    let t = tex.to_str().unwrap();
    let run = |extra: &[&str], input: &str| {
        let mut args = vec!["sample", "--texture", t];
        args.extend_from_slice(extra);
        let (ok, out, err) = run_bin(&args, input);
        assert!(ok, "{extra:?}: {err}");
        out
    };
    for (options, input, want) in [
        // Mirror: u = 1.25 reads u = 0.75 (green); mirror-once: u = −0.25 → 0.25 (red).
        (
            &["--address", "mirror"][..],
            "1.25,0.25,0,2\n",
            "0,255,0,255\n",
        ),
        (
            &["--address", "mirror-once"],
            "-0.25,0.25,0,2\n",
            "255,0,0,255\n",
        ),
        // Border per axis: u wraps, v outside reads the border colour.
        (
            &["--address", "wrap,border", "--border", "10,20,30,40"],
            "1.25,-0.5,0,2\n1.25,0.25,0,2\n",
            "10,20,30,40\n255,0,0,255\n",
        ),
        // Bias +1 → level 1; min-lod 1 → level 1; max-lod 0 → level 0.
        (&["--bias", "1"], "0.25,0.25,0,2\n", "128,128,128,255\n"),
        (&["--min-lod", "1"], "0.25,0.25,0,2\n", "128,128,128,255\n"),
        (
            &["--max-lod", "0", "--bias", "-0.5"],
            "0.25,0.25,5,2\n",
            "255,0,0,255\n",
        ),
        // Formats: L8 reads red as luminance, A8 keeps alpha only; RGB565
        // keeps 255 and 0 exactly.
        (&["--format", "l8"], "0.75,0.25,0,2\n", "0,0,0,255\n"),
        (&["--format", "a8"], "0.25,0.25,0,2\n", "0,0,0,255\n"),
        (
            &["--format", "rgb565"],
            "0.75,0.75,0,2\n",
            "255,255,255,255\n",
        ),
        // BC1: the encoder's endpoints are the first two texels farthest
        // apart (all pairs tie here: red and green), so red survives exactly.
        (&["--format", "bc1"], "0.25,0.25,0,2\n", "255,0,0,255\n"),
        // sRGB: a texel comes back as stored (decode + encode), linear
        // output of half red/green = 255·(EOTF(1)/2) per channel: 127.5 →
        // 128; the sRGB pyramid's level 1 is the linear mean of the four
        // texels: red = (1 + 0 + 0 + 1)/4 = 0.5 linear → sRGB 188.
        (&["--srgb"], "0.25,0.25,0,2\n", "255,0,0,255\n"),
        (
            &["--srgb", "--linear-output"],
            "0.5,0.25,0,1\n",
            "128,128,0,255\n",
        ),
        (&["--srgb"], "0.5,0.5,1,2\n", "188,188,188,255\n"),
        // Anisotropic line: 8:1 along u over the top row at lod 0 → probes
        // spread evenly between red and green: half each (127.5 → 128),
        // in both tiers (FAST: 8-bit weights, exact here).
        (&[], "0.5,0.25,0,0.5,0,0,0.0625\n", "128,128,0,255\n"),
        (
            &["--precision", "fast"],
            "0.5,0.25,0,0.5,0,0,0.0625\n",
            "128,128,0,255\n",
        ),
        // FAST: a quarter texel between red and green at 8 sub-texel bits.
        (
            &["--precision", "fast"],
            "0.375,0.25,0,1\n",
            "191,64,0,255\n",
        ),
    ] {
        assert_eq!(run(options, input), want, "{options:?} {input:?}");
    }
    // Invalid options: clear errors.
    for (args, what) in [
        (vec!["--bias", "16"], "bias"),
        (vec!["--min-lod", "2", "--max-lod", "1"], "min lod"),
        (vec!["--max-aniso", "17"], "anisotropy"),
        (vec!["--format", "rgb565", "--srgb"], "sRGB"),
        (vec!["--linear-output"], "--srgb"),
        (vec!["--border", "1,2,3"], "border"),
    ] {
        let mut a = vec!["sample", "--texture", t];
        a.extend_from_slice(&args);
        let (ok, _, err) = run_bin(&a, "0.5,0.5,0,0\n");
        assert!(!ok && err.contains(what), "{args:?}: {err}");
    }
    // --help documents the line format.
    let (ok, out, _) = run_bin(&["sample", "--help"], "");
    assert!(ok && out.contains("u,v,mode,dudx,dvdx,dudy,dvdy"), "{out}");
}
