//! BART kitchen and robots render through the firmware texture path at a
//! reduced size (skipped with a clear line when the scenes are absent).

use std::path::PathBuf;

use raymip_host::render::{Arithmetic, Method, Options, Prepared, render};
use raymip_host::scene::aff;
use raymip_host::scene::aff_adapter;

fn bart_dir() -> Option<PathBuf> {
    let d = std::env::var_os("RAYMIP_BART_DIR").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/bart"),
        PathBuf::from,
    );
    d.is_dir().then_some(d)
}

fn check(name: &str, triangles: usize, textured: usize) {
    let Some(dir) = bart_dir() else {
        println!("SKIP: BART scenes (../shared/scenes/bart) not found; {name} not rendered");
        return;
    };
    let top = aff::find_top_level(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
    let loaded = aff::load(&top, aff::DEFAULT_TIME).unwrap_or_else(|e| panic!("{e}"));
    // Published counts (triangles read after triangulation); zero-area
    // triangles are dropped by the loader.
    assert_eq!(loaded.stats.triangles_read, triangles, "{name} triangles");
    assert_eq!(loaded.stats.textured_read, textured, "{name} textured");
    let dropped = loaded.stats.skipped_degenerate;
    let scene = aff_adapter(loaded);
    assert_eq!(scene.triangles.len() + dropped, triangles);
    let prep = Prepared::new(scene, Some((160, 96))).unwrap();
    for method in [Method::Table, Method::Cone] {
        let opts = Options {
            method,
            arithmetic: Arithmetic::Fixed,
            size: Some((160, 96)),
            bounces: 10,
            spp: 1,
            record_blocks: false,
            aniso: None,
            progress: false,
        };
        let img = render(&prep, &opts);
        let c = &img.counters;
        println!("{name} {}: {c:?}", method.name());
        assert_eq!(c.paths, 160 * 96);
        assert!(c.hits > 0 && c.textured_hits > 0, "{name}: no textured hit");
        assert_eq!(c.level_hist.iter().sum::<u64>(), c.textured_hits);
        assert!(img.rgb.iter().flatten().all(|x| x.is_finite()));
    }
}

#[test]
fn bart_kitchen_renders() {
    check("kitchen", 110_561, 5_328);
}

#[test]
fn bart_robots_renders() {
    check("robots", 71_708, 65_786);
}
