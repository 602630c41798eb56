//! Renderer tests on the built-in scenes (reduced sizes to keep CI fast).

use raymip_host::output::metrics::psnr;
use raymip_host::render::{Arithmetic, Image, Method, Options, Prepared, RenderError, render};
use raymip_host::scene::builtin::{
    self, NAMES, fronto_quad, mirror_quad, one_texel_per_pixel_distance,
};

const SIZE: (u32, u32) = (200, 120);

fn opts(method: Method, arithmetic: Arithmetic) -> Options {
    Options {
        method,
        arithmetic,
        size: Some(SIZE),
        bounces: 10,
        spp: 64,
        record_blocks: false,
        aniso: None,
        progress: false,
    }
}

fn prep(name: &str) -> Prepared {
    Prepared::new(builtin::by_name(name).unwrap(), Some(SIZE)).unwrap()
}

/// Every built-in scene at 10 bounces, both methods and precisions: the
/// fixed-point image within 50 dB of the float one, no branch dropped.
#[test]
fn fixed_vs_float_psnr_at_least_50_db() {
    for name in NAMES {
        let p = prep(name);
        for m in [Method::Table, Method::Cone] {
            let a = render(&p, &opts(m, Arithmetic::Fixed));
            let b = render(&p, &opts(m, Arithmetic::Float));
            // Issue 11, defect 4: at 10 bounces no branch is dropped (a
            // 10-entry stack drops some on `glass`).
            for (img, pr) in [(&a, "fixed"), (&b, "float")] {
                assert!(img.counters.stack_peak <= 11, "{name}: {:?}", img.counters);
                assert_eq!(
                    img.counters.stack_full,
                    0,
                    "{name} {} {pr}: branches dropped on a full ray stack",
                    m.name()
                );
            }
            let q = psnr(&a.to_rgb8(), &b.to_rgb8());
            println!("{name} {}: fixed vs float {q:.2} dB", m.name());
            assert!(q >= 50.0, "{name} {}: {q:.2} dB < 50 dB", m.name());
        }
    }
}

/// Lod of the centre pixel of a fronto-parallel quad at `k` times the
/// one-texel-per-pixel distance.
fn centre_lod(k: f64, m: Method, p: Arithmetic) -> f64 {
    let (fov, tex, side) = (45.0, 256, 2.0);
    let d = one_texel_per_pixel_distance(side, tex, fov, SIZE.1);
    let scene = fronto_quad(side, tex, k * d, fov, SIZE.0, SIZE.1);
    let prep = Prepared::new(scene, None).unwrap();
    let img: Image = render(&prep, &opts(m, p));
    let i = (SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) as usize;
    f64::from(img.lod[i])
}

#[test]
fn fronto_parallel_quad_lod_zero_then_one() {
    let tol = 1.0 / 256.0;
    // Ray differentials measure the same footprint: f64, and the
    // firmware's fixed-point ones within their stated bound. So do the
    // G-buffer's: on a plane facing the camera the hit point moves
    // linearly with the pixel, so the neighbour difference is the
    // derivative.
    let rd_tol = raymip::lod::raydiff::RAYDIFF_LOD_MAX_ERROR;
    for m in [
        Method::Table,
        Method::Cone,
        Method::Raydiff,
        Method::Gbuffer,
    ] {
        for p in [Arithmetic::Fixed, Arithmetic::Float] {
            let tol = if m.has_footprint() && p == Arithmetic::Fixed {
                rd_tol
            } else {
                tol
            };
            let l1 = centre_lod(1.0, m, p);
            let l2 = centre_lod(2.0, m, p);
            println!(
                "{} {}: lod {l1:.5} at Pb, {l2:.5} at 2·Pb",
                m.name(),
                p.name()
            );
            assert!(
                l1.abs() <= tol,
                "{} {}: lod {l1} at one texel per pixel",
                m.name(),
                p.name()
            );
            assert!(
                (l2 - 1.0).abs() <= tol,
                "{} {}: lod {l2} at twice the distance",
                m.name(),
                p.name()
            );
        }
    }
}

