//! Code-size probe: the skeleton of `size-min`/`size-full` without any
//! raymip call (runtime, semihosting exit, panic handler and the texture
//! data); `scripts/budgets` subtracts its sections from theirs.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use core::hint::black_box as bb;
use raymip_size_probe as _;

raymip_demo_entry::main! {
    bb(&raymip_demo_scene::TEX0);
    semihosting::process::exit(bb(0))
}
