//! Budgets of single per-hit calls (run by `scripts/budgets` under QEMU).
//!
//! Each measured function is a `#[no_mangle] #[inline(never)]` wrapper
//! around one library call, called [`N`] times with pseudo-random inputs the
//! optimiser cannot see (`black_box`):
//!
//! * `rm_bench_lod`: one table LOD (`log2 Pl − log2 Pb`, rounded);
//! * `rm_bench_cone_lod`: one ray-cone LOD with the normal term;
//! * `rm_bench_bilinear`: one bilinear sample at the nearest level;
//! * `rm_bench_trilinear`: one trilinear sample (two bilinear levels and the
//!   blend; the LOD always has a fractional part, so both levels are read).
//!
//! `scripts/budgets` counts the instructions executed from each wrapper's
//! entry to its return from the QEMU execution trace (`-d exec,nochain`
//! with one instruction per translation block), on both targets. On RISC-V
//! this binary also reads `minstret` around every call (exact under
//! `-icount shift=0`) and prints the call-inclusive counts minus an empty
//! call. The stack each wrapper uses is measured by stack painting.
#![no_std]
#![no_main]
#![deny(unsafe_code)]

use core::hint::black_box as bb;

use fixed::types::{I16F16, U1F31};
use raymip::filter::{Address, Mode, Sampler, TexCoord};
use raymip::lod::{Lod, cone_lod, table_lod};
use raymip::mip::{Pyramid, Texel};
use raymip::raystack::{PathLength, Width};
use raymip::table::Log2Pb;
use raymip_demo_firmware::stack;
use semihosting::{println, process};

#[cfg(target_arch = "arm")]
use cortex_m_rt::entry;
#[cfg(target_arch = "riscv32")]
use riscv_rt::entry;

/// Calls per measured function.
const N: u32 = 64;
/// Stack bytes painted per measurement.
const PAINT: usize = 2048;

type Tex = Sampler<Pyramid<'static>>;

/// One table LOD.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_lod(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    table_lod(pl, pb)
}

/// One ray-cone LOD with the normal term.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_cone_lod(w: Width, delta: I16F16, n_dot_d: Option<U1F31>) -> Lod {
    cone_lod(w, delta, n_dot_d)
}

/// One bilinear sample at the nearest level.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_bilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::BilinearNearestLevel)
}

/// One trilinear sample.
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_trilinear(s: &mut Tex, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
    s.sample(u, v, lod, Mode::Trilinear)
}

/// An empty call (baseline of the `minstret` call-inclusive counts).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_bench_empty(x: u32) -> u32 {
    x
}

/// Deterministic xorshift inputs.
struct Rng(u32);

impl Rng {
    fn next(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }
}

/// Retired-instruction counter (RISC-V `minstret`; 0 elsewhere).
#[inline(always)]
fn instret() -> u32 {
    #[cfg(target_arch = "riscv32")]
    {
        riscv::register::minstret::read() as u32
    }
    #[cfg(not(target_arch = "riscv32"))]
    {
        0
    }
}

/// min / sum / max of per-call counts.
#[derive(Clone, Copy)]
struct Stat {
    min: u32,
    sum: u32,
    max: u32,
}

impl Stat {
    const fn new() -> Self {
        Self {
            min: u32::MAX,
            sum: 0,
            max: 0,
        }
    }
    fn add(&mut self, x: u32) {
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.sum += x;
    }
}

/// Measures one wrapper: `input` draws the arguments of a call, `call`
/// makes it; returns the call-inclusive `minstret` statistics and the
/// painted stack depth.
#[inline(always)]
fn measure<I>(
    rng: &mut Rng,
    mut input: impl FnMut(&mut Rng) -> I,
    mut call: impl FnMut(I) -> u32,
) -> (Stat, usize) {
    let mut s = Stat::new();
    let top = stack::sp();
    stack::paint(top, PAINT);
    for _ in 0..N {
        let x = bb(input(rng));
        let a = instret();
        let y = call(x);
        let b = instret();
        bb(y);
        s.add(b.wrapping_sub(a));
    }
    (s, stack::used(top, PAINT))
}

/// The driver: every measured call happens here (the trace counter ends a
/// call when execution is back inside this function).
#[allow(unsafe_code)]
#[unsafe(no_mangle)]
#[inline(never)]
pub fn rm_budget_driver(tex: &mut Tex) {
    let mut rng = Rng(0x2545_F491);
    let (empty, _) = measure(&mut rng, |r| r.next(), rm_bench_empty);
    let (lod, lod_stack) = measure(
        &mut rng,
        |r| {
            // Pl over 2^-16 .. 2^16 scene units, log2 Pb over [-16, 16).
            let shift = 16 + r.next() % 32;
            let pl = PathLength::from_bits((u64::from(r.next()) << (shift - 16)) | 1);
            let pb = Log2Pb::from_log2(I16F16::from_bits((r.next() as i32) >> 11));
            (pl, pb)
        },
        |(pl, pb)| rm_bench_lod(pl, pb).map_or(0, |l| l.to_bits() as u32),
    );
    let (cone, cone_stack) = measure(
        &mut rng,
        |r| {
            let w = Width::from_bits(i64::from(r.next()) << (r.next() % 24));
            let d = I16F16::from_bits((r.next() as i32) >> 10);
            let c = Some(U1F31::from_bits(r.next() | (1 << 20)));
            (w, d, c)
        },
        |(w, d, c)| rm_bench_cone_lod(w, d, c).to_bits() as u32,
    );
    let (bil, bil_stack) = measure(
        &mut rng,
        |r| {
            let u = TexCoord::from_bits(i64::from(r.next()));
            let v = TexCoord::from_bits(i64::from(r.next()));
            let lod = Lod::from_bits((r.next() % (5 << 8)) as i16);
            (u, v, lod)
        },
        |(u, v, lod)| rm_bench_bilinear(tex, u, v, lod),
    );
    let (tri, tri_stack) = measure(
        &mut rng,
        |r| {
            let u = TexCoord::from_bits(i64::from(r.next()));
            let v = TexCoord::from_bits(i64::from(r.next()));
            // Fractional part never 0: both levels are filtered.
            let lod = Lod::from_bits((r.next() % (5 << 8)) as i16 | 1);
            (u, v, lod)
        },
        |(u, v, lod)| rm_bench_trilinear(tex, u, v, lod),
    );
    if cfg!(target_arch = "riscv32") {
        // Call-inclusive minus the empty call's count.
        let e = empty.min;
        for (name, s) in [
            ("lod", lod),
            ("cone_lod", cone),
            ("bilinear", bil),
            ("trilinear", tri),
        ] {
            println!(
                "minstret {name}: min {} mean {} max {} (minus empty call {e})",
                s.min - e,
                (s.sum - N * e) / N,
                s.max - e
            );
        }
    }
    for (name, bytes) in [
        ("lod", lod_stack),
        ("cone_lod", cone_stack),
        ("bilinear", bil_stack),
        ("trilinear", tri_stack),
    ] {
        println!("stack {name}: {bytes} bytes");
    }
}

#[entry]
fn main() -> ! {
    let Some(g) = raymip_demo_scene::tex_geometry() else {
        process::exit(1)
    };
    let Ok(p) = Pyramid::new(g, &raymip_demo_scene::TEX0) else {
        process::exit(1)
    };
    let mut tex = Sampler::new(p, Address::Wrap);
    rm_budget_driver(&mut tex);
    process::exit(0)
}
