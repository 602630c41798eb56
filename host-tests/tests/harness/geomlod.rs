//! Stochastic geometric LOD end to end on `builtin:instances`: the mesh
//! chain, t = 0 equals discrete, path consistency of the ray mask over a
//! full frame, convergence of accumulated frames to the exact blend, the
//! firmware's selection against an f64 reference, and the CLI.

use std::process::Command;
use std::sync::OnceLock;

use raymip_host::render::CameraFrame;
use raymip_host::render::instances::{
    Config, FrameStats, GeomLodMode, InstanceScene, MaskPolicy, Prepared, accumulate, blend, mean,
    rms,
};
use raymip_host::scene::instances::{LEVELS, View, Z_FAR, Z_NEAR};
use raymip_reference::geomlod;

fn scene() -> &'static InstanceScene {
    static S: OnceLock<InstanceScene> = OnceLock::new();
    S.get_or_init(InstanceScene::build)
}

fn cfg(mode: GeomLodMode, t: f64, view: View, size: (u32, u32)) -> Config {
    Config {
        mode,
        transition: t,
        view,
        size,
        frames: 1,
        bounces: 2,
        ..Config::default()
    }
}

#[test]
fn mesh_chain_is_dense_and_halves() {
    let s = scene();
    assert_eq!(s.placements.len(), 64 * 60);
    assert_eq!(s.lod_triangles.len(), 8);
    assert!(s.lod_triangles[0] >= 65_536, "{:?}", s.lod_triangles);
    for w in s.lod_triangles.windows(2) {
        let r = w[1] as f64 / w[0] as f64;
        assert!((0.45..=0.55).contains(&r), "{:?}", s.lod_triangles);
    }
    let total = s.lod_triangles[0] as f64 / s.lod_triangles[7] as f64;
    assert!((100.0..=160.0).contains(&total), "LOD 0 / LOD 7 = {total}");
}

#[test]
fn transition_zero_is_exactly_discrete() {
    let s = scene();
    for view in View::ALL {
        let d = cfg(GeomLodMode::Discrete, 0.0, view, (48, 32));
        let t0 = cfg(GeomLodMode::Stochastic, 0.0, view, (48, 32));
        let pd = Prepared::new(s, &d).unwrap();
        let pt = Prepared::new(s, &t0).unwrap();
        assert_eq!(pd.records, pt.records, "{view:?}");
        assert_eq!(pd.records.len(), s.placements.len());
        let (fd, ft) = (
            pd.render_frame(s, &d, 3, None),
            pt.render_frame(s, &t0, 3, None),
        );
        assert_eq!(fd.rgb, ft.rgb);
        assert_eq!(fd.lod, ft.lod);
        let strip = |mut f: FrameStats| {
            f.render_s = 0.0;
            f.cpu_s = 0.0;
            f
        };
        assert_eq!(strip(fd.stats), strip(ft.stats));
    }
}

#[test]
fn every_ray_of_a_path_honours_the_primary_mask() {
    let s = scene();
    for view in [View::High, View::Close] {
        let c = cfg(GeomLodMode::Stochastic, 1.0, view, (160, 96));
        let p = Prepared::new(s, &c).unwrap();
        assert!(
            p.records.len() > s.placements.len(),
            "some instances in transition"
        );
        let f = p.render_frame(s, &c, 0, None);
        let st = f.stats;
        assert_eq!(st.primary, 160 * 96);
        assert!(st.reflection > 1000 && st.shadow > 1000, "{st:?}");
        assert!(st.masked > 0, "masks must exclude instances: {st:?}");
        assert_eq!(st.mismatches, 0, "{view:?}: {st:?}");
        // The counter can fail: secondary rays with a fresh random bit
        // hit instances the primary mask excludes.
        let bad = Config {
            policy: MaskPolicy::PerRay,
            ..c
        };
        let fb = p.render_frame(s, &bad, 0, None);
        assert!(fb.stats.mismatches > 0, "{view:?}: {:?}", fb.stats);
    }
}

