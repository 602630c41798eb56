//! BART kitchen and robots load with the published counts (README of
//! `../shared/scenes/bart`), a sane camera and finite geometry.
//!
//! Expected values come from the scene folder's README (counted there by a
//! script that follows the reference parser) and from the scene files
//! themselves (camera keys), never from this loader.

use std::path::{Path, PathBuf};
use std::time::Instant;

use raymip_host::output::report::markdown_cells;
use raymip_host::scene::V3;
use raymip_host::scene::aff::{self, DEFAULT_TIME, Scene};

/// `../shared/scenes/bart` relative to the repository root; the variable
/// `RAYMIP_BART_DIR` overrides it (git worktrees live elsewhere).
fn bart() -> Option<PathBuf> {
    let dir = std::env::var_os("RAYMIP_BART_DIR").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/bart"),
        PathBuf::from,
    );
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("SKIP: {} not found", dir.display());
        None
    }
}

fn load(dir: &Path, scene: &str, time: f64) -> Scene {
    let top = aff::find_top_level(&dir.join(scene)).unwrap();
    let start = Instant::now();
    let s = aff::load(&top, time).unwrap_or_else(|e| panic!("{e}"));
    println!(
        "{scene}: loaded {} in {:.0} ms ({} files, {} lines, {} textures)",
        top.display(),
        start.elapsed().as_secs_f64() * 1e3,
        s.stats.files,
        s.stats.lines,
        s.textures.len()
    );
    s
}

struct Expect {
    triangles: usize,
    textured: usize,
    zero_area: usize,
    zero_area_textured: usize,
    zero_uv: usize,
    textures: usize,
    lights: usize,
    materials: usize,
    u: (f64, f64),
    v: (f64, f64),
    /// Half the last published digit of the UV ranges.
    uv_tol: f64,
}

