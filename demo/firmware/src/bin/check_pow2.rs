//! Cross-core check of the power-of-two pyramid on a soft core (with
//! feature `cfu` the co-processor's texture unit samples it): prints the
//! line of `raymip_demo_scene::pow2_check`; `scripts/softcore` requires it
//! to equal the host's `raymip-demo pow2-check` on all four soft cores.
//! Its own binary, so the `cycles` binary's layout (and with it the
//! cached cores' cycles) does not depend on the check.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use raymip_demo_firmware::{exit, println};

raymip_demo_entry::main! {
    match raymip_demo_scene::pow2_check::run() {
        Some(c) => {
            println!("{c}");
            exit(0)
        }
        None => {
            println!("error: the demo texture is invalid");
            exit(1)
        }
    }
}