/// Issue 21: in every isotropic filter mode each textured hit is sampled
/// once, at the lod its method chose: the sum of the lods the texture unit
/// was given equals the sum of the method's lods (the level histogram's
/// values), exactly, for every method and precision; no anisotropic sample
/// is taken unless asked for, and then only those. The sums differ between
/// methods, so a sample taken at another method's lod would show.
#[test]
fn every_filter_samples_at_the_methods_lod() {
    use raymip::texture::sampler::stochastic::StochasticMode;
    use raymip_host::render::texunit::Filter;
    use raymip_host::render::{FrameFilter, render_filtered};
    let size = (96, 60);
    let p = Prepared::new(builtin::by_name("hall").unwrap(), Some(size)).unwrap();
    let o = |m, pr| Options {
        size: Some(size),
        bounces: 3,
        ..opts(m, pr)
    };
    let filters = [
        Filter::Nearest,
        Filter::Bilinear,
        Filter::Trilinear,
        Filter::BilinearLevel0,
        Filter::Stochastic(StochasticMode::Trilinear),
        Filter::Stochastic(StochasticMode::Bilinear),
        Filter::Stochastic(StochasticMode::TrilinearBilinear),
    ];
    for pr in [Arithmetic::Fixed, Arithmetic::Float] {
        let mut sums = Vec::new();
        let methods = [
            Method::Table,
            Method::Cone,
            Method::Raydiff,
            Method::Gbuffer,
            Method::Mip0,
        ];
        for m in methods {
            for filter in filters {
                let img = render_filtered(&p, &o(m, pr), Some(FrameFilter { filter, frame: 0 }));
                let c = &img.counters;
                let what = format!("{} {} {filter:?}", m.name(), pr.name());
                assert!(c.textured_hits > 1000, "{what}: {c:?}");
                assert_eq!(
                    c.samples, c.textured_hits,
                    "{what}: one sample per textured hit"
                );
                assert_eq!(c.aniso_samples, 0, "{what}");
                assert_eq!(
                    c.sampled_lod_sum_256, c.lod_sum_256,
                    "{what}: the unit sampled at other lods than the method chose"
                );
                if filter == Filter::Trilinear {
                    sums.push((m.name(), c.lod_sum_256));
                }
            }
        }
        for (i, a) in sums.iter().enumerate() {
            for b in &sums[i + 1..] {
                assert_ne!(
                    a.1,
                    b.1,
                    "{} {}: {} and {} lods sum alike",
                    pr.name(),
                    a.0,
                    a.0,
                    b.0
                );
            }
        }
        for m in [Method::Raydiff, Method::Gbuffer] {
            let aniso = render(
                &p,
                &Options {
                    aniso: Some(4),
                    ..o(m, pr)
                },
            );
            let c = &aniso.counters;
            let what = format!("{} {} aniso", m.name(), pr.name());
            assert_eq!(c.aniso_samples, c.textured_hits, "{what}");
            assert_eq!(c.samples, 0, "{what}: no isotropic sample");
        }
    }
}

/// Issue 21: the lod a sample uses is the chosen method's in every filter
/// mode. The firmware ray differentials drive the fixed render (its image
/// within 40 dB of the f64 ray differentials'); with at most one probe an
/// anisotropic sample is the trilinear one at the ray-differential lod
/// (the major axis), in both precisions; the table and cone methods have no
/// footprint, so anisotropic filtering is refused for them.
#[test]
fn sampling_uses_the_chosen_methods_lod_in_every_filter_mode() {
    let p = prep("hall");
    let fixed = render(&p, &opts(Method::Raydiff, Arithmetic::Fixed));
    let float = render(&p, &opts(Method::Raydiff, Arithmetic::Float));
    let q = psnr(&fixed.to_rgb8(), &float.to_rgb8());
    println!("hall raydiff: fixed (firmware differentials) vs float {q:.2} dB");
    assert!(q >= 40.0, "raydiff fixed vs float: {q:.2} dB");
    for pr in [Arithmetic::Fixed, Arithmetic::Float] {
        let tri = render(&p, &opts(Method::Raydiff, pr));
        let one = render(
            &p,
            &Options {
                aniso: Some(1),
                ..opts(Method::Raydiff, pr)
            },
        );
        let q = psnr(&tri.to_rgb8(), &one.to_rgb8());
        println!(
            "hall raydiff {}: trilinear vs one aniso probe {q:.2} dB",
            pr.name()
        );
        assert!(q >= 40.0, "{}: {q:.2} dB", pr.name());
        let bits = |i: &Image| i.lod.iter().map(|l| l.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&tri),
            bits(&one),
            "{}: the reported lod is the method's",
            pr.name()
        );
    }
    for m in [Method::Table, Method::Cone, Method::Mip0] {
        let o = Options {
            aniso: Some(8),
            ..opts(m, Arithmetic::Fixed)
        };
        assert!(
            matches!(
                o.validate(),
                Err(RenderError::AnisoNeedsRaydiff { method }) if method == m
            ),
            "{}",
            m.name()
        );
        assert!(opts(m, Arithmetic::Fixed).validate().is_ok());
    }
}