fn check_common(s: &Scene, e: &Expect) {
    let st = &s.stats;
    // Counting definition: triangles read after triangulation, before the
    // zero-area ones are dropped.
    assert_eq!(st.triangles_read, e.triangles);
    assert_eq!(st.textured_read, e.textured);
    assert_eq!(st.skipped_degenerate, e.zero_area);
    assert_eq!(st.skipped_degenerate_textured, e.zero_area_textured);
    assert_eq!(st.hidden, 0);
    assert_eq!(s.triangles.len(), e.triangles - e.zero_area);
    let textured = s.triangles.iter().filter(|t| t.texture.is_some()).count();
    assert_eq!(textured, e.textured - e.zero_area_textured);
    assert_eq!(st.zero_uv_area, e.zero_uv);
    assert_eq!(s.textures.len(), e.textures);
    assert_eq!(s.lights.len(), e.lights);
    assert_eq!(s.materials.len(), e.materials);
    assert!(st.camera_from_track);

    // Every texture referenced, loaded, shared by index.
    let mut used = vec![false; s.textures.len()];
    let (mut umin, mut umax, mut vmin, mut vmax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for t in &s.triangles {
        assert!(t.p.iter().all(|x| x.is_finite()));
        assert!((t.material as usize) < s.materials.len());
        assert_eq!(t.uv.is_some(), t.texture.is_some());
        if let Some(n) = t.n {
            for ni in n {
                let len = (ni[0] * ni[0] + ni[1] * ni[1] + ni[2] * ni[2]).sqrt();
                assert!((len - 1.0).abs() < 1e-9, "normal {ni:?}");
            }
        }
        if let (Some(uv), Some(tex)) = (t.uv, t.texture) {
            used[tex as usize] = true;
            for [u, v] in uv {
                assert!(u.is_finite() && v.is_finite(), "uv {u} {v}");
                umin = umin.min(u);
                umax = umax.max(u);
                vmin = vmin.min(v);
                vmax = vmax.max(v);
            }
        }
    }
    assert!(used.iter().all(|&u| u));
    for tex in &s.textures {
        let img = &tex.image;
        assert_eq!(img.pixels.len(), (img.width * img.height) as usize);
    }
    // UV ranges as published (rounded; a mirrored v would fail).
    let near = |a: f64, b: f64| (a - b).abs() <= e.uv_tol;
    assert!(
        near(umin, e.u.0) && near(umax, e.u.1),
        "u {umin}..{umax} vs {:?}",
        e.u
    );
    assert!(
        near(vmin, e.v.0) && near(vmax, e.v.1),
        "v {vmin}..{vmax} vs {:?}",
        e.v
    );
    let m = &s.materials;
    assert!(m.iter().all(|m| m.ior > 0.0));
    let c = &s.camera;
    assert_eq!((c.width, c.height), (800, 600));
    assert!(c.hither > 0.0);
    let dir = [0, 1, 2].map(|i| c.at[i] - c.from[i]);
    let dl = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
    let ul = (c.up[0] * c.up[0] + c.up[1] * c.up[1] + c.up[2] * c.up[2]).sqrt();
    assert!(dl > 0.0 && ul > 0.0);
    // up not parallel to the view direction
    let d = (dir[0] * c.up[0] + dir[1] * c.up[1] + dir[2] * c.up[2]) / (dl * ul);
    assert!(d.abs() < 0.99);
}

/// Rodrigues: rotate `v` by `deg` about unit `axis` (written independently
/// of the loader's quaternion code).
fn rotate(v: [f64; 3], axis: [f64; 3], deg: f64) -> [f64; 3] {
    let l = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let k = axis.map(|a| a / l);
    let (s, c) = deg.to_radians().sin_cos();
    let kxv = [
        k[1] * v[2] - k[2] * v[1],
        k[2] * v[0] - k[0] * v[2],
        k[0] * v[1] - k[1] * v[0],
    ];
    let kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    [0, 1, 2].map(|i| v[i] * c + kxv[i] * s + k[i] * kv * (1.0 - c))
}

fn assert_camera_at_key(s: &Scene, from: V3, axis: V3, deg: f64) {
    let c = &s.camera;
    for (got, want) in c.from.to_array().into_iter().zip(from.to_array()) {
        assert!((got - want).abs() < 1e-9, "from {:?}", c.from);
    }
    let dir = rotate([0.0, 0.0, -1.0], axis.to_array(), deg);
    let up = rotate([0.0, 1.0, 0.0], axis.to_array(), deg);
    for i in 0..3 {
        assert!((c.at[i] - c.from[i] - dir[i]).abs() < 1e-9, "dir");
        assert!((c.up[i] - up[i]).abs() < 1e-9, "up");
    }
}

/// The published counts of `scene` (`kitchen` or `robots`): its column of
/// the table in the scene folder's README, parsed here so that nothing is
/// transcribed. The UV tolerance is half the last published digit.
fn published(dir: &Path, scene: &str) -> Expect {
    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    let cells = markdown_cells;
    let header = readme
        .lines()
        .find(|l| l.starts_with("| | kitchen"))
        .expect("published table");
    let col = cells(header)
        .iter()
        .position(|c| c.starts_with(scene))
        .unwrap();
    let row = |name: &str| -> String {
        let line = readme
            .lines()
            .find(|l| l.starts_with(&format!("| {name} |")))
            .unwrap_or_else(|| panic!("row {name:?}"));
        cells(line)[col].clone()
    };
    // The leading number of a cell and the one in brackets after it, if any.
    let numbers = |cell: &str| -> (usize, usize) {
        let int = |t: &str| -> usize {
            let d: String = t.chars().take_while(char::is_ascii_digit).collect();
            d.parse().unwrap_or(0)
        };
        let cell = cell.replace(',', "");
        let bracket = cell.split_once('(').map_or(0, |(_, b)| int(b));
        (int(&cell), bracket)
    };
    let (zero_area, zero_area_textured) = numbers(&row("zero-area triangles"));
    // "u −4.1…62.1, v −8.0…2.8"
    let uv = row("UV range (repeat wrap)").replace('\u{2212}', "-");
    let range = |axis: &str| -> (f64, f64) {
        let r = uv.split(", ").find_map(|p| p.strip_prefix(axis)).unwrap();
        let (lo, hi) = r.split_once('\u{2026}').unwrap();
        (lo.parse().unwrap(), hi.parse().unwrap())
    };
    let decimals = uv.split_once('.').map_or(0, |(_, f)| {
        f.chars().take_while(char::is_ascii_digit).count()
    });
    Expect {
        triangles: numbers(&row("triangles")).0,
        textured: numbers(&row("of which textured")).0,
        zero_area,
        zero_area_textured,
        zero_uv: numbers(&row("textured tris with zero UV area")).0,
        textures: numbers(&row("textures used")).0,
        lights: numbers(&row("lights")).0,
        materials: numbers(&row("distinct materials")).0,
        u: range("u "),
        v: range("v "),
        uv_tol: 0.51 * 10f64.powi(-(decimals as i32)),
    }
}

/// Both scenes load with the published counts; at t = 0 the camera is at
/// key 1 of the scene's `camera` track (key values from the scene files:
/// kitchen.aff and Robot.aff, whose keys 0 and 1 are both at t = 0).
#[test]
fn scenes_load_with_published_counts() {
    let Some(dir) = bart() else { return };
    for (scene, from, axis, deg) in [
        (
            "kitchen",
            [3.75, 2.3, 3.6],
            [0.77895, -0.61838, -0.10410],
            -31.77348,
        ),
        (
            "robots",
            [-3.5, 2.0, -203.0],
            [-0.85813, 0.513, -0.02546],
            -6.6,
        ),
    ] {
        let s = load(&dir, scene, DEFAULT_TIME);
        check_common(&s, &published(&dir, scene));
        assert_camera_at_key(&s, V3::from(from), V3::from(axis), deg);
        if scene == "kitchen" {
            assert_eq!(s.background, V3::new(0.5, 0.5, 1.0));
            assert_eq!(s.ambient, V3::splat(2.5));
            assert_eq!(s.camera.fov_y_deg, 40.0);
            assert_eq!(s.camera.hither, 0.01);
            let floor = s.textures.iter().find(|t| t.name == "floor.ppm").unwrap();
            assert_eq!((floor.image.width, floor.image.height), (1044, 1044));
            assert!(s.stats.unbound_tracks.is_empty());
        } else {
            assert_eq!(s.background, V3::splat(0.0));
            assert_eq!(s.lights[0].position, V3::new(1.0, 500.0, 1.0));
            assert_eq!(s.camera.hither, 1.0);
            // Robot1/Robot2 use `x` names that have no `k` track: identity.
            assert_eq!(
                s.stats.unbound_tracks,
                [
                    "grip_lift1",
                    "grip_rot1",
                    "gun_lift2",
                    "gun_rot2",
                    "head_rot2"
                ]
            );
        }
    }
}

#[test]
fn robots_finite_where_reference_goes_nan() {
    // grip_rot2's non-unit axes send the reference to NaN for t in
    // [5.888, 6.0] and (42.0, 42.182); the clamp keeps everything finite.
    let Some(dir) = bart() else { return };
    for t in [5.9, 5.99, 42.1] {
        let s = load(&dir, "robots", t);
        assert_eq!(s.triangles.len(), 71_708 - 128);
        assert!(
            s.triangles
                .iter()
                .all(|t| t.p.iter().all(|x| x.is_finite())),
            "t = {t}"
        );
    }
}

#[test]
fn animation_moves_the_toy_car_and_camera() {
    let Some(dir) = bart() else { return };
    let a = load(&dir, "kitchen", 0.0);
    let b = load(&dir, "kitchen", 10.0);
    assert_eq!(a.triangles.len(), b.triangles.len());
    let moved = a
        .triangles
        .iter()
        .zip(&b.triangles)
        .filter(|(x, y)| x.p != y.p)
        .count();
    // The toy car (7,218 triangles in the README) moves; nothing else does.
    assert!(moved > 0 && moved <= 7_218, "{moved}");
    assert_ne!(a.camera.from, b.camera.from);
}

#[test]
fn top_level_files_are_found() {
    let Some(dir) = bart() else { return };
    let k = aff::find_top_level(&dir.join("kitchen")).unwrap();
    assert_eq!(k.file_name().unwrap(), "kitchen.aff");
    let r = aff::find_top_level(&dir.join("robots")).unwrap();
    assert_eq!(r.file_name().unwrap(), "Robot.aff");
}
