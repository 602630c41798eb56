//! The firmware's ray-differential lod against the f64 reference on random
//! camera chains of every case class of the documented input range
//! (`raymip_host::raydiff_chains`): within the first-order bound the
//! firmware's per-operation constants give, exact for the degenerate
//! classes, and within `RAYDIFF_LOD_MAX_ERROR` wherever that bound is.

use proptest::prelude::*;
use raymip::lod::raydiff::RAYDIFF_LOD_MAX_ERROR;
use raymip::rng::XorShift64;
use raymip_host::raydiff_chains::{CLASSES, Class, Raymip, run};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    /// One chain per case: its class, its seed.
    #[test]
    fn every_class_within_its_bound(class in 0..CLASSES.len(), seed in 1u64..) {
        let class = CLASSES[class];
        let o = run(&Raymip, class, &mut XorShift64(seed));
        if matches!(class, Class::Collinear | Class::FlatUv) {
            // The exact zero tests: Lod::MAX or Lod::MIN, no rounding.
            prop_assert_eq!(o.err, 0.0, "{:?}", o);
        }
        prop_assert!(o.err <= o.bound, "{:?}", o);
        if o.bound <= RAYDIFF_LOD_MAX_ERROR {
            prop_assert!(o.err <= RAYDIFF_LOD_MAX_ERROR);
        }
    }
}

/// The bound is not vacuous: on the ordinary classes nearly every chain's
/// bound is below `RAYDIFF_LOD_MAX_ERROR`, and no measured error exceeds
/// it in any class.
#[test]
fn the_bound_is_tight_where_it_should_be() {
    for class in CLASSES {
        let (mut tight, mut n, mut worst) = (0, 0, 0.0f64);
        for i in 0..2_000u64 {
            let o = run(&Raymip, class, &mut XorShift64(0x5EED ^ (i << 8) | 1));
            n += 1;
            tight += usize::from(o.bound <= RAYDIFF_LOD_MAX_ERROR);
            worst = worst.max(o.err);
        }
        println!(
            "{}: {tight}/{n} chains with the bound within 2⁻⁷, largest error {worst:.5}",
            class.name()
        );
        assert!(worst <= RAYDIFF_LOD_MAX_ERROR, "{}: {worst}", class.name());
        if matches!(
            class,
            Class::Ordinary | Class::Sliver | Class::Lopsided | Class::SlowUv
        ) {
            assert!(tight * 100 >= n * 99, "{}: {tight}/{n}", class.name());
        }
    }
}
