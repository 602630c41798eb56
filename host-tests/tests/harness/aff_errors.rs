//! Malformed AFF and PPM inputs: every error names `file:line`, nothing
//! panics; CRLF line ends and Latin-1 bytes are accepted.
//!
//! The scene files are written to a temporary folder at test time; the
//! expected lines are counted by hand from the texts below.

use std::path::{Path, PathBuf};

use raymip_host::scene::V3;
use raymip_host::scene::aff::{self, AffErrorKind, DEFAULT_TIME};

/// A fresh folder for one test.
fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("raymip-aff-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(d: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = d.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// 2×1 P6 texture.
fn ppm() -> Vec<u8> {
    let mut b = b"P6\n2 1\n255\n".to_vec();
    b.extend([255, 0, 0, 0, 255, 0]);
    b
}

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.1\nresolution 64 48\n";

/// A material and the start of a mesh (lines 8–10 after [`VIEW`]): the
/// vertex count and rows follow.
const MESH: &str = "fm 1 1 1 1 1 1 0 0 0 1 0 1\nm\nvertices";

/// Loads `top` from `files` (name, text) and returns the error text.
fn load_err(test: &str, files: &[(&str, &[u8])]) -> (String, aff::AffError) {
    let d = dir(test);
    for (name, text) in files {
        write(&d, name, text);
    }
    let top = d.join(files[0].0);
    let e = match aff::load(&top, DEFAULT_TIME) {
        Ok(_) => panic!("{test}: expected an error"),
        Err(e) => e,
    };
    let msg = e.to_string();
    println!("{test}: {msg}");
    std::fs::remove_dir_all(&d).ok();
    (msg, e)
}

/// Loads the one file `top.aff` with text `top`, checks that the error is
/// at `top.aff:line` and says `what`, and returns it.
fn top_fails_at(test: &str, top: &str, line: usize, what: &str) -> (String, aff::AffError) {
    let (msg, e) = load_err(test, &[("top.aff", top.as_bytes())]);
    assert_at(&msg, "top.aff", line, what);
    (msg, e)
}

fn assert_at(msg: &str, file: &str, line: usize, what: &str) {
    let at = format!("{file}:{line}: ");
    assert!(msg.contains(&at), "expected {at:?} in {msg:?}");
    assert!(msg.contains(what), "expected {what:?} in {msg:?}");
}

#[test]
fn truncated_record() {
    let top = format!("{VIEW}fm 0.1 0.2 0.3\n  0.5 0.5\n");
    // The file ends on line 10 (after the newline that closes line 9).
    let (msg, e) = top_fails_at("trunc", &top, 10, "unexpected end of file");
    assert!(msg.contains("`fm` field 6 of 12"), "{msg}");
    assert!(matches!(*e.kind, AffErrorKind::UnexpectedEof { .. }));
}

/// Counts and numbers that do not fit: (test, text after the view, line,
/// what the error says).
#[test]
fn count_and_number_errors() {
    for (name, body, line, what) in [
        // `vertices 4` but only three rows (lines 11–13): the parser meets
        // `triangles` on line 14 where the tenth coordinate should be.
        (
            "nverts",
            format!("{MESH} 4\n0 0 0\n1 0 0\n0 1 0\ntriangles 1\n0 1 2\n"),
            14,
            "(mesh vertex 4 of 4), found \"triangles\"",
        ),
        (
            "index",
            format!("{MESH} 3\n0 0 0\n1 0 0\n0 1 0\ntriangles 2\n0 1 2\n0 1 3\n"),
            16,
            "vertex index 3 out of range",
        ),
        // Too many vertices declared the other way: four rows for
        // `vertices 3` leaves a number where a section keyword must be.
        (
            "extra",
            format!("{MESH} 3\n0 0 0\n1 0 0\n0 1 0\n1 1 0\ntriangles 1\n0 1 2\n"),
            14,
            "count too small",
        ),
        // `p 4` with three vertices: the next command's letter is read as
        // the twelfth coordinate.
        (
            "poly",
            "p 4\n0 0 0\n1 0 0\n0 1 0\nl 0 5 0\n".into(),
            12,
            "polygon vertex 4 of 4",
        ),
        (
            "poly2",
            "p 2\n0 0 0\n1 0 0\n".into(),
            8,
            "polygon with 2 vertices",
        ),
        // A 3-key spline channel (needs 4).
        (
            "keys",
            "k spin\n{\nrot 3\n0 0 1 0 0 0 0 0\n1 0 1 0 90 0 0 0\n2 0 1 0 180 0 0 0\n}\n".into(),
            10,
            "at least 4",
        ),
        // Huge counts are errors, not allocation failures.
        (
            "huge",
            "m\nvertices 999999999999999999\n0 0 0\n".into(),
            11,
            "mesh vertex 2 of 999999999999999999",
        ),
        (
            "hugep",
            "p 99999999999\n".into(),
            9,
            "unexpected end of file",
        ),
        // nan / inf are not numbers here; nor is a negative count.
        ("nan", "b 0 nan 0\n".into(), 8, "\"nan\""),
        ("negcount", "p -3\n".into(), 8, "\"-3\""),
    ] {
        top_fails_at(name, &format!("{VIEW}{body}"), line, what);
    }
    let (_, e) = top_fails_at("num", &format!("{VIEW}l 1 2 3x\n"), 8, "\"3x\"");
    assert!(matches!(*e.kind, AffErrorKind::BadNumber { .. }));
}

#[test]
fn missing_include_names_the_including_line() {
    let top = format!("{VIEW}\ni 0 nothere.aff\n");
    let (_, e) = top_fails_at("inc", &top, 9, "nothere.aff");
    assert!(matches!(*e.kind, AffErrorKind::MissingInclude { .. }));
}

#[test]
fn recursive_include_is_an_error_not_a_stack_overflow() {
    let top = format!("{VIEW}i 0 top.aff\n");
    top_fails_at("rec", &top, 8, "nested deeper");
}

#[test]
fn missing_texture() {
    let top = format!(
        "{VIEW}{MESH} 3\n0 0 0\n1 0 0\n0 1 0\ntexturecoords 3 gone.ppm\n0 0\n1 0\n0 1\ntriangles 1\n0 1 2 0 1 2\n"
    );
    let (msg, e) = top_fails_at("tex", &top, 14, "gone.ppm");
    assert!(msg.contains("cannot read"), "{msg}");
    assert!(matches!(*e.kind, AffErrorKind::Texture { .. }));
    let top = format!("{VIEW}tt gone.ppm\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n");
    top_fails_at("tt", &top, 8, "gone.ppm");
}

/// Errors inside a file the top file reads: the inner file's location,
/// and the include chain or the `tt` line that read it. (test, top text,
/// the other files, where the error is, what else the message names.)
#[test]
fn errors_in_read_files_name_the_chain() {
    let include = format!("{VIEW}i 0 mid.aff\n");
    let texture = format!("{VIEW}\n\ntt bad.ppm\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n");
    type Files<'a> = &'a [(&'a str, &'a [u8])];
    type Case<'a> = (
        &'a str,
        &'a str,
        Files<'a>,
        (&'a str, usize, &'a str),
        &'a [&'a str],
    );
    let cases: [Case; 3] = [
        (
            "chain",
            &include,
            &[
                ("mid.aff", b"% comment\ni 0 inner.aff\n"),
                ("inner.aff", b"fm 1 1 1\n1 1 1\n0 0 0 1 zero 1\n"),
            ],
            ("inner.aff", 3, "\"zero\""),
            &["mid.aff:2", "top.aff:8"],
        ),
        // Bad PPM header.
        (
            "ppm",
            &texture,
            &[("bad.ppm", b"P5\n2 1\n255\n\0\0")],
            ("top.aff", 10, "bad.ppm"),
            &["bad.ppm:1: not a binary PPM"],
        ),
        // Truncated raster.
        (
            "ppm2",
            &texture,
            &[("bad.ppm", b"P6\n4 4\n255\n\0\0\0")],
            ("top.aff", 10, "truncated raster"),
            &[],
        ),
    ];
    for (name, top, files, (file, line, what), also) in cases {
        let mut all = vec![("top.aff", top.as_bytes())];
        all.extend_from_slice(files);
        let (msg, _) = load_err(name, &all);
        assert_at(&msg, file, line, what);
        for a in also {
            assert!(msg.contains(a), "{name}: {msg}");
        }
    }
}

