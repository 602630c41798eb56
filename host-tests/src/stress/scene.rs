//! Scene edges: non-finite numbers in a scene file, and a render of
//! degenerate geometry.

use super::{Runner, bad, err, value};

pub(super) fn scene_file(r: &mut Runner) {
    let dir = std::env::temp_dir().join(format!("raymip-stress-{}", std::process::id()));
    for (name, text) in [
        (
            "NaN vertex",
            "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 8 8\nf 1 1 1 0 0 0 0 0\np 3\nnan 0 0\n1 0 0\n0 1 0\n",
        ),
        (
            "inf vertex",
            "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 8 8\nf 1 1 1 0 0 0 0 0\np 3\n0 0 0\n1e400 0 0\n0 1 0\n",
        ),
        (
            "NaN camera angle",
            "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle nan\nhither 0.01\nresolution 8 8\n",
        ),
    ] {
        let dir = dir.clone();
        r.case(name, "scene: load_aff", move || {
            std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
            let p = dir.join("s.aff");
            std::fs::write(&p, text).map_err(|e| e.to_string())?;
            let res = crate::scene::load_aff(&p, 0.0).map_err(|e| e.to_string());
            match res {
                Err(e) if e.contains("s.aff") => err(e.lines().next().unwrap_or("").to_string()),
                Err(e) => bad(format!("error without the file: {e}")),
                Ok(_) => bad("accepted"),
            }
        });
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 48×32 render (table and cone methods, fixed and float, 12 bounces)
/// of a scene with a zero-area and a collinear textured triangle, a
/// zero-UV-area one, a floor seen at grazing incidence from 10⁻³ above it
/// and two facing mirrors.
pub(super) fn degenerate_scene() -> crate::scene::Scene {
    use crate::scene::builtin::{quads, tiles_texture};
    use crate::scene::{Camera, Light, Material, Scene, Triangle, V3};
    let mat = |specular: f64| Material {
        ambient: V3::splat(0.2),
        diffuse: V3::splat(0.7),
        specular: V3::splat(specular),
        shine: 50.0,
        transmission: V3::ZERO,
        ior: 1.0,
    };
    let tri = |p: [V3; 3], uv: [[f64; 2]; 3]| Triangle {
        p,
        n: None,
        uv: Some(uv),
        material: 0,
        texture: Some(0),
    };
    let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let mut t = vec![
        tri([V3::new(0.0, 1.0, -3.0); 3], uv),
        tri(
            [
                V3::new(-1.0, 0.5, -3.0),
                V3::new(0.0, 1.0, -3.0),
                V3::new(1.0, 1.5, -3.0),
            ],
            uv,
        ),
        tri(
            [
                V3::new(-1.0, 0.5, -2.5),
                V3::new(1.0, 0.5, -2.5),
                V3::new(0.0, 1.5, -2.5),
            ],
            [[0.5, 0.5]; 3],
        ),
    ];
    // A long floor and two panels at z = ∓6.
    #[rustfmt::skip]
    t.extend(quads(&[
        ([-50.0, 0.0, 5.0], [100.0, 0.0, 0.0], [0.0, 0.0, -200.0], [50.0, 100.0], 0, Some(0)),
        ([-3.0, 0.0, -6.0], [6.0, 0.0, 0.0],   [0.0, 3.0, 0.0],    [1.0, 1.0],    1, None),
        ([-3.0, 0.0, 6.0],  [6.0, 0.0, 0.0],   [0.0, 3.0, 0.0],    [1.0, 1.0],    1, None),
    ]));
    Scene {
        camera: Camera::looking_at(
            V3::new(0.0, 1.0e-3, 0.0),
            V3::new(0.0, 1.0e-3, -1.0),
            60.0,
            (48, 32),
        ),
        background: V3::splat(0.5),
        environment: None,
        ambient: V3::splat(0.2),
        lights: vec![Light {
            position: V3::new(0.0, 5.0, 0.0),
            color: V3::splat(0.8),
        }],
        materials: vec![mat(0.0), mat(0.95)],
        textures: vec![tiles_texture()],
        triangles: t,
    }
}

pub(super) fn render_degenerate(r: &mut Runner) {
    use crate::render::{Arithmetic, Method, Options, Prepared, render};
    let scene = degenerate_scene();
    for method in [Method::Table, Method::Cone] {
        for arithmetic in [Arithmetic::Fixed, Arithmetic::Float] {
            let scene = scene.clone();
            r.case(
                format!(
                    "zero-area, collinear, zero-UV triangles; grazing floor; mirrors ({} {})",
                    method.name(),
                    arithmetic.name()
                ),
                "renderer: render (12 bounces)",
                move || {
                    let prep = Prepared::new(scene, None).map_err(|e| e.to_string())?;
                    let img = render(
                        &prep,
                        &Options {
                            method,
                            arithmetic,
                            size: None,
                            bounces: 12,
                            spp: 1,
                            record_blocks: false,
                            progress: false,
                            aniso: None,
                        },
                    );
                    let c = &img.counters;
                    if img.rgb.iter().flatten().all(|x| x.is_finite())
                        && c.stack_full == 0
                        && c.textured_hits > 0
                    {
                        value(format!(
                            "{} textured hits, deepest path {}, finite image, no branch dropped",
                            c.textured_hits,
                            c.max_depth()
                        ))
                    } else {
                        bad(format!("{c:?}"))
                    }
                },
            );
        }
    }
}
