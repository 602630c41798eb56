//! Semantics of small hand-written AFF scenes: global material state,
//! late-bound tracks, camera track, `tpa`, normals under non-uniform scale,
//! separate index streams, visibility, detail levels, primitives.
//! Expected values are worked out by hand in the comments.

use std::path::PathBuf;

use raymip_host::scene::V3;
use raymip_host::scene::aff::{self, Scene};

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.1\nresolution 64 48\n";

fn scene(test: &str, files: &[(&str, &str)], time: f64) -> Scene {
    let d: PathBuf =
        std::env::temp_dir().join(format!("raymip-affs-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    for (name, text) in files {
        std::fs::write(d.join(name), text).unwrap();
    }
    let s = aff::load(&d.join(files[0].0), time).unwrap_or_else(|e| panic!("{test}: {e}"));
    std::fs::remove_dir_all(&d).ok();
    s
}

fn close(a: V3, b: V3) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-9)
}

const TRI: &str = "p 3 0 0 0 1 0 0 0 1 0\n";

fn fm(d: f64) -> String {
    format!("fm 0 0 0 {d} {d} {d} 0 0 0 1 0 1\n")
}

#[test]
fn material_is_global_state() {
    // fm 0.1; { fm 0.2; tri → 0.2 }; tri → still 0.2 (not restored at `}`);
    // include that only sets fm 0.3; tri → 0.3 (not restored at end of file).
    let top = format!(
        "{VIEW}{}xs 1 1 1 0 1 0 0 0 0 0 {{\n{}{TRI}}}\n{TRI}i 0 param.aff\n{TRI}",
        fm(0.1),
        fm(0.2)
    );
    let s = scene("mat", &[("top.aff", &top), ("param.aff", &fm(0.3))], 0.0);
    let d: Vec<f64> = s
        .triangles
        .iter()
        .map(|t| s.materials[t.material as usize].diffuse[0])
        .collect();
    assert_eq!(d, [0.2, 0.2, 0.3]);
    // fm 0.1 was never used by a primitive but is a material all the same.
    assert_eq!(s.materials.len(), 3);
}

#[test]
fn tracks_bind_late_last_wins_missing_is_identity() {
    // `x car` before `k car`; two `k car` tracks, the later (x = 7) wins;
    // `x ghost` has no track → identity.
    let k = |x: f64| {
        format!(
            "k car {{\ntransl 4\n0 {x} 0 0 0 0 0\n1 {x} 0 0 0 0 0\n2 {x} 0 0 0 0 0\n3 {x} 0 0 0 0 0\n}}\n"
        )
    };
    let top = format!(
        "{VIEW}{}x car {{\n{TRI}}}\nx ghost {{\n{TRI}}}\n{}{}",
        fm(0.5),
        k(5.0),
        k(7.0)
    );
    let s = scene("late", &[("top.aff", &top)], 1.5);
    assert!(close(s.triangles[0].p[0], V3::new(7.0, 0.0, 0.0)));
    assert!(close(s.triangles[1].p[0], V3::new(0.0, 0.0, 0.0)));
    assert_eq!(s.stats.unbound_tracks, ["ghost"]);
}

#[test]
fn camera_track_replaces_view_block() {
    // Constant track: eye (1,2,3), rotation 90° about +y. Local −z turns
    // into −x (R·z = x), local +y stays +y: at = (0,2,3), up = (0,1,0).
    let top = format!(
        "{VIEW}k camera {{\ntransl 4\n0 1 2 3 0 0 0\n1 1 2 3 0 0 0\n2 1 2 3 0 0 0\n3 1 2 3 0 0 0\n\
rot 4\n0 0 1 0 90 0 0 0\n1 0 1 0 90 0 0 0\n2 0 1 0 90 0 0 0\n3 0 1 0 90 0 0 0\n}}\n"
    );
    let s = scene("cam", &[("top.aff", &top)], 0.0);
    let c = s.camera;
    assert!(close(c.from, V3::new(1.0, 2.0, 3.0)));
    assert!(close(c.at, V3::new(0.0, 2.0, 3.0)), "{:?}", c.at);
    assert!(close(c.up, V3::new(0.0, 1.0, 0.0)));
    // angle, hither, resolution still from `v`.
    assert_eq!(
        (c.fov_y_deg, c.hither, c.width, c.height),
        (45.0, 0.1, 64, 48)
    );
    assert!(s.stats.camera_from_track);
}