#[test]
fn structure_errors() {
    let cases: &[(&str, String, usize, &str)] = &[
        (
            "unknown",
            format!("{VIEW}q 1 2 3\n"),
            8,
            "unknown command \"q\"",
        ),
        ("close", format!("{VIEW}}}\n"), 8, "without a matching"),
        (
            "open",
            format!("{VIEW}xs 1 1 1 0 1 0 0 0 0 0\n{{\n"),
            9,
            "never closed",
        ),
        (
            "nobrace",
            format!("{VIEW}xs 1 1 1 0 1 0 0 0 0 0\nl 1 1 1\n"),
            9,
            "expected '{' after `xs`",
        ),
        (
            "viewkw",
            "v\nfrom 0 0 5\nat 0 0 0\nupp 0 1 0\n".to_string(),
            4,
            "expected keyword \"up\"",
        ),
        (
            "fov",
            VIEW.replace("angle 45", "angle 0"),
            5,
            "field of view",
        ),
        (
            "chan",
            format!("{VIEW}k t\n{{\nwobble 4\n}}\n"),
            10,
            "unknown track channel",
        ),
    ];
    for (name, text, line, what) in cases {
        top_fails_at(name, text, *line, what);
    }
    // No `v` at all: the whole top file is named.
    let (msg, _) = load_err("noview", &[("top.aff", b"l 1 2 3\n")]);
    assert!(msg.contains("top.aff: no view"), "{msg}");
}