#[test]
fn hall_mip_mapped_closer_to_truth_than_mip0() {
    let p = prep("hall");
    let truth = render(&p, &opts(Method::Truth, Arithmetic::Float)).to_rgb8();
    let mip0 = psnr(
        &render(&p, &opts(Method::Mip0, Arithmetic::Fixed)).to_rgb8(),
        &truth,
    );
    for m in [Method::Table, Method::Cone] {
        for pr in [Arithmetic::Fixed, Arithmetic::Float] {
            let q = psnr(&render(&p, &opts(m, pr)).to_rgb8(), &truth);
            println!(
                "hall {} {}: {q:.2} dB vs truth (mip0 {mip0:.2} dB)",
                m.name(),
                pr.name()
            );
            assert!(
                q > mip0 + 1.0,
                "{} {}: {q:.2} dB not above mip0 {mip0:.2} dB",
                m.name(),
                pr.name()
            );
        }
    }
}

#[test]
fn mirror_room_has_deep_paths_and_glass_refracts() {
    let img = render(&prep("mirrors"), &opts(Method::Table, Arithmetic::Fixed));
    let c = &img.counters;
    println!("mirrors: hits per depth {:?}", c.depth_hist);
    assert!(c.max_depth() >= 8, "deepest path {} bounces", c.max_depth());
    assert!(c.depth_hist[8] > 0 && c.depth_hist[10] > 0);
    assert_eq!(c.saturations, 0);
    let g = render(&prep("glass"), &opts(Method::Cone, Arithmetic::Fixed));
    assert!(g.counters.bounces > 0 && g.counters.textured_hits > 0);
    // Every textured hit lands in one histogram bin.
    let sum: u64 = g.counters.level_hist.iter().sum();
    assert_eq!(sum, g.counters.textured_hits);
}

#[test]
fn table1_mip_mapping_raises_cache_hit_rate_on_hall() {
    let row = raymip_host::cli::table1::measure("hall", builtin::hall(), SIZE, 10, false).unwrap();
    println!("{row:?}");
    assert!(row.accesses[0] > 0 && row.accesses[1] > 0);
    assert!((row.level_share.iter().sum::<f64>() - 100.0).abs() < 1e-6);
    assert!(
        row.cache_on > row.cache_off,
        "{} vs {}",
        row.cache_on,
        row.cache_off
    );
}

#[test]
fn mirror_bounce_carries_path_length_into_the_lod() {
    // The square seen through a flat 45° mirror: Pl = a + b, so the lod is
    // log2((a + b)/Pb) at the centre pixel, for every method.
    let (fov, tex, side) = (45.0, 256, 2.0);
    let pb = one_texel_per_pixel_distance(side, tex, fov, SIZE.1);
    let tol = 1.0 / 256.0;
    for (k, want) in [(1.0, 0.0), (2.0, 1.0)] {
        let scene = mirror_quad(side, tex, 0.3 * k * pb, 0.7 * k * pb, fov, SIZE.0, SIZE.1);
        let prep = Prepared::new(scene, None).unwrap();
        for (m, p) in [
            (Method::Table, Arithmetic::Fixed),
            (Method::Table, Arithmetic::Float),
            (Method::Cone, Arithmetic::Fixed),
            (Method::Cone, Arithmetic::Float),
            (Method::Raydiff, Arithmetic::Float),
            (Method::Raydiff, Arithmetic::Fixed),
            (Method::Gbuffer, Arithmetic::Float),
            (Method::Gbuffer, Arithmetic::Fixed),
        ] {
            let img = render(&prep, &opts(m, p));
            let i = (SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) as usize;
            let l = f64::from(img.lod[i]);
            println!("{} {} k={k}: lod {l:.5}", m.name(), p.name());
            // The firmware ray differentials: within their stated bound.
            let tol = if (m, p) == (Method::Raydiff, Arithmetic::Fixed) {
                raymip::lod::raydiff::RAYDIFF_LOD_MAX_ERROR
            } else {
                tol
            };
            assert!(
                (l - want).abs() <= tol,
                "{} {}: lod {l}, want {want}",
                m.name(),
                p.name()
            );
            assert!(
                img.counters.depth_hist[1] > 0,
                "the square is seen after one bounce"
            );
        }
    }
}