#[test]
fn tpa_interpolates_linearly_and_clamps() {
    // Keys at t = 0 and t = 2; x of vertex 0 goes 0 → 4 → at t = 0.5: 1.
    let top = format!(
        "{VIEW}{}tpa 2\n0  0 0 0 0 0 1e-3  1 0 0 0 0 1e-3  0 1 0 0 0 1e-3\n\
2  4 0 0 0 0 1  5 0 0 0 0 1  4 1 0 0 0 1\n",
        fm(0.5)
    );
    for (t, x) in [(-1.0, 0.0), (0.5, 1.0), (2.0, 4.0), (9.0, 4.0)] {
        let s = scene("tpa", &[("top.aff", &top)], t);
        let tri = s.triangles[0];
        assert!((tri.p[0][0] - x).abs() < 1e-12, "t {t}: {:?}", tri.p);
        // Non-unit normals come out unit length.
        assert!(close(tri.n.unwrap()[0], V3::new(0.0, 0.0, 1.0)));
    }
}

#[test]
fn normals_use_inverse_transpose_and_streams_are_separate() {
    // Mesh with 4 vertices, 2 normals, 3 UVs; the triangle uses vertex
    // indices 3 1 0, normal indices 1 1 0, uv indices 2 0 1.
    // Under xs 2 1 1 the normal (1,1,0)/√2 becomes ∝ (1/2, 1, 0).
    let top = format!(
        "{VIEW}{}xs 2 1 1 0 1 0 0 0 0 0 {{\nm\nvertices 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n\
normals 2\n0 0 1\n0.70710678118654752 0.70710678118654752 0\n\
texturecoords 3 t.ppm\n0.5 0.5\n0.25 0.75\n1 2\ntriangles 1\n3 1 0  1 1 0  2 0 1\n}}\n",
        fm(0.5)
    );
    let mut ppm = b"P6 1 1 255\n".to_vec();
    ppm.extend([1, 2, 3]);
    let d = std::env::temp_dir().join(format!("raymip-affs-{}-nrm", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("t.ppm"), ppm).unwrap();
    std::fs::write(d.join("top.aff"), top).unwrap();
    let s = aff::load(&d.join("top.aff"), 0.0).unwrap();
    std::fs::remove_dir_all(&d).ok();
    let t = s.triangles[0];
    assert!(close(t.p[0], V3::new(0.0, 0.0, 1.0)) && close(t.p[1], V3::new(2.0, 0.0, 0.0)));
    let l = (0.25f64 + 1.0).sqrt();
    let n = t.n.unwrap();
    assert!(close(n[0], V3::new(0.5 / l, 1.0 / l, 0.0)) && close(n[2], V3::new(0.0, 0.0, 1.0)));
    assert_eq!(t.uv.unwrap(), [[1.0, 2.0], [0.5, 0.5], [0.25, 0.75]]);
    assert_eq!(t.texture, Some(0));
    assert_eq!(s.textures[0].image.pixels, [[1, 2, 3]]);
}

#[test]
fn visibility_detail_lights_and_primitives() {
    // Visibility: hidden from t = 1 on. Detail: `i 1 …` skipped at level 0
    // (the file does not even exist). `la`: light at the track's position.
    let top = format!(
        "{VIEW}{}x blink {{\n{TRI}}}\n\
k blink {{\nvisibility 2\n0 1\n1 0\ntransl 4\n0 9 8 7 0 0 0\n1 9 8 7 0 0 0\n2 9 8 7 0 0 0\n3 9 8 7 0 0 0\n}}\n\
i 1 absent.aff\nla blink 0 0 0 0.5 0.5 0.5\nl 1 1 1\n\
s 0 0 0 1\nc 0 0 0 1 0 2 0 0.5\np 5 0 0 0 1 0 0 2 1 0 1 2 0 0 1 0\n",
        fm(0.5)
    );
    let s0 = scene("vis0", &[("top.aff", &top)], 0.5);
    let s1 = scene("vis1", &[("top.aff", &top)], 1.5);
    // 1 + 960 (sphere) + 64 (cone) + 3 (pentagon fan).
    assert_eq!(s0.triangles.len(), 1 + 960 + 64 + 3);
    assert_eq!(s1.triangles.len(), 960 + 64 + 3);
    assert_eq!(s1.stats.hidden, 1);
    assert!(close(s0.lights[0].position, V3::new(9.0, 8.0, 7.0)));
    assert_eq!(s0.lights[0].color, V3::splat(0.5));
    assert_eq!(s0.lights[1].color, V3::splat(1.0));
    assert_eq!(
        (s0.stats.spheres, s0.stats.cones, s0.stats.polygons),
        (1, 1, 2)
    );
}

#[test]
fn zero_area_triangles_are_counted_and_dropped() {
    // Repeated vertex and collinear vertices: read, counted, dropped.
    let top = format!(
        "{VIEW}{}m\nvertices 4\n0 0 0\n1 0 0\n2 0 0\n0 1 0\ntriangles 3\n0 1 3\n0 0 1\n0 1 2\n",
        fm(0.5)
    );
    let s = scene("zero", &[("top.aff", &top)], 0.0);
    assert_eq!(s.stats.triangles_read, 3);
    assert_eq!(s.stats.skipped_degenerate, 2);
    assert_eq!(s.triangles.len(), 1);
}

#[test]
fn primitives_before_any_material_use_the_default() {
    let s = scene("dflt", &[("top.aff", &format!("{VIEW}{TRI}"))], 0.0);
    assert!(s.stats.used_default_material);
    assert_eq!(s.materials[0], aff::DEFAULT_MATERIAL);
}

#[test]
fn classic_material_pp_and_ttp() {
    // `f R G B Kd Ks shine T ior`: diffuse = Kd·RGB, specular = Ks white,
    // ambient = diffuse (this loader's reading), ior −1 → 1.
    // `pp 4`: quad with normals, fan → 2 triangles; `ttp`: textured
    // triangle with normals (here deliberately non-unit: normalised).
    let top = format!(
        "{VIEW}f 1 0.5 0 0.8 0.3 20 0.1 -1\n\
pp 4 0 0 0 0 0 1  1 0 0 0 0 1  1 1 0 0 0 1  0 1 0 0 0 1\n\
ttp t.ppm 0 0 0 0 0 2 0.1 0.2  1 0 0 0 0 2 0.3 0.4  0 1 0 0 0 2 0.5 0.6\n"
    );
    let d: PathBuf = std::env::temp_dir().join(format!("raymip-affs-{}-ttp", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let mut ppm = b"P6 1 1 255\n".to_vec();
    ppm.extend([9, 9, 9]);
    std::fs::write(d.join("t.ppm"), ppm).unwrap();
    std::fs::write(d.join("top.aff"), top).unwrap();
    let s = aff::load(&d.join("top.aff"), 0.0).unwrap_or_else(|e| panic!("{e}"));
    std::fs::remove_dir_all(&d).ok();
    let m = s.materials[0];
    assert_eq!(m.diffuse, V3::new(0.8, 0.4, 0.0));
    assert_eq!(m.ambient, m.diffuse);
    assert_eq!(m.specular, V3::splat(0.3));
    assert_eq!(
        (m.shine, m.transmission, m.ior),
        (20.0, V3::splat(0.1), 1.0)
    );
    assert_eq!(s.triangles.len(), 3);
    assert_eq!(
        s.triangles[1].p,
        [
            V3::splat(0.0),
            V3::new(1.0, 1.0, 0.0),
            V3::new(0.0, 1.0, 0.0)
        ]
    );
    let t = s.triangles[2];
    assert_eq!(t.n.unwrap()[0], V3::new(0.0, 0.0, 1.0));
    assert_eq!(t.uv.unwrap(), [[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]]);
    assert_eq!(t.texture, Some(0));
}