/// Accumulated frames converge to the exact per-pixel blend (the mean of
/// the 8 single-bit renders: for primary hits `(popcount(mask_a)·C_a +
/// popcount(mask_b)·C_b)/8`). With independent uniform mask bits per
/// frame, the expected squared error of an N-frame mean at pixel p is
/// σ²_p/N (σ²_p the variance of the 8 renders); the measured mean squared
/// error must lie within [0.6, 1.4] × that prediction and below 0.05² RMS.
#[test]
fn accumulation_converges_to_the_blend() {
    let s = scene();
    let frames = 64;
    let c = Config {
        frames,
        ..cfg(GeomLodMode::Stochastic, 1.0, View::High, (64, 40))
    };
    let p = Prepared::new(s, &c).unwrap();
    let b = blend(&p, s, &c);
    let singles: Vec<_> = (0..8)
        .map(|k| p.render_frame(s, &c, 0, Some(1 << k)))
        .collect();
    let blend_check = mean(&singles.iter().map(|f| f.lod.as_slice()).collect::<Vec<_>>());
    assert_eq!(blend_check, b.lod);
    let var: f64 = (0..b.lod.len())
        .map(|px| {
            (0..3)
                .map(|ch| {
                    singles
                        .iter()
                        .map(|f| (f.lod[px][ch] - b.lod[px][ch]).powi(2))
                        .sum::<f64>()
                        / 8.0
                })
                .sum::<f64>()
        })
        .sum::<f64>()
        / (3 * b.lod.len()) as f64;
    assert!(var > 1e-3, "the view must have dissolving pixels ({var})");
    let acc = accumulate(&p, s, &c, false);
    let mse: f64 = acc
        .lod
        .iter()
        .zip(&b.lod)
        .map(|(a, e)| (0..3).map(|k| (a[k] - e[k]).powi(2)).sum::<f64>())
        .sum::<f64>()
        / (3 * b.lod.len()) as f64;
    let predicted = var / f64::from(frames);
    let ratio = mse / predicted;
    assert!(
        (0.6..=1.4).contains(&ratio),
        "mse {mse:.3e} vs predicted {predicted:.3e} (ratio {ratio:.2})"
    );
    assert!(mse.sqrt() < 0.05, "rms {}", mse.sqrt());
    // And the error shrinks with the frame count.
    let first = rms(&acc.snapshots[0].1, &b.lod);
    let last = rms(&acc.snapshots.last().unwrap().1, &b.lod);
    assert!(
        last < first / 4.0,
        "rms 1 frame {first}, {frames} frames {last}"
    );
}

/// The firmware's discrete choice against the f64 LOD formula for every
/// instance of every view (ties within 10⁻⁴ level of a half skipped).
#[test]
fn selection_matches_f64() {
    let s = scene();
    for view in View::ALL {
        let c = cfg(GeomLodMode::Discrete, 0.0, view, (80, 48));
        let p = Prepared::new(s, &c).unwrap();
        let cam = CameraFrame::new(&view.camera(80, 48), 80, 48);
        let mut checked = 0;
        for r in &p.records {
            let z = (s.placements[r.id as usize].translation - cam.eye).dot(cam.fwd);
            let l = geomlod::lod_param(z, Z_NEAR, Z_FAR, LEVELS, 0.0);
            if (l.fract() - 0.5).abs() < 1e-4 {
                continue;
            }
            assert_eq!(f64::from(r.lod), l.round(), "{view:?} z {z} l {l}");
            assert_eq!(r.mask, 0xFF);
            checked += 1;
        }
        assert!(checked > 3000);
    }
}

#[test]
fn cli_renders_instances() {
    let out = std::env::temp_dir().join(format!("raymip-geomlod-cli-{}", std::process::id()));
    let st = Command::new(env!("CARGO_BIN_EXE_raymip-host"))
        .args([
            "render",
            "--scene",
            "builtin:instances",
            "--geom-lod",
            "stochastic",
            "--transition",
            "0.25",
            "--frames",
            "2",
            "--view",
            "low",
            "--size",
            "32x20",
            "--bounces",
            "1",
            "--reference",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    for f in [
        "image.png",
        "lod.png",
        "frame0.png",
        "lod_frame0.png",
        "lod_blend.png",
        "report.json",
        "report.md",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let report = std::fs::read_to_string(out.join("report.json")).unwrap();
    assert!(report.contains("\"mismatches\": 0"), "{report}");
    let bad = Command::new(env!("CARGO_BIN_EXE_raymip-host"))
        .args([
            "render",
            "--scene",
            "builtin:instances",
            "--transition",
            "1.5",
            "--size",
            "8x8",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("transition"));
    let _ = std::fs::remove_dir_all(&out);
}