#[test]
fn crlf_latin1_comments_and_optional_fields_are_accepted() {
    let d = dir("crlf");
    let text = "% caf\u{f6} comment\r\nb 0.1 0.2 0.3  # trailing comment\r\n\
v\r\nfrom 0 0 5\r\nat 0 0 0\r\nup 0 1 0\r\nangle 45\r\nhither 0.00001\r\nresolution 64 48\r\n\
l 1 2 3\r\nl 1 2 3 0.5 0.5 0.5 % grey\r\n\
fm 0.1 0.1 0.1  0.5 0.5 0.5  0 0 0  10 0.5 0\r\n\
xs 2 2 2 0 0 1 90 1 0 0{\r\n\
p 3 0 0 0  1 0 0  0 1 0\r\n}\r\n\
tt tex.ppm 0 0 0 0 0  1 0 0 1 0  0 1 0 0 1\r\n";
    // Turn the `ö` (UTF-8 C3 B6) into the single Latin-1 byte F6.
    let mut bytes = text.as_bytes().to_vec();
    let at = bytes.windows(2).position(|w| w == [0xC3, 0xB6]).unwrap();
    bytes.splice(at..at + 2, [0xF6]);
    let top = write(&d, "top.aff", &bytes);
    let mut tex = b"P6\n# header comment\n2 1\n255\n".to_vec();
    tex.extend([255, 0, 0, 0, 255, 0, 0x0A]); // one stray trailing byte
    write(&d, "tex.ppm", &tex);
    let s = aff::load(&top, DEFAULT_TIME).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.background, V3::new(0.1, 0.2, 0.3));
    assert_eq!(s.camera.hither, 1.0, "hither < 1e-4 reads as 1");
    assert_eq!(s.lights.len(), 2);
    assert_eq!(
        s.lights[0].color,
        V3::splat(1.0),
        "default light colour is white"
    );
    assert_eq!(s.lights[1].color, V3::splat(0.5));
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.materials[0].ior, 1.0, "ior 0 is guarded to 1");
    assert_eq!(s.triangles.len(), 2);
    // Polygon: scaled by 2, rotated 90° about z, moved by (1,0,0):
    // (1,0,0) → (2,0,0) → (0,2,0) → (1,2,0).
    let p = s.triangles[0].p;
    assert!((p[1][0] - 1.0).abs() < 1e-12 && (p[1][1] - 2.0).abs() < 1e-12);
    assert_eq!(s.textures.len(), 1);
    assert_eq!(s.textures[0].image.pixels, vec![[255, 0, 0], [0, 255, 0]]);
    assert_eq!(s.triangles[1].texture, Some(0));
    assert_eq!(s.stats.lines, 16);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn every_truncation_of_a_valid_scene_is_ok_or_located_error() {
    let d = dir("prefix");
    write(&d, "t.ppm", &ppm());
    let full = format!(
        "{VIEW}fm 0.1 0.1 0.1 0.5 0.5 0.5 0 0 0 10 0 1\n\
xs 1 1 1 0 1 0 30 0 0 0 {{\n\
x anim {{\n\
m\nvertices 3\n0 0 0\n1 0 0\n0 1 0\nnormals 1\n0 0 1\ntexturecoords 3 t.ppm\n0 0\n1 0\n0 1\n\
triangles 1\n0 1 2 0 0 0 0 1 2\n}}\n}}\n\
s 0 0 0 1\nc 0 0 0 1 0 1 0 1\n\
k anim {{\ntransl 4\n0 0 0 0 0 0 0\n1 1 0 0 0 0 0\n2 2 0 0 0 0 0\n3 3 0 0 0 0 0\n}}\n"
    );
    // The whole file loads.
    let top = write(&d, "top.aff", full.as_bytes());
    let s = aff::load(&top, 1.5).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.triangles.len(), 1 + 960 + 64);
    // Every prefix either loads or fails with a located message.
    for cut in 0..full.len() {
        write(&d, "top.aff", &full.as_bytes()[..cut]);
        if let Err(e) = aff::load(&top, 1.5) {
            let msg = e.to_string();
            assert!(msg.contains("top.aff"), "cut {cut}: {msg}");
        }
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn top_level_detection() {
    let d = dir("toplevel");
    write(&d, "a.aff", b"i 0 b.aff\n% i 0 c.aff (commented out)\n");
    write(&d, "b.aff", b"l 1 1 1\n");
    write(&d, "c.aff", b"l 1 1 1\n");
    let e = aff::find_top_level(&d).unwrap_err().to_string();
    assert!(e.contains("a.aff") && e.contains("c.aff"), "{e}");
    write(&d, "a.aff", b"i 0 b.aff\ni 0 c.aff\n");
    assert_eq!(aff::find_top_level(&d).unwrap(), d.join("a.aff"));
    std::fs::remove_dir_all(&d).ok();
    let e = aff::find_top_level(&d).unwrap_err().to_string();
    assert!(e.contains("cannot read"), "{e}");
}

mod mutations {
    use super::*;
    use proptest::prelude::*;

    const SCENE: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.1\nresolution 64 48\n\
fm 0.1 0.1 0.1 0.5 0.5 0.5 0 0 0 10 0 1\nxs 1 1 1 0 1 0 30 0 0 0 {\nx anim {\n\
m\nvertices 3\n0 0 0\n1 0 0\n0 1 0\nnormals 1\n0 0 1\ntexturecoords 3 t.ppm\n0 0\n1 0\n0 1\n\
triangles 1\n0 1 2 0 0 0 0 1 2\n}\n}\np 4 0 0 0 1 0 0 1 1 0 0 1 0\ntpa 2 0 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\n\
1 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\n\
k anim {\ntransl 4\n0 0 0 0 0 0 0\n1 1 0 0 0 0 0\n2 2 0 0 0 0 0\n3 3 0 0 0 0 0\n\
rot 4\n0 0 1 0 0 0 0 0\n1 0 1 0 90 0 0 0\n2 0 1 0 180 0 0 0\n3 0 1 0 270 0 0 0\n}\n";

    #[test]
    fn unedited_scene_loads() {
        let d = dir("mutations-base");
        std::fs::write(d.join("t.ppm"), ppm()).unwrap();
        let top = write(&d, "top.aff", SCENE.as_bytes());
        let s = aff::load(&top, 1.5).unwrap_or_else(|e| panic!("{e}"));
        // mesh 1 + quad 2 + tpa 1
        assert_eq!(s.triangles.len(), 4);
        std::fs::remove_dir_all(&d).ok();
    }

    const ALPHABET: &[u8] = b" \n0123456789.-e{}%#xmkvpi";

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]
        /// Random byte edits of a valid scene load or fail with a located
        /// message; never panic.
        #[test]
        fn edited_scenes_never_panic(
            edits in proptest::collection::vec((0usize..2000, 0usize..ALPHABET.len(), 0u8..3), 1..6),
            time in -2.0f64..5.0,
        ) {
            let d = dir("mutations");
            std::fs::write(d.join("t.ppm"), ppm()).unwrap();
            let mut bytes = SCENE.as_bytes().to_vec();
            for (pos, ch, op) in edits {
                let pos = pos % (bytes.len() + 1);
                match op {
                    0 if pos < bytes.len() => { bytes[pos] = ALPHABET[ch]; }
                    1 => bytes.insert(pos, ALPHABET[ch]),
                    _ if pos < bytes.len() => { bytes.remove(pos); }
                    _ => {}
                }
            }
            let top = d.join("top.aff");
            std::fs::write(&top, &bytes).unwrap();
            match aff::load(&top, time) {
                Ok(s) => {
                    for t in &s.triangles {
                        prop_assert!(t.p.iter().all(|v| v.is_finite()));
                    }
                }
                Err(e) => {
                    let msg = e.to_string();
                    prop_assert!(msg.contains("top.aff") || msg.contains("t.ppm"), "{}", msg);
                }
            }
        }
    }
}

