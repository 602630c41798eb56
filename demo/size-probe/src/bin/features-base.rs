//! Code-size probe: the skeleton of `features` without any raymip call
//! (runtime, semihosting exit, panic handler and the texture data);
//! `scripts/features` subtracts its sections from each feature set's.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;

raymip_demo_entry::main! {
    bb(&raymip_size_probe::TEX);
    raymip_size_probe::keep_type_sizes();
    semihosting::process::exit(bb(0))
}
