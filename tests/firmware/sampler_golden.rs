//! RGBA8 wrap / clamp-to-edge results of the ACCURATE paths, bit for bit,
//! against hashes recorded from the `filter::Sampler` of commit b4ea951
//! (the static keys `Sampler::wrap` / `Sampler::clamp`, and the run-time
//! form `Sampler::with_address`): every filter mode, the batch entry
//! point, stochastic filtering, direct pyramid reads and reads through a
//! texel cache, on power-of-two and other sizes, tiny, one-wide and
//! partial chains. The inputs are `common::samples_for` over the full
//! coordinate and lod range (the generator of `texture_accuracy.rs`, own
//! seeds).
//!
//! The recorded values come from the old implementation, not from the code
//! under test: a change of any result (or fetch counter) of these
//! configurations changes a hash. To find the first differing sample,
//! check out b4ea951 and print the outputs of the same loop.

use raymip::texture::sampler::Key;
use raymip::texture::sampler::stochastic::StochasticMode;
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::mip::{Pyramid, TexelSource, full_levels};
use raymip::texture::storage::pow2::Pow2Pyramid;
use raymip::texture::{AddressMode, FetchStats, Mode, Sampler};
use raymip::units::{Lod, TexCoord};

use crate::common;
use common::{random_texture, samples_for};

/// FNV-1a, 64 bit.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn word(&mut self, x: u64) {
        for b in x.to_le_bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

const MODES: [Mode; 4] = [
    Mode::Trilinear,
    Mode::BilinearNearestLevel,
    Mode::Nearest,
    Mode::NearestTexelLinearLevel,
];

const STOCHASTIC: [StochasticMode; 3] = [
    StochasticMode::Trilinear,
    StochasticMode::Bilinear,
    StochasticMode::TrilinearBilinear,
];

/// Hash of every ACCURATE result and counter of `make()`'s sampler.
fn hash_all<S: TexelSource, K: Key<Stats = FetchStats>>(
    samples: &[(TexCoord, TexCoord, Lod)],
    mut make: impl FnMut() -> Sampler<S, K>,
) -> u64 {
    let mut h = Fnv::new();
    for mode in MODES {
        let mut s = make();
        for &(u, v, lod) in samples {
            h.word(u64::from(s.sample(u, v, lod, mode)));
        }
        h.word(s.stats().fetched);
        h.word(s.stats().skipped);
        let mut b = make();
        let mut out = vec![0; samples.len()];
        h.word(b.sample_batch(samples, mode, &mut out) as u64);
        for t in out {
            h.word(u64::from(t));
        }
        h.word(b.stats().fetched);
        h.word(b.stats().skipped);
    }
    for mode in STOCHASTIC {
        let mut s = make();
        for (i, &(u, v, lod)) in samples.iter().enumerate() {
            let bits = (i as u32).wrapping_mul(0x9E37_79B9) ^ 0x5bd1_e995;
            h.word(u64::from(s.sample_stochastic(u, v, lod, mode, bits)));
        }
        h.word(s.stats().fetched);
    }
    h.0
}

/// `(width, height, levels, hash direct wrap, direct clamp, cached wrap,
/// cached clamp)`, recorded at b4ea951.
const RECORDED: [(u32, u32, u8, [u64; 4]); 9] = [
    (
        1,
        1,
        1,
        [
            0x42e916e5d9e3ac7c,
            0x42e916e5d9e3ac7c,
            0x42e916e5d9e3ac7c,
            0x42e916e5d9e3ac7c,
        ],
    ),
    (
        1,
        9,
        4,
        [
            0xbc9cd41aeb75d349,
            0xc76b0319ccf85162,
            0xbc9cd41aeb75d349,
            0xc76b0319ccf85162,
        ],
    ),
    (
        7,
        1,
        3,
        [
            0xc5bbd4ce20b649ab,
            0x18eca39acb4be84e,
            0xc5bbd4ce20b649ab,
            0x18eca39acb4be84e,
        ],
    ),
    (
        2,
        2,
        2,
        [
            0xe3a0b3bc61eade41,
            0xca403baaa9518ed8,
            0xe3a0b3bc61eade41,
            0xca403baaa9518ed8,
        ],
    ),
    (
        13,
        7,
        4,
        [
            0x8b03b517c8d5e803,
            0x9ebdae996c45fda1,
            0x8b03b517c8d5e803,
            0x9ebdae996c45fda1,
        ],
    ),
    (
        16,
        8,
        5,
        [
            0xbd039afb61ed8db9,
            0x037f58ce5aee9e94,
            0xbd039afb61ed8db9,
            0x037f58ce5aee9e94,
        ],
    ),
    (
        32,
        32,
        6,
        [
            0x812c694efc2792ce,
            0x17db01ad11d610d5,
            0x812c694efc2792ce,
            0x17db01ad11d610d5,
        ],
    ),
    (
        64,
        16,
        3,
        [
            0x902b2c352d586cf5,
            0x4df1df42e53500a6,
            0x902b2c352d586cf5,
            0x4df1df42e53500a6,
        ],
    ),
    (
        100,
        60,
        7,
        [
            0x3b28fba17d315b8c,
            0x227708ade2b8929c,
            0x3b28fba17d315b8c,
            0x227708ade2b8929c,
        ],
    ),
];

fn hashes(w: u32, h: u32, levels: u8) -> [u64; 4] {
    let levels = levels.min(full_levels(w, h));
    let (g, buf) = random_texture(w, h, levels, u64::from(w) * 104_729 + u64::from(h)).unwrap();
    let p = Pyramid::new(g, &buf).unwrap();
    let n = if cfg!(miri) { 8 } else { 400 };
    let samples = samples_for(&g, n, u64::from(w) << 8 ^ u64::from(h) ^ 0xA5, true);
    let mut out = [0u64; 4];
    let cached = || TexelCache::<_, 4, 2>::new(p);
    out[0] = hash_all(&samples, || Sampler::wrap(p));
    out[1] = hash_all(&samples, || Sampler::clamp(p));
    out[2] = hash_all(&samples, || Sampler::wrap(cached()));
    out[3] = hash_all(&samples, || Sampler::clamp(cached()));
    // Power-of-two sides: the direct path of the level views gives the
    // same results and counters.
    if let Ok(d) = Pow2Pyramid::new(p) {
        assert_eq!(
            hash_all(&samples, || Sampler::wrap(d)),
            out[0],
            "direct wrap"
        );
        assert_eq!(
            hash_all(&samples, || Sampler::clamp(d)),
            out[1],
            "direct clamp"
        );
    }
    // The run-time forms give the same results: the address matched per
    // axis, and the key table of the C ABI.
    for (i, a) in [AddressMode::Wrap, AddressMode::ClampToEdge]
        .into_iter()
        .enumerate()
    {
        assert_eq!(
            hash_all(&samples, || Sampler::with_address(p, a)),
            out[i],
            "{a:?}"
        );
        assert_eq!(
            hash_all(&samples, || Sampler::with_address(cached(), a)),
            out[2 + i],
            "{a:?} cached"
        );
    }
    out
}

#[test]
#[cfg_attr(miri, ignore = "hashes of the full sample sets (minutes under Miri)")]
fn accurate_results_equal_the_recorded_filter_sampler() {
    let mut bad = Vec::new();
    for (w, h, levels, want) in RECORDED {
        let got = hashes(w, h, levels);
        println!("({w}, {h}, {levels}): {got:#018x?}");
        if got != want {
            bad.push((w, h));
        }
    }
    assert!(
        bad.is_empty(),
        "results differ from the recorded ones for {bad:?}"
    );
}