#[test]
fn convex_mirror_spreads_the_cone_like_paraxial_optics() {
    use raymip_host::scene::builtin::{quad, sphere};
    use raymip_host::scene::{Camera, Material, Scene, V3};
    // Camera at the origin looking down −z at a mirror sphere (r = 1, front
    // 4 away); the centre ray comes straight back and meets a textured
    // square 4 behind the camera. Paraxially a convex mirror adds 2·w/r to
    // the cone angle: width at the square = 4γ + (γ + 8γ)·8 = 76γ, so the
    // lod is log2(76/Pb), while the path length alone gives log2(12/Pb).
    let (fov, tex, side) = (45.0, 256, 20.0);
    let pb = one_texel_per_pixel_distance(side, tex, fov, SIZE.1);
    let mat = |d: f64, s: f64| Material {
        ambient: V3::splat(d),
        diffuse: V3::splat(d),
        specular: V3::splat(s),
        shine: 10.0,
        transmission: V3::ZERO,
        ior: 1.0,
    };
    let mut triangles = sphere(V3::new(0.013, 0.007, -5.0), 1.0, 256, 128, 1);
    let h = side / 2.0;
    triangles.extend(quad(
        V3::new(-h, -h, 4.0),
        V3::new(side, 0.0, 0.0),
        V3::new(0.0, side, 0.0),
        1.0,
        1.0,
        0,
        Some(0),
    ));
    let mut scene: Scene = fronto_quad(side, tex, 1.0, fov, SIZE.0, SIZE.1);
    scene.camera = Camera::looking_at(V3::ZERO, V3::new(0.0, 0.0, -1.0), fov, SIZE);
    scene.materials = vec![mat(1.0, 0.0), mat(0.0, 1.0)];
    scene.triangles = triangles;
    let prep = Prepared::new(scene, None).unwrap();
    let i = (SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) as usize;
    let lod = |m: Method, p: Arithmetic| f64::from(render(&prep, &opts(m, p)).lod[i]);
    let (want_cone, want_table) = ((76.0 / pb).log2(), (12.0 / pb).log2());
    for p in [Arithmetic::Fixed, Arithmetic::Float] {
        let t = lod(Method::Table, p);
        let c = lod(Method::Cone, p);
        println!(
            "{}: table {t:.4} (want {want_table:.4}), cone {c:.4} (want {want_cone:.4})",
            p.name()
        );
        assert!((t - want_table).abs() < 0.01, "table {t} vs {want_table}");
        assert!((c - want_cone).abs() < 0.1, "cone {c} vs {want_cone}");
    }
    let r = lod(Method::Raydiff, Arithmetic::Float);
    println!("raydiff {r:.4}");
    assert!((r - want_cone).abs() < 0.1, "raydiff {r} vs {want_cone}");
}

