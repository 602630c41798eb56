//! The run-time-configured sampler (`DynSampler` through a texel cache:
//! every format, colour space, tier, address mode per axis, border, bias,
//! lod clamps and filter, anisotropic included) against the f64 reference
//! (`raymip_host::accuracy::fuzz_case`): every case must stay
//! within the documented bound of its configuration.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raymip_host::accuracy::fuzz_case;

fuzz_target!(|data: &[u8]| {
    if let Some((case, error, bound)) = fuzz_case(data) {
        assert!(
            error <= bound,
            "{case}: error {error} LSB > bound {bound} LSB"
        );
    }
});
