//! Cross-core check of the power-of-two pyramid: random trilinear and
//! bilinear samples of [`crate::tex0_pow2`] (direct level views; with
//! raymip's feature `cfu` the co-processor's texture unit samples them)
//! against the same texture as a plain `Pyramid` (read texel by texel: no
//! unit), wrap and mirror/clamp-to-edge, lods from below level 0 to above
//! the last level. The firmware binary `check-pow2` prints the line on the
//! four soft cores, `raymip-demo pow2-check` on the host;
//! `scripts/softcore` requires every core's line to equal the host's.
//!
//! Two figures in the line: the mismatches between the two pyramids on the
//! core itself, and an FNV-1a hash of the power-of-two pyramid's samples.
//! With feature `cfu` the plain pyramid's samples use the co-processor's
//! filter instructions too, so a filter error shows in the hash (against
//! the host's software samples), not in the mismatches.

use core::fmt;

use raymip::rng::XorShift32;
use raymip::texture::address::{ClampToEdge, Mirror, Wrap};
use raymip::texture::kernel::Linear;
use raymip::texture::storage::mip::{Pyramid, Texel};
use raymip::texture::storage::pow2::Pow2Pyramid;
use raymip::texture::{Cfg, Mode, NoStats, Sampler};
use raymip::units::{Accurate, Lod, TexCoord};

use crate::Fnv1a;

/// Random inputs per address-mode pair and filter mode (four of each:
/// wrap and mirror/clamp-to-edge, trilinear and bilinear).
pub const SAMPLES: u32 = 128;

/// Seed of the inputs' generator.
const SEED: u32 = 0x7E57_C0DE;

/// The outcome of [`run`]; its `Display` is the line the host and the
/// cores print.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Samples drawn (of each pyramid).
    pub n: u32,
    /// Samples where the two pyramids differ.
    pub mismatches: u32,
    /// FNV-1a of the power-of-two pyramid's samples (RGBA bytes in order).
    pub hash: u32,
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "check pow2: n {} mismatches {} hash {:#010x}",
            self.n, self.mismatches, self.hash
        )
    }
}

/// One sample: `u`, `v`, lod, mode.
type Sample<'a> = &'a mut dyn FnMut(TexCoord, TexCoord, Lod, Mode) -> Texel;

/// Samples where `a` and `b` differ over [`SAMPLES`] random inputs per
/// filter mode (any `u`, `v`; lods from −2 to 10: the pyramid has
/// [`crate::TEX_LEVELS`] levels); `a`'s samples go into `hash`.
fn mismatches(rng: &mut XorShift32, hash: &mut Fnv1a, a: Sample<'_>, b: Sample<'_>) -> u32 {
    let mut bad = 0;
    for mode in [Mode::Trilinear, Mode::BilinearNearestLevel] {
        for _ in 0..SAMPLES {
            let u = TexCoord::from_bits(i64::from(rng.next_u32() as i32));
            let v = TexCoord::from_bits(i64::from(rng.next_u32() as i32));
            let lod = Lod::from_bits((rng.next_u32() % (12 << 8)) as i16 - (2 << 8));
            let t = a(u, v, lod, mode);
            bad += u32::from(t != b(u, v, lod, mode));
            hash.write(&t.to_le_bytes());
        }
    }
    bad
}

/// Runs the check; `None` if the demo texture is invalid.
#[must_use]
pub fn run() -> Option<Outcome> {
    let (g, p) = crate::tex0_pow2()?;
    let plain = Pyramid::new(g, &crate::TEX0).ok()?;
    let mut rng = XorShift32(SEED);
    let mut hash = Fnv1a::default();
    type Ww<S> = Sampler<S, Cfg<Wrap, Wrap, Linear, Accurate, NoStats>>;
    type Mc<S> = Sampler<S, Cfg<Mirror, ClampToEdge, Linear, Accurate, NoStats>>;
    let mut pow2_ww: Ww<Pow2Pyramid<'static>> = Sampler::new(p);
    let mut plain_ww: Ww<Pyramid<'static>> = Sampler::new(plain);
    let mut pow2_mc: Mc<Pow2Pyramid<'static>> = Sampler::new(p);
    let mut plain_mc: Mc<Pyramid<'static>> = Sampler::new(plain);
    let bad = mismatches(
        &mut rng,
        &mut hash,
        &mut |u, v, l, m| pow2_ww.sample(u, v, l, m),
        &mut |u, v, l, m| plain_ww.sample(u, v, l, m),
    ) + mismatches(
        &mut rng,
        &mut hash,
        &mut |u, v, l, m| pow2_mc.sample(u, v, l, m),
        &mut |u, v, l, m| plain_mc.sample(u, v, l, m),
    );
    Some(Outcome {
        n: 4 * SAMPLES,
        mismatches: bad,
        hash: hash.finish(),
    })
}
