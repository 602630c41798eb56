//! Issue 13: a render with pyramids trimmed to the levels the set-up
//! analysis allows is bit-identical to the render with full pyramids, on
//! every built-in scene and on BART kitchen and robots (skipped with a
//! clear line when `../shared/scenes/bart` is absent); small sizes.

use raymip_host::render::skip::{bit_identical, plan, render_trimmed};
use raymip_host::render::{Arithmetic, Method, Options, Prepared, render};
use raymip_host::scene::{builtin, default_bart_dir, load_scene_dir};

fn opts(method: Method, size: (u32, u32)) -> Options {
    Options {
        method,
        arithmetic: Arithmetic::Fixed,
        size: Some(size),
        bounces: 10,
        spp: 2,
        record_blocks: false,
        progress: false,
        aniso: None,
    }
}

/// Full and trimmed renders of `prep` with the table method and mip 0;
/// returns the bytes saved by the table method's trimming.
fn check(label: &str, prep: &mut Prepared, size: (u32, u32)) -> u64 {
    let mut saved = 0;
    for method in [Method::Table, Method::Mip0] {
        let o = opts(method, size);
        let p = plan(prep, &o);
        assert!(p.applies, "{label}: the plan must apply to {method:?}");
        let full = render(prep, &o);
        let trimmed = render_trimmed(prep, &o, &p);
        println!(
            "{label} {}: stored {} of {} bytes ({:.1} % saved), {} textures skipped",
            method.name(),
            p.stored_bytes,
            p.full_bytes,
            p.saved_percent(),
            p.textures_skipped
        );
        assert!(full.counters.textured_hits > 0, "{label}: no textured hit");
        assert!(
            bit_identical(&full, &trimmed),
            "{label} {}: trimmed render differs from the full one",
            method.name()
        );
        if method == Method::Table {
            saved = p.saved_bytes();
        } else {
            // Mip 0 reads level 0 only: every coarser level is left out.
            for t in p.textures.iter().filter(|t| t.triangles > 0) {
                assert_eq!(t.stored, Some((0, 0)), "{label}: {}", t.name);
            }
        }
    }
    saved
}

#[test]
fn builtin_scenes_trimmed_renders_are_bit_identical() {
    let mut saved = 0;
    for name in builtin::NAMES {
        let scene = builtin::by_name(name).unwrap();
        let mut prep = Prepared::new(scene, Some((80, 48))).unwrap();
        saved += check(name, &mut prep, (80, 48));
    }
    // The comparison is only worth something if trimming removed levels.
    assert!(saved > 0, "no built-in scene trimmed anything");
}

/// Negative control: storing only the coarsest allowed level of every
/// texture changes the render (the comparison can fail). (Dropping just
/// the first allowed level need not: the bounds are conservative, from
/// bounding boxes, and the nearest box point may be out of view.)
#[test]
fn trimming_one_level_too_many_is_detected() {
    let scene = builtin::by_name("hall").unwrap();
    let size = (80, 48);
    let mut prep = Prepared::new(scene, Some(size)).unwrap();
    let o = opts(Method::Table, size);
    let mut p = plan(&prep, &o);
    let full = render(&prep, &o);
    let mut tightened = false;
    for t in &mut p.textures {
        if let Some((first, last)) = t.stored
            && t.triangles > 0
            && first < last
        {
            t.stored = Some((last, last));
            tightened = true;
        }
    }
    assert!(tightened, "hall: no texture with two stored levels");
    let trimmed = render_trimmed(&mut prep, &o, &p);
    assert!(
        !bit_identical(&full, &trimmed),
        "too-tight trimming went unnoticed"
    );
}

fn bart(name: &str) {
    let dir = default_bart_dir().join(name);
    if !dir.is_dir() {
        println!("SKIP: BART scenes (../shared/scenes/bart) not found; {name} not checked");
        return;
    }
    let scene = load_scene_dir(&dir, 0.0).unwrap();
    let size = (96, 64);
    let mut prep = Prepared::new(scene, Some(size)).unwrap();
    check(name, &mut prep, size);
}

#[test]
fn bart_kitchen_trimmed_render_is_bit_identical() {
    bart("kitchen");
}

#[test]
fn bart_robots_trimmed_render_is_bit_identical() {
    bart("robots");
}