/// `load_from_memory` (the fuzz target's entry) reads the same scene as
/// `load` from files, includes and textures included, and never the file
/// system: a name missing from memory is a located error even when a file
/// of that name exists in the working folder.
#[test]
fn memory_load_equals_file_load() {
    let d = dir("memory");
    let top = format!("{VIEW}fm 0.1 0.1 0.1 0.5 0.5 0.5 0 0 0 10 0 1\ni 0 part.aff\n");
    let part = "tt t.ppm 0 0 0 0 0  1 0 0 1 0  0 1 0 0 1\np 3 0 0 1  1 0 1  0 1 1\n";
    let files: [(&str, &[u8]); 3] = [
        ("top.aff", top.as_bytes()),
        ("part.aff", part.as_bytes()),
        ("t.ppm", &ppm()),
    ];
    for (name, bytes) in files {
        write(&d, name, bytes);
    }
    let disk = aff::load(&d.join("top.aff"), DEFAULT_TIME).unwrap_or_else(|e| panic!("{e}"));
    let mem =
        aff::load_from_memory(&files, "top.aff", DEFAULT_TIME).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(mem.triangles, disk.triangles);
    assert_eq!(mem.materials, disk.materials);
    assert_eq!(mem.camera, disk.camera);
    assert_eq!(mem.textures.len(), 1);
    assert_eq!(mem.textures[0].image, disk.textures[0].image);
    assert_eq!(mem.stats.distinct_files, disk.stats.distinct_files);
    let e = aff::load_from_memory(&files[..2], "top.aff", DEFAULT_TIME).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("t.ppm") && msg.contains("part.aff"), "{msg}");
    assert!(aff::load_from_memory(&files, "top.aff", f64::NAN).is_err());
    std::fs::remove_dir_all(&d).ok();
}
