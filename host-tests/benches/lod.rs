//! ns per LOD evaluation: fixed point (the firmware path) against an f32
//! version using `libm::log2f`, table method and ray-cone method, one run.
//!
//! Run: `cargo bench -p raymip-host --bench lod`.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fixed::types::{I16F16, I32F32, U1F31, U32F32};
use raymip::lod::{cone_lod, table_lod};
use raymip::rng::XorShift64;
use raymip::units::{Accurate, Delta, Log2Pb, PathLength, Width};

const N: usize = 1024;

/// Deterministic pseudo-random inputs (xorshift), the same for both precisions.
fn inputs() -> Vec<(f32, f32, f32, f32)> {
    let mut rng = XorShift64(0x2545_F491_4F6C_DD1D);
    let mut next = || (rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
    (0..N)
        .map(|_| {
            let pl = 2f32.powf(next() * 20.0 - 8.0); // path length 2^-8 .. 2^12
            let pb = next() * 16.0 - 4.0; // log2 Pb
            let w = pl * 1.0e-3; // cone width
            let cos = 0.05 + 0.95 * next(); // |n·d|
            (pl, pb, w, cos)
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let inp = inputs();
    let fixed_in: Vec<(U32F32, Log2Pb, I32F32, I16F16, U1F31)> = inp
        .iter()
        .map(|&(pl, pb, w, cos)| {
            (
                U32F32::from_num(pl),
                Log2Pb::from_log2(I16F16::from_num(pb)),
                I32F32::from_num(w),
                I16F16::from_num(-pb - 10.0),
                U1F31::from_num(cos),
            )
        })
        .collect();

    let mut g = c.benchmark_group("lod");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("table/fixed", |b| {
        b.iter(|| {
            for &(pl, pb, ..) in black_box(&fixed_in) {
                black_box(table_lod::<Accurate>(PathLength::from_fixed(pl), pb));
            }
        })
    });
    g.bench_function("table/f32-libm", |b| {
        b.iter(|| {
            for &(pl, pb, ..) in black_box(&inp) {
                black_box(libm::log2f(pl) - pb);
            }
        })
    });
    g.bench_function("cone/fixed", |b| {
        b.iter(|| {
            for &(_, _, w, d, cos) in black_box(&fixed_in) {
                black_box(cone_lod::<Accurate>(
                    Width::from_fixed(w),
                    Delta::from_fixed(d),
                    Some(cos),
                ));
            }
        })
    });
    g.bench_function("cone/f32-libm", |b| {
        b.iter(|| {
            for &(_, pb, w, cos) in black_box(&inp) {
                let d = -pb - 10.0;
                black_box(d + libm::log2f(w.abs()) - libm::log2f(cos.clamp(1.0 / 65536.0, 1.0)));
            }
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
