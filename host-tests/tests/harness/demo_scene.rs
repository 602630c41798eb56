//! The bare-metal demo scene on the host.

use std::path::Path;

use raymip_host::cli::demo_data::{generate_data, stale_files};

/// `demo/scene/src/data.rs` and the texture pyramids equal what the
/// generator writes now.
#[test]
fn demo_data_is_up_to_date() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let stale = stale_files(&root, &generate_data().unwrap());
    assert!(
        stale.is_empty(),
        "{stale:?} stale: run `cargo run -p raymip-host --bin raymip-demo -- gen-data`"
    );
}

/// The fixed-point set-up on the host rebuilds exactly the static table
/// (what the firmware checks at start-up on each target).
#[test]
fn rebuilt_table_equals_static_table() {
    let (_, counters) = raymip_demo_scene::render_checksum().unwrap();
    assert_eq!(counters.table_mismatches, 0);
    assert_eq!(
        counters.pixels,
        raymip_demo_scene::WIDTH * raymip_demo_scene::HEIGHT
    );
    assert_eq!(counters.segments, counters.hits + counters.misses);
    assert_eq!(counters.pushes, counters.pops);
    // Issue 11, defect 4: no mirror branch is dropped (one entry per path).
    assert_eq!(counters.stack_full, 0);
}

/// Every table LOD of the demo's textured hits is within the documented
/// bound of an independent f64 evaluation `log2(Pl / Pb)` with `Pb` from the
/// f64 geometry of the scene (triangle area / texel count / pixel angle).
#[test]
fn demo_table_entries_match_f64_geometry() {
    use raymip_demo_scene::{Material, QUADS, TEX_SIZE};
    let fov = raymip_demo_scene::FOV_Y_DEGREES.to_radians();
    let gamma = (2.0 * (fov / 2.0).tan() / f64::from(raymip_demo_scene::HEIGHT)).atan();
    let table = raymip_demo_scene::static_table();
    for quad in &QUADS {
        let Material::Textured { scale, .. } = quad.material else {
            assert!(table[quad.tri].is_untextured());
            continue;
        };
        // A texel is (1/scale)/TEX_SIZE scene units wide (isotropic mapping).
        let texel = 65536.0 / f64::from(scale) / f64::from(TEX_SIZE);
        let want = (texel / gamma).log2();
        for k in 0..2 {
            let got = table[quad.tri + k].to_i16f16().to_num::<f64>();
            assert!(
                (got - want).abs() <= raymip::setup::table::TABLE_MAX_ERROR,
                "triangle {}: log2 Pb {got} vs f64 {want}",
                quad.tri + k
            );
        }
    }
}
