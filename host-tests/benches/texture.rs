//! ns per bilinear and trilinear sample: firmware fixed point against the
//! f32 implementation (`raymip::baseline_f32`), one run, same pyramid and
//! inputs; then texel-cache hit rates for a scanline walk at lod 0 and 2
//! (printed).
//!
//! Run: `cargo bench -p raymip-host --bench texture`.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group};
use raymip::baseline_f32::SamplerF32;
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::mip::{Geometry, Pyramid, Texel};
use raymip::texture::{AddressMode, Mode, Sampler};
use raymip::units::{Lod, TexCoord};
use raymip_host::workload::{random_inputs, random_pyramid, to_fixed};

const N: usize = 1024;
/// Side of the texture of the timing runs: 256×256 RGBA8 plus levels
/// (≈ 350 KB) stays in the L2 cache, so the timings compare arithmetic,
/// not DRAM latency (both precisions read the same memory).
const BENCH_SIZE: u32 = 256;
/// Side of the texture of the cache walk.
const SIZE: u32 = 1024;

fn bench(c: &mut Criterion) {
    let (g, buf) = random_pyramid(BENCH_SIZE).expect("pyramid");
    let inp = random_inputs(N);
    let fixed_in = to_fixed(&inp);
    let pyramid = Pyramid::new(g, &buf).expect("pyramid");
    let mut fixed = Sampler::wrap(pyramid);
    let float = SamplerF32::new(g, &buf, AddressMode::Wrap).expect("f32 sampler");

    let mut grp = c.benchmark_group("texture");
    grp.throughput(Throughput::Elements(N as u64));
    for (name, mode) in [
        ("bilinear", Mode::BilinearNearestLevel),
        ("trilinear", Mode::Trilinear),
    ] {
        grp.bench_function(format!("{name}/fixed"), |b| {
            b.iter(|| {
                for &(u, v, l) in black_box(&fixed_in) {
                    black_box(fixed.sample(u, v, l, mode));
                }
            })
        });
        grp.bench_function(format!("{name}/f32"), |b| {
            b.iter(|| {
                for &(u, v, l) in black_box(&inp) {
                    black_box(float.sample(u, v, l, mode));
                }
            })
        });
    }
    grp.finish();
}

/// Hit rate of a 16 KiB, 4-way cache (64 sets × 4 ways of 4×4 RGBA8
/// blocks) for a row-by-row walk over a screen that shows the whole
/// texture once, one pixel per `2^lod` texels of level 0, bilinear at level
/// `level` (`level = lod`: mip-mapped; `level = 0`: mip mapping off).
fn scanline_hit_rate(g: Geometry, buf: &[Texel], lod: u32, level: u8) -> (f64, u64, u64) {
    let pyramid = Pyramid::new(g, buf).expect("pyramid");
    let cache: TexelCache<Pyramid<'_>, 64, 4> = TexelCache::new(pyramid);
    let mut s = Sampler::wrap(cache);
    let pixels = SIZE >> lod;
    let l = Lod::from_num(level);
    for y in 0..pixels {
        for x in 0..pixels {
            let u = TexCoord::from_num((f64::from(x) + 0.5) / f64::from(pixels));
            let v = TexCoord::from_num((f64::from(y) + 0.5) / f64::from(pixels));
            black_box(s.sample(u, v, l, Mode::BilinearNearestLevel));
        }
    }
    let st = s.source().stats();
    (st.hit_rate(), st.hits, st.misses)
}

fn cache_report() {
    let (g, buf) = random_pyramid(SIZE).expect("pyramid");
    println!("texel cache: 16 KiB, 64 sets x 4 ways, 4x4 RGBA8 blocks (64 B), LRU, Morton order");
    println!("scanline walk over a {SIZE}x{SIZE} texture, bilinear, one access per texel read:");
    for (lod, level, what) in [
        (0, 0, "lod 0 (level 0)"),
        (2, 2, "lod 2 (level 2, mip-mapped)"),
        (2, 0, "lod 2 minification with mip mapping off (level 0)"),
    ] {
        let (rate, hits, misses) = scanline_hit_rate(g, &buf, lod, level);
        println!(
            "  {what:<52} hit rate {:6.2} %  ({hits} hits, {misses} misses)",
            100.0 * rate
        );
    }
}

criterion_group!(benches, bench);

fn main() {
    cache_report();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