/// Issue 11, defect 4: the ray-stack worst case. Two facing beam-splitter
/// panes (specular 0.7, transmission 0.3, index 1) over a textured floor:
/// every hit on a pane pushes a refraction and a reflection, the
/// reflection (pushed last) is traced first and hits the other pane, so a
/// refraction waits at every depth: `stack_bound(10, 2) = 11` entries at 10
/// bounces, one more than the paper's 10. The renderer's stack holds them
/// all (no branch dropped) and the peak is exactly the bound.
#[test]
fn beam_splitter_corridor_reaches_the_stack_bound_without_dropping() {
    use raymip::path::raystack::stack_bound;
    use raymip_host::scene::{Camera, Light, Material, Scene, V3};
    let mat = |diffuse: f64, specular: f64, transmission: f64| Material {
        ambient: V3::splat(diffuse),
        diffuse: V3::splat(diffuse),
        specular: V3::splat(specular),
        shine: 200.0,
        transmission: V3::splat(transmission),
        ior: 1.0,
    };
    let (splitter, floor) = (mat(0.05, 0.7, 0.3), mat(0.8, 0.0, 0.0));
    // The panes x = ∓1 and the floor.
    #[rustfmt::skip]
    let t = builtin::quads(&[
        ([-1.0, -1.0, 1.0], [0.0, 0.0, -101.0], [0.0, 4.0, 0.0],    [1.0, 1.0],   0, None),
        ([1.0, -1.0, 1.0],  [0.0, 0.0, -101.0], [0.0, 4.0, 0.0],    [1.0, 1.0],   0, None),
        ([-1.0, -1.0, 1.0], [2.0, 0.0, 0.0],    [0.0, 0.0, -101.0], [2.0, 100.0], 1, Some(0)),
    ]);
    let scene = Scene {
        camera: Camera::looking_at(
            V3::new(0.0, 0.5, 0.0),
            V3::new(0.0, 0.3, -1.0),
            60.0,
            (64, 48),
        ),
        background: V3::new(0.6, 0.7, 0.85),
        environment: None,
        ambient: V3::splat(0.2),
        lights: vec![Light {
            position: V3::new(0.0, 2.5, -3.0),
            color: V3::splat(0.8),
        }],
        materials: vec![splitter, floor],
        textures: vec![builtin::tiles_texture()],
        triangles: t,
    };
    let prep = Prepared::new(scene, None).unwrap();
    for m in [Method::Table, Method::Cone] {
        let c = render(&prep, &opts(m, Arithmetic::Fixed)).counters;
        println!(
            "corridor {}: stack peak {} entries, {} dropped, hits per depth {:?}",
            m.name(),
            c.stack_peak,
            c.stack_full,
            c.depth_hist
        );
        assert_eq!(c.stack_full, 0, "{}: branches dropped", m.name());
        assert_eq!(c.stack_peak, stack_bound(10, 2) as u64, "{}", m.name());
    }
}

/// Rays that leave `builtin:envmap` sample its environment map at the
/// method's lod: the cone and ray-differential lods beat mip 0
/// against the supersampled truth in both precisions (the pattern aliases
/// at level 0), ray differentials beat cones (the glass sphere: refracted
/// cones keep their spread), and the fixed-point lookups (firmware lod,
/// CORDIC `(u, v)`, sampler) stay within 45 dB of the f64 ones.
#[test]
fn envmap_misses_are_filtered_at_the_methods_lod() {
    let p = prep("envmap");
    assert!(p.env.is_some());
    let truth = render(&p, &opts(Method::Truth, Arithmetic::Float)).to_rgb8();
    for pr in [Arithmetic::Fixed, Arithmetic::Float] {
        let q = |m| psnr(&render(&p, &opts(m, pr)).to_rgb8(), &truth);
        let (mip0, cone, rd) = (q(Method::Mip0), q(Method::Cone), q(Method::Raydiff));
        println!(
            "envmap {}: mip0 {mip0:.2} cone {cone:.2} raydiff {rd:.2} dB",
            pr.name()
        );
        assert!(
            cone > mip0 + 2.0 && rd > cone,
            "{}: {mip0} {cone} {rd}",
            pr.name()
        );
    }
    for m in [Method::Mip0, Method::Cone, Method::Raydiff] {
        let a = render(&p, &opts(m, Arithmetic::Fixed)).to_rgb8();
        let b = render(&p, &opts(m, Arithmetic::Float)).to_rgb8();
        let q = psnr(&a, &b);
        assert!(q >= 45.0, "envmap {}: fixed vs float {q:.2} dB", m.name());
    }
}
