//! Level of detail per ray hit.
//!
//! * Table method (Park et al. 2011): `lod = log2 Pl − log2 Pb`, one
//!   logarithm and one subtraction: [`table_lod`].
//! * Ray cones (Akenine-Möller et al., RTG ch. 20):
//!   `λ = Δ + log2|w| − log2|n·d|`: [`cone_lod`]. With zero surface spread
//!   (`β = 0`) a primary cone has `w = γ·Pl`, so `λ = Δ + log2 γ + log2 Pl`
//!   `= log2 Pl − log2 Pb`: without the normal term both methods agree (a
//!   tested identity, within 1/256 level).
//!
//! Results are [`Lod`] (I8F8, rounded to nearest 1/256 level, saturating at
//! ±128). [`clamp_lod`] limits a value to a texture's stored levels.
//!
//! # Error bound
//!
//! A table lod is within [`LOD_MAX_ERROR`] `= 2⁻⁸` level of the exact
//! `log2(Pl/Pb)` for `Pl ∈ [2⁻¹⁶, 2¹⁶]` scene units, also after ten
//! accumulated bounces (log2 error ≤ 2⁻¹³, entry error ≤ 2⁻¹⁰, output
//! rounding ≤ 2⁻⁹). It is monotonic non-decreasing in `Pl`.
//!
//! # Precision tiers
//!
//! Every method takes its tier as a type parameter ([`Tier`]):
//! `table_lod::<Accurate>(pl, pb)`, `cone_lod::<Fast>(w, Δ, n·d)`.
//!
//! | tier | calls | log2 | error bound |
//! |---|---|---|---|
//! | [`Accurate`] (bit-identical on every target) | [`table_lod`], [`cone_lod`], [`table_lod_batch`], [`cone_lod_batch`] | 64-entry table, linear interpolation, ≤ 2⁻¹³ | ≤ 2⁻⁸ level |
//! | [`Fast`] (fewer instructions per hit; identical on every target, may differ from ACCURATE by 1/256 level) | the same calls, and from the ray stack's normalised `Pl` [`table_lod_norm`], [`table_lod_norm_batch`] (no leading-zero count, one [`LodWord`] per hit) | 1024-entry table, no interpolation ([`log2::fast`](crate::log2::fast)), ≤ 2⁻¹⁰ | ≤ 2⁻⁸ level |
//!
//! Both meet the same documented bound [`LOD_MAX_ERROR`]; the FAST tier
//! spends its margin (`2⁻¹⁰ + 2⁻¹⁰ + 2⁻⁹ = 2⁻⁸` with the entry error).
//! Instruction counts per target are in `BUDGETS.md`.
//!
//! # Grazing angles
//!
//! `−log2|n·d|` grows without bound as `n·d → 0`; `|n·d|` is clamped to
//! `[MIN_COS = 2⁻¹⁶, 1]`, so the normal term lies in `[0, 16]` levels.
//!
//! # Submodules
//!
//! * `raydiff` (feature `raydiff`): the texture-space footprint of a hit
//!   from its ray differentials, and its lod.
//! * `envmap` (feature `envmap`): the lods of rays that leave the scene on
//!   a latitude-longitude environment map, and the direction → `(u, v)`
//!   mapping.

#[cfg(feature = "envmap")]
pub mod envmap;
#[cfg(feature = "raydiff")]
pub mod raydiff;

#[cfg(feature = "cone")]
use fixed::types::U1F31;

#[cfg(feature = "cone")]
use crate::log2::LOD_BIAS;
#[cfg(feature = "cone")]
use crate::log2::fast::log2_u1f31_fast_biased;
use crate::log2::fast::{NormPl, log2_u32f32_fast_parts};
#[cfg(all(feature = "cone", not(all(feature = "pcpi", target_arch = "riscv32"))))]
use crate::log2::log2_u1f31_biased;
use crate::log2::log2_u32f32_parts;
#[cfg(feature = "cone")]
use crate::units::Delta;
#[cfg(feature = "cone")]
use crate::units::MIN_COS;
#[cfg(feature = "cone")]
use crate::units::Width;
#[cfg(doc)]
use crate::units::{Accurate, Fast};
use crate::units::{Lod, Log2Pb, PathLength, Precision, Tier};

/// Documented error bound of [`table_lod`] and [`cone_lod`] against f64, in
/// levels: 2⁻⁸.
pub const LOD_MAX_ERROR: f64 = 1.0 / 256.0;

/// Table method: `lod = log2 Pl − log2 Pb` for the accumulated path length
/// `pl` (scene units) and the hit triangle's table entry, in tier `T`.
/// `None` for an untextured triangle (nothing to fetch). `Pl = 0` is read
/// as 2⁻³².
///
/// | tier | log2 | error against f64 |
/// |---|---|---|
/// | [`Accurate`] | 64-entry table, interpolated ([`log2`](crate::log2)) | ≤ [`LOD_MAX_ERROR`] `= 2⁻⁸` level |
/// | [`Fast`] | 1024-entry table, no interpolation ([`log2::fast`](crate::log2::fast)) | ≤ [`LOD_MAX_ERROR`] (log2 ≤ 2⁻¹⁰, entry ≤ 2⁻¹⁰, output rounding ≤ 2⁻⁹); may differ from [`Accurate`] by one step (1/256 level) |
///
/// Both are monotonic non-decreasing in `Pl` and identical on every
/// target. No saturation is needed: `log2 Pl ∈ [−32, 32)` and every entry
/// lies in `[−95, 95]`, so the difference lies in `(−127, 127)`, inside
/// [`Lod`].
#[inline]
#[must_use]
pub fn table_lod<T: Tier>(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    match T::PRECISION {
        Precision::Accurate => accurate_table_lod(pl, pb),
        Precision::Fast => fast_table_lod(pl, pb),
    }
}

/// [`table_lod`] in [`Accurate`].
#[inline(always)]
fn accurate_table_lod(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    // Feature `pcpi` on riscv32: `tex.log2pl` and `tex.lod`, the same bits
    // (the untextured marker comes back as `pcpi::UNTEXTURED`).
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    {
        use crate::coproc::pcpi;
        let r = pcpi::lod(pcpi::log2pl(pl.to_bits()), pb.to_bits());
        if r == pcpi::UNTEXTURED {
            None
        } else {
            Some(Lod::from_bits(r as i16))
        }
    }
    #[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
    table_lod_soft(pl, pb)
}

/// The software [`table_lod`] in [`Accurate`] (every target; without
/// feature `pcpi` the only one).
#[cfg_attr(all(feature = "pcpi", target_arch = "riscv32"), allow(dead_code))]
#[inline(always)]
fn table_lod_soft(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    if pb.is_untextured() {
        return None;
    }
    // log2 Pl + 0x80 = biased − (lz << 16) in I16F16 bits (the I8F8
    // rounding offset is folded into the log2 table).
    let (lz, biased) = log2_u32f32_parts(pl.to_bits());
    let d = biased as i32 - (((lz as i32) << 16) + pb.to_i16f16().to_bits());
    Some(Lod::from_bits((d >> 8) as i16))
}

/// Ray-cone method: `λ = Δ + log2|w| − log2|n·d|` for cone width `width`
/// (scene units), triangle constant `delta` (`Δ`, from
/// `Log2Pb::delta`) and, optionally, `|n·d|` (clamped to
/// `[MIN_COS, 1]`), in tier `T`. `w = 0` is read as 2⁻³². Saturates at the
/// [`Lod`] range. Feature `cone`.
///
/// | tier | log2 | error against f64 of the same inputs |
/// |---|---|---|
/// | [`Accurate`] | 64-entry table, interpolated ([`log2`](crate::log2)) | ≤ [`LOD_MAX_ERROR`] `= 2⁻⁸` level |
/// | [`Fast`] | both logarithms from the 1024-entry table, no interpolation ([`log2::fast`](crate::log2::fast)) | ≤ [`LOD_MAX_ERROR`] (two log2 ≤ 2⁻¹⁰ each, output rounding ≤ 2⁻⁹); may differ from [`Accurate`] by one step |
#[cfg(feature = "cone")]
#[inline]
#[must_use]
pub fn cone_lod<T: Tier>(width: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod {
    match T::PRECISION {
        Precision::Accurate => accurate_cone_lod(width, delta, n_dot_d),
        Precision::Fast => fast_cone_lod(width, delta, n_dot_d),
    }
}

/// [`cone_lod`] in [`Accurate`].
#[cfg(feature = "cone")]
#[inline(always)]
fn accurate_cone_lod(width: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod {
    // Every term in I16F16 bits: log2|w| ∈ [−32, 32) levels, the normal
    // term ∈ [0, 16]. With Δ clamped to ±2^30 bits (±16384 levels) nothing
    // overflows i32, and the result equals the saturating sum: once |Δ|
    // exceeds 2^30 bits the sum lies beyond ±2^29 bits either way, far past
    // the ±2^23 bits that `Lod` holds, so both saturate to the same end.
    let delta = delta.to_bits().clamp(-(1 << 30), 1 << 30);
    // Feature `pcpi` on riscv32: both logarithms from `tex.log2pl`, the
    // same bits: log2|w| + 0x80 directly, and for `c` (U1F31, read as the
    // U32F32 value `c · 2⁻³²`, which has the same mantissa and 32 more
    // leading zeros) `log2_u1f31_biased(c) − LOD_BIAS = tex.log2pl(c) +
    // (1 << 16) − 0x80`.
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    let l = {
        use crate::coproc::pcpi::log2pl;
        let mut l = delta + log2pl(width.to_bits().unsigned_abs());
        if let Some(c) = n_dot_d {
            let c = c.to_bits().clamp(MIN_COS.to_bits(), 1 << 31);
            l -= log2pl(u64::from(c)) + (1 << 16) - 0x80;
        }
        l
    };
    #[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
    let l = {
        let (lz, biased) = log2_u32f32_parts(width.to_bits().unsigned_abs());
        // log2|w| + 0x80 (the I8F8 rounding offset) + Δ.
        let mut l = delta + (biased as i32 - ((lz as i32) << 16));
        if let Some(c) = n_dot_d {
            let c = c.to_bits().clamp(MIN_COS.to_bits(), 1 << 31);
            // Both terms carry LOD_BIAS: it cancels.
            l -= log2_u1f31_biased(c) - LOD_BIAS as i32;
        }
        l
    };
    Lod::from_bits((l >> 8).clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16)
}

/// The loop of every batch entry point: `out[i] = f(hits[i])` for
/// `i < n = min(hits.len(), out.len())`; returns `n`. Never panics.
#[inline(always)]
fn batch<I: Copy, O>(hits: &[I], out: &mut [O], f: impl Fn(I) -> O) -> usize {
    let n = hits.len().min(out.len());
    for (o, &h) in out.iter_mut().zip(hits) {
        *o = f(h);
    }
    n
}

/// Batch of [`table_lod`] in tier `T`: `out[i] = table_lod::<T>(hits[i].0,
/// hits[i].1)` for `i < n = min(hits.len(), out.len())`, in caller memory;
/// returns `n` (results past `n` are left untouched). Same results as the
/// per-hit call, bit for bit; never panics. The FAST batch from the ray
/// stack's normalised path lengths is [`table_lod_norm_batch`].
#[inline]
pub fn table_lod_batch<T: Tier>(hits: &[(PathLength, Log2Pb)], out: &mut [Option<Lod>]) -> usize {
    batch(hits, out, |(pl, pb)| table_lod::<T>(pl, pb))
}

/// Batch of [`cone_lod`] in tier `T`: `out[i] = cone_lod::<T>(w, Δ, n·d)`
/// of `hits[i]` for `i < n = min(hits.len(), out.len())`, in caller
/// memory; returns `n`. Same results as the per-hit call, bit for bit;
/// never panics. Feature `cone`.
#[cfg(feature = "cone")]
#[inline]
pub fn cone_lod_batch<T: Tier>(hits: &[(Width, Delta, Option<U1F31>)], out: &mut [Lod]) -> usize {
    batch(hits, out, |(w, d, c)| cone_lod::<T>(w, d, c))
}

/// [`table_lod`] in [`Fast`].
#[inline(always)]
fn fast_table_lod(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
    if pb.is_untextured() {
        return None;
    }
    let (lz, biased) = log2_u32f32_fast_parts(pl.to_bits());
    // `(x − (lz << 16)) >> 8 = (x >> 8) − (lz << 8)`: the low byte of
    // `lz << 16` is zero.
    let d = ((biased as i32 - pb.to_i16f16().to_bits()) >> 8) - ((lz as i32) << 8);
    Some(Lod::from_bits(d as i16))
}

/// [`cone_lod`] in [`Fast`].
#[cfg(feature = "cone")]
#[inline(always)]
fn fast_cone_lod(width: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod {
    // Overflow-free for the reasons given in `accurate_cone_lod`; the upper end
    // `2³⁰ − 1` (a power-of-two range) is one `ssat` on the Cortex-M4.
    let delta = delta.to_bits().clamp(-(1 << 30), (1 << 30) - 1);
    let (lz, biased) = log2_u32f32_fast_parts(width.to_bits().unsigned_abs());
    let mut l = delta + (biased as i32 - ((lz as i32) << 16));
    if let Some(c) = n_dot_d {
        let c = c.to_bits().clamp(MIN_COS.to_bits(), 1 << 31);
        l -= log2_u1f31_fast_biased(c) - LOD_BIAS as i32;
    }
    Lod::from_bits((l >> 8).clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16)
}

/// A FAST table lod or "untextured" in one 32-bit word, the element
/// [`table_lod_norm_batch`] writes: a textured hit's [`Lod`] bits
/// sign-extended (a word in `[−2¹⁵, 2¹⁵)`; the batch's lie in
/// `[−32512, 32512]`, ±127 levels), an untextured hit any word outside
/// `[−2¹⁵, 2¹⁵)`, the niche that takes the place of `Option`'s tag, so a
/// batch stores one word per hit and needs no branch. [`LodWord::get`]
/// reads it as `Option<Lod>`.
///
/// The batch reaches the niche arithmetically: `log2 Pl + 2⁻⁹` lies in
/// `[−32, 32 + 2⁻⁹]` ([`NormPl`]) and a textured `log2 Pb` in `[−95, 95]`,
/// so their I16F16 difference lies within ±2²³; the untextured marker
/// [`Log2Pb::UNTEXTURED`] is `−2³¹` (I16F16 bits), and the wrapping
/// difference with it flips bit 31, which puts the word (the difference
/// `>> 8`) within 2¹³ of ±2²³. [`LodWord::UNTEXTURED`] is the canonical
/// untextured word; equality compares [`LodWord::get`], not the bits.
///
/// # Example
/// ```
/// use raymip::lod::{LodWord, table_lod_norm_batch, table_lod_norm};
/// use raymip::log2::fast::NormPl;
/// use raymip::{Lod, Log2Pb, PathLength};
/// let key = NormPl::new(PathLength::from_num(12));
/// let hits = [(key, Log2Pb::from_bits(0)), (key, Log2Pb::UNTEXTURED)];
/// let mut out = [LodWord::UNTEXTURED; 2];
/// assert_eq!(table_lod_norm_batch(&hits, &mut out), 2);
/// assert_eq!(out[0].get(), table_lod_norm(key, Log2Pb::from_bits(0)));
/// assert!(out[0].get().is_some_and(|l| l > Lod::from_num(3.5)));
/// assert_eq!(out[1].get(), None);
/// assert_eq!(out[1], LodWord::UNTEXTURED);
/// assert_eq!(LodWord::from(Some(Lod::ONE)).0, 256);
/// ```
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct LodWord(
    /// The raw word: [`Lod`] bits in `[−2¹⁵, 2¹⁵)`, else untextured (every
    /// value is a valid word).
    pub i32,
);

impl LodWord {
    /// The canonical untextured word, `i32::MIN` (any word outside
    /// `[−2¹⁵, 2¹⁵)` reads as untextured).
    pub const UNTEXTURED: Self = Self(i32::MIN);

    /// The lod, or `None` for an untextured hit (a word outside
    /// `[−2¹⁵, 2¹⁵)`). Never panics.
    #[inline]
    #[must_use]
    pub const fn get(self) -> Option<Lod> {
        let lod = self.0 as i16;
        if lod as i32 == self.0 {
            Some(Lod::from_bits(lod))
        } else {
            None
        }
    }
}

/// [`LodWord::UNTEXTURED`], as `Option`'s default is `None`.
impl Default for LodWord {
    fn default() -> Self {
        Self::UNTEXTURED
    }
}

/// Equal when [`LodWord::get`] is: every untextured word equals every other.
impl PartialEq for LodWord {
    fn eq(&self, other: &Self) -> bool {
        self.get() == other.get()
    }
}

impl Eq for LodWord {}

/// `Some(lod)` → the lod's bits, `None` → [`LodWord::UNTEXTURED`].
impl From<Option<Lod>> for LodWord {
    fn from(lod: Option<Lod>) -> Self {
        lod.map_or(Self::UNTEXTURED, |l| Self(i32::from(l.to_bits())))
    }
}

/// [`LodWord::get`].
impl From<LodWord> for Option<Lod> {
    fn from(w: LodWord) -> Self {
        w.get()
    }
}

/// The FAST table lod from a normalised path length as a [`LodWord`],
/// branch-free (the one home of the arithmetic of [`table_lod_norm`] and
/// [`table_lod_norm_batch`]): `(log2 Pl + 2⁻⁹ − log2 Pb) >> 8` in I16F16
/// bits, wrapping, so the untextured marker lands in the niche (see
/// [`LodWord`]).
#[inline(always)]
fn table_lod_norm_word(pl: NormPl, pb: Log2Pb) -> LodWord {
    LodWord(pl.log2_rounding_bits().wrapping_sub(pb.to_bits()) >> 8)
}

/// FAST table method from a normalised path length ([`NormPl`], kept in
/// every ray-stack entry as [`crate::path::raystack::PathState::pl_norm`]): no
/// leading-zero count, one table read and two additions. Bit-identical to
/// [`table_lod::<Fast>`](table_lod) of the path length the key was made from (tested for
/// every table index and octave), so within [`LOD_MAX_ERROR`] `= 2⁻⁸`
/// level of f64 and monotonic in `Pl`. `None` for an untextured triangle.
/// Never panics (every key is valid, see [`NormPl`]).
#[inline]
#[must_use]
pub fn table_lod_norm(pl: NormPl, pb: Log2Pb) -> Option<Lod> {
    table_lod_norm_word(pl, pb).get()
}

/// Batch of the FAST table method (error ≤ [`LOD_MAX_ERROR`]) from
/// normalised path lengths, one word per hit: `out[i]` is
/// `table_lod_norm(hits[i].0, hits[i].1)` as a [`LodWord`] (read it with
/// [`LodWord::get`]; equal to [`table_lod::<Fast>`](table_lod) of the path lengths the
/// keys were made from) for `i < n = min(hits.len(), out.len())`, in
/// caller memory; returns `n` (words past `n` are left untouched). Same
/// results as the per-hit call, bit for bit; branch-free per hit (an
/// untextured entry gives a word in the niche); never panics. The keys come
/// from the ray stack ([`crate::path::raystack::PathState::pl_norm`]) or
/// [`NormPl::new`].
#[inline]
pub fn table_lod_norm_batch(hits: &[(NormPl, Log2Pb)], out: &mut [LodWord]) -> usize {
    batch(hits, out, |(pl, pb)| table_lod_norm_word(pl, pb))
}

/// Clamps `lod` to the stored levels `[0, levels − 1]` of a texture
/// (`levels = 0` is treated as 1). [`Lod`] cannot exceed 127 + 255/256, so
/// `levels > 128` behaves as 128 (top level 127). Never panics.
#[inline]
#[must_use]
pub fn clamp_lod(lod: Lod, levels: u8) -> Lod {
    // levels − 1 ≤ 127 keeps the shift inside i16 (127 << 8 = 32512).
    let top = Lod::from_bits(i16::from(levels.saturating_sub(1).min(127)) << 8);
    lod.max(Lod::ZERO).min(top)
}

/// Convenience: a table lod in tier `T` clamped to a texture's stored
/// levels.
#[inline]
#[must_use]
pub fn table_lod_clamped<T: Tier>(pl: PathLength, pb: Log2Pb, levels: u8) -> Option<Lod> {
    table_lod::<T>(pl, pb).map(|l| clamp_lod(l, levels))
}

#[cfg(test)]
mod tests {
    use crate::units::{Accurate, Coord, Fast, Spread, TexCoord};
    extern crate std;
    use super::*;
    use crate::path::raystack::PathState;
    use crate::setup::camera::PixelSpread;
    use crate::setup::table::TexTriangle;

    use fixed::types::I16F16;
    #[cfg(feature = "cone")]
    use fixed::types::U1F31;
    use proptest::prelude::*;

    fn q(x: f64) -> f64 {
        Coord::from_num(x).to_num()
    }

    fn make(p: [[f64; 3]; 3], uv: [[f64; 2]; 3], w: u32, h: u32) -> TexTriangle {
        TexTriangle::new(
            p.map(|v| v.map(Coord::from_num)),
            uv.map(|v| v.map(TexCoord::from_num)),
            w,
            h,
        )
        .unwrap()
    }

    /// A fronto-parallel square of side `s` (two triangles; one is enough)
    /// mapped to the whole `w × h` texture, seen by a camera with vertical
    /// field of view `fov` and image height `hgt`.
    #[test]
    fn fronto_parallel_one_texel_per_pixel_is_lod_zero() {
        for &(s, w, fov_deg, hgt) in &[
            (1.0f64, 256u32, 60.0f64, 480u32),
            (0.01, 1024, 40.0, 600),
            (250.0, 64, 90.0, 1080),
            (3.7, 512, 36.87, 600),
        ] {
            let fov = fov_deg.to_radians();
            let spread = PixelSpread::from_fov_y(fov, hgt).unwrap();
            let tri = make(
                [[0.0, 0.0, 0.0], [s, 0.0, 0.0], [0.0, s, 0.0]],
                [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
                w,
                w,
            );
            let pb = Log2Pb::compute(&tri, &spread);
            // On the axis a pixel at distance d is d·2·tan(fov/2)/H wide; one
            // texel is s/w wide: they are equal at
            let d = (s / f64::from(w)) * f64::from(hgt) / (2.0 * (fov / 2.0).tan());
            for (mult, want) in [(1.0, 0.0), (2.0, 1.0), (4.0, 2.0), (0.5, -1.0)] {
                let lod = table_lod::<Accurate>(PathLength::from_num(d * mult), pb).unwrap();
                let err = (lod.to_num::<f64>() - want).abs();
                assert!(
                    err <= LOD_MAX_ERROR,
                    "side {s}, {w} texels, fov {fov_deg}, H {hgt}: lod at {mult}·d = {lod}, want {want}"
                );
                // The same through a primary ray cone.
                #[cfg(feature = "cone")]
                let st = PathState::primary(&spread, 0).advance(PathLength::from_num(d * mult));
                #[cfg(feature = "cone")]
                {
                    let c = cone_lod::<Accurate>(st.cone.width, pb.delta(&spread).unwrap(), None);
                    assert!(
                        (c.to_num::<f64>() - want).abs() <= LOD_MAX_ERROR,
                        "cone {c} want {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn untextured_zero_and_degenerate() {
        assert_eq!(
            table_lod::<Accurate>(PathLength::from_num(3), Log2Pb::UNTEXTURED),
            None
        );
        let pb = Log2Pb::from_log2(I16F16::from_num(2));
        assert_eq!(
            table_lod::<Accurate>(PathLength::ZERO, pb),
            Some(Lod::from_num(-34))
        );
        // Degenerate markers: every Pl gives lod ≥ 63 (coarsest) or ≤ −63 (level 0).
        for pl in [
            PathLength::ZERO,
            PathLength::DELTA,
            PathLength::from_num(1),
            PathLength::MAX,
        ] {
            assert!(
                table_lod::<Accurate>(pl, Log2Pb::DEGENERATE_GEOMETRY).unwrap()
                    >= Lod::from_num(63)
            );
            assert!(
                table_lod::<Accurate>(pl, Log2Pb::DEGENERATE_UV).unwrap() <= Lod::from_num(-63)
            );
        }
        #[cfg(feature = "cone")]
        assert_eq!(
            cone_lod::<Accurate>(Width::ZERO, Delta::from_num(3), None),
            Lod::from_num(-29)
        );
        assert_eq!(clamp_lod(Lod::MIN, 5), Lod::ZERO);
        assert_eq!(clamp_lod(Lod::MAX, 5), Lod::from_num(4));
        assert_eq!(clamp_lod(Lod::MAX, 0), Lod::ZERO);
        assert_eq!(clamp_lod(Lod::from_num(2.5), 5), Lod::from_num(2.5));
        // Level counts past what Lod can name: top level 127, no panic.
        assert_eq!(clamp_lod(Lod::MAX, 129), Lod::from_num(127));
        assert_eq!(clamp_lod(Lod::MAX, 255), Lod::from_num(127));
        assert_eq!(clamp_lod(Lod::from_num(3.25), 255), Lod::from_num(3.25));
        assert_eq!(clamp_lod(Lod::MIN, 255), Lod::ZERO);
        assert_eq!(
            table_lod_clamped::<Accurate>(PathLength::MAX, Log2Pb::DEGENERATE_GEOMETRY, 11),
            Some(Lod::from_num(10))
        );
        assert_eq!(
            table_lod_clamped::<Accurate>(PathLength::ZERO, Log2Pb::DEGENERATE_UV, 11),
            Some(Lod::ZERO)
        );
    }

    /// FAST paths at the extremes: untextured, zero, the largest `Pl`,
    /// the degenerate markers, grazing and saturated cones.
    #[test]
    fn fast_paths_at_the_extremes() {
        let pb = Log2Pb::from_log2(I16F16::from_num(2));
        assert_eq!(
            table_lod::<Fast>(PathLength::from_num(3), Log2Pb::UNTEXTURED),
            None
        );
        assert_eq!(
            table_lod::<Fast>(PathLength::ZERO, pb),
            Some(Lod::from_num(-34))
        );
        assert_eq!(
            table_lod::<Fast>(PathLength::DELTA, pb),
            Some(Lod::from_num(-34))
        );
        assert_eq!(
            table_lod::<Fast>(PathLength::MAX, pb),
            Some(Lod::from_num(30))
        );
        assert_eq!(
            table_lod::<Fast>(PathLength::from_num(4), pb),
            Some(Lod::ZERO)
        );
        assert_eq!(
            table_lod_norm(NormPl::new(PathLength::from_num(3)), Log2Pb::UNTEXTURED),
            None
        );
        assert_eq!(table_lod_norm(NormPl::ZERO, pb), Some(Lod::from_num(-34)));
        // Raw key words are clamped to valid keys (exponent in [−32, 31]),
        // so even the extreme words give a lod in [−127, −63] here.
        for bits in [i32::MIN, -1, 0, 1023, 0xFC00, i32::MAX] {
            let l = table_lod_norm(NormPl::from_bits(bits), Log2Pb::DEGENERATE_UV).unwrap();
            assert!(
                (Lod::from_num(-127)..=Lod::from_num(-63)).contains(&l),
                "{bits:#x}: {l}"
            );
        }
        for pl in [PathLength::ZERO, PathLength::from_num(1), PathLength::MAX] {
            for m in [
                Log2Pb::DEGENERATE_GEOMETRY,
                Log2Pb::DEGENERATE_UV,
                Log2Pb::MIN,
                Log2Pb::MAX,
                pb,
            ] {
                assert_eq!(table_lod_norm(NormPl::new(pl), m), table_lod::<Fast>(pl, m));
            }
            assert!(
                table_lod::<Fast>(pl, Log2Pb::DEGENERATE_GEOMETRY).unwrap() >= Lod::from_num(63)
            );
            assert!(table_lod::<Fast>(pl, Log2Pb::DEGENERATE_UV).unwrap() <= Lod::from_num(-63));
            assert!(table_lod::<Fast>(pl, Log2Pb::MIN).is_some());
        }
        #[cfg(feature = "cone")]
        {
            let (w, d) = (Width::from_num(1), Delta::ZERO);
            assert_eq!(cone_lod::<Fast>(w, d, Some(U1F31::from_num(1))), Lod::ZERO);
            assert_eq!(
                cone_lod::<Fast>(w, d, Some(U1F31::from_num(0.5))),
                Lod::from_num(1)
            );
            assert_eq!(cone_lod::<Fast>(w, d, Some(U1F31::ZERO)), Lod::from_num(16));
            assert_eq!(cone_lod::<Fast>(w, d, Some(U1F31::MAX)), Lod::ZERO);
            assert_eq!(
                cone_lod::<Fast>(-Width::from_num(4), d, None),
                Lod::from_num(2)
            );
            assert_eq!(
                cone_lod::<Fast>(Width::ZERO, Delta::from_num(3), None),
                Lod::from_num(-29)
            );
            assert_eq!(cone_lod::<Fast>(Width::MAX, Delta::MAX, None), Lod::MAX);
            assert_eq!(
                cone_lod::<Fast>(Width::MIN, Delta::MIN, Some(U1F31::MAX)),
                Lod::MIN
            );
            assert_eq!(
                cone_lod::<Fast>(Width::ZERO, Delta::MIN, Some(U1F31::ZERO)),
                Lod::MIN
            );
        }
    }

    #[test]
    fn lod_word_niche() {
        // The Lod range reads back, every word outside it is untextured.
        assert_eq!(LodWord(0).get(), Some(Lod::ZERO));
        assert_eq!(LodWord(-1).get(), Some(-Lod::DELTA));
        assert_eq!(LodWord(32767).get(), Some(Lod::MAX));
        assert_eq!(LodWord(-32768).get(), Some(Lod::MIN));
        for bits in [32768, -32769, 1 << 23, -(1 << 23), i32::MIN, i32::MAX] {
            assert_eq!(LodWord(bits).get(), None, "{bits:#x}");
            assert_eq!(LodWord(bits), LodWord::UNTEXTURED);
        }
        assert_eq!(LodWord::UNTEXTURED.0, i32::MIN);
        assert_eq!(LodWord::default(), LodWord::UNTEXTURED);
        assert_eq!(LodWord::from(Some(Lod::from_num(-2.5))).0, -640);
        assert_eq!(LodWord::from(None), LodWord::UNTEXTURED);
        assert_ne!(LodWord(1), LodWord::UNTEXTURED);
        assert_ne!(LodWord(1), LodWord(2));
        for l in [Lod::MIN, -Lod::DELTA, Lod::ZERO, Lod::MAX] {
            assert_eq!(Option::<Lod>::from(LodWord::from(Some(l))), Some(l));
        }
        // The untextured marker lands in the niche for the extreme keys:
        // `log2 Pl + 2⁻⁹` of about −32 and 32 (the wrap goes either way).
        let max_key = NormPl::from_bits((31 << 16) | 1023);
        assert_eq!(NormPl::from_bits(i32::MAX), max_key);
        for key in [NormPl::ZERO, NormPl::new(PathLength::ONE), max_key] {
            let mut w = [LodWord(0); 2];
            table_lod_norm_batch(&[(key, Log2Pb::UNTEXTURED), (key, Log2Pb::MAX)], &mut w);
            assert_eq!(w[0].get(), None, "{key:?}: {:#x}", w[0].0);
            assert!(w[1].get().is_some());
        }
        // The ends of the textured range: ±127 levels (±32512 bits).
        let mut w = [LodWord::UNTEXTURED; 2];
        table_lod_norm_batch(
            &[
                (max_key, Log2Pb::DEGENERATE_GEOMETRY),
                (NormPl::ZERO, Log2Pb::DEGENERATE_UV),
            ],
            &mut w,
        );
        assert_eq!(w.map(|w| w.0), [32512, -32512]);
    }

    #[test]
    #[cfg(feature = "cone")]
    fn normal_term_and_grazing_clamp() {
        let w = Width::from_num(1);
        let d = Delta::ZERO;
        assert_eq!(
            cone_lod::<Accurate>(w, d, Some(U1F31::from_num(1))),
            Lod::ZERO
        );
        let half = cone_lod::<Accurate>(w, d, Some(U1F31::from_num(0.5)));
        assert_eq!(half, Lod::from_num(1));
        // Grazing: n·d = 0 and tiny values clamp to 16 levels.
        assert_eq!(
            cone_lod::<Accurate>(w, d, Some(U1F31::ZERO)),
            Lod::from_num(16)
        );
        assert_eq!(
            cone_lod::<Accurate>(w, d, Some(U1F31::DELTA)),
            Lod::from_num(16)
        );
        // |n·d| > 1 (not physical) clamps to 1.
        assert_eq!(
            cone_lod::<Accurate>(w, d, Some(U1F31::from_num(1.9))),
            Lod::ZERO
        );
        // Negative width uses |w|.
        assert_eq!(
            cone_lod::<Accurate>(-Width::from_num(4), d, None),
            Lod::from_num(2)
        );
    }

    fn coord() -> impl Strategy<Value = f64> {
        prop_oneof![-1.0e3..1.0e3f64, -10.0..10.0f64]
    }

    fn tri_strategy() -> impl Strategy<Value = ([[f64; 3]; 3], [[f64; 2]; 3], u32, u32)> {
        (
            [
                [coord(), coord(), coord()],
                [coord(), coord(), coord()],
                [coord(), coord(), coord()],
            ],
            [
                [-50.0..50.0f64, -50.0..50.0f64],
                [-50.0..50.0f64, -50.0..50.0f64],
                [-50.0..50.0f64, -50.0..50.0f64],
            ],
            1u32..4096,
            1u32..4096,
        )
    }

    /// The formulas as first written (one `log2_bits` per term, saturating
    /// I16F16 sums, rounding to I8F8): the optimised per-hit code must give
    /// the same bits for every input.
    fn table_lod_formula(pl: PathLength, pb: Log2Pb) -> Option<Lod> {
        if pb.is_untextured() {
            return None;
        }
        let d = crate::log2::log2_u32f32(pl.to_fixed()).to_bits() - pb.to_i16f16().to_bits();
        Some(Lod::from_bits(((d + 0x80) >> 8) as i16))
    }

    #[cfg(feature = "cone")]
    fn cone_lod_formula(width: Width, delta: Delta, n_dot_d: Option<U1F31>) -> Lod {
        use crate::log2::log2_bits;
        let lw = log2_bits(width.to_bits().unsigned_abs(), 32);
        let mut l = delta.saturating_add(Delta::from_fixed(lw));
        if let Some(c) = n_dot_d {
            let c = c.to_bits().clamp(MIN_COS.to_bits(), 1 << 31);
            l = l.saturating_sub(Delta::from_fixed(log2_bits(u64::from(c), 31)));
        }
        let r = l.to_bits().saturating_add(0x80) >> 8;
        Lod::from_bits(r.clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16)
    }

    #[test]
    fn per_hit_code_equals_formula_at_the_edges() {
        let pls = [
            0u64,
            1,
            2,
            0xFFFF_FFFF,
            1 << 32,
            (1 << 32) + 1,
            u64::MAX,
            1 << 63,
        ];
        let pbs = [
            i32::MIN,
            i32::MIN + 1,
            -95 << 16,
            -1,
            0,
            1,
            95 << 16,
            i32::MAX,
        ];
        for &p in &pls {
            for &b in &pbs {
                let (pl, pb) = (PathLength::from_bits(p), Log2Pb::from_bits(b));
                assert_eq!(
                    table_lod::<Accurate>(pl, pb),
                    table_lod_formula(pl, pb),
                    "{p:#x} {b:#x}"
                );
                #[cfg(feature = "cone")]
                let d = Delta::from_bits(b);
                #[cfg(feature = "cone")]
                for c in [
                    None,
                    Some(0u32),
                    Some(1),
                    Some(1 << 15),
                    Some(1 << 31),
                    Some(u32::MAX),
                ] {
                    let (w, c) = (Width::from_bits(p as i64), c.map(U1F31::from_bits));
                    assert_eq!(
                        cone_lod::<Accurate>(w, d, c),
                        cone_lod_formula(w, d, c),
                        "{p:#x} {b:#x} {c:?}"
                    );
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4_000))]

        /// Per-hit lod against f64 for Pl in [2^-16, 2^16] reached by up to
        /// ten accumulated segments.
        #[test]
        fn table_lod_matches_f64_after_bounces(
            (p, uv, w, h) in tri_strategy(),
            g in 1.0e-4..0.05f64,
            segs in proptest::collection::vec(-16.0..16.0f64, 1..=10),
        ) {
            let p = p.map(|v| v.map(q));
            let uv = uv.map(|v| v.map(q));
            let gq = Spread::from_num(g);
            let spread = PixelSpread::from_angle(gq).unwrap();
            let pb = Log2Pb::compute(&make(p, uv, w, h), &spread);
            let want_pb = raymip_reference::pb::log2_pb_f64(&p, &uv, f64::from(w), f64::from(h), gq.to_num());
            prop_assume!(want_pb.is_finite() && want_pb.abs() < 100.0);
            // Segments whose sum lies in [2^-16, 2^16].
            let n = segs.len() as f64;
            let mut st = PathState::primary(&spread, 0);
            let mut pl = 0.0;
            for &e in &segs {
                let t = PathLength::from_num(2f64.powf(e) / n);
                st = st.advance(t).bounce(Spread::ZERO);
                pl += t.to_num::<f64>();
            }
            prop_assume!((2f64.powi(-16)..=2f64.powi(16)).contains(&pl));
            let want = pl.log2() - want_pb;
            prop_assume!(want.abs() < 120.0);
            let got = table_lod::<Accurate>(st.pl, pb).unwrap().to_num::<f64>();
            prop_assert!((got - want).abs() <= LOD_MAX_ERROR,
                "table lod {} vs f64 {} (Pl {}, log2 Pb {})", got, want, pl, want_pb);
            // The FAST path within the same bound (entry error included).
            let fast = table_lod::<Fast>(st.pl, pb).unwrap().to_num::<f64>();
            prop_assert!((fast - want).abs() <= LOD_MAX_ERROR,
                "fast table lod {} vs f64 {} (Pl {}, log2 Pb {})", fast, want, pl, want_pb);
            // The FAST batch from the ray stack's normalised Pl.
            let mut w = [LodWord::UNTEXTURED];
            table_lod_norm_batch(&[(st.pl_norm, pb)], &mut w);
            let batch = w[0].get().unwrap().to_num::<f64>();
            prop_assert!((batch - want).abs() <= LOD_MAX_ERROR,
                "fast table batch {} vs f64 {} (Pl {}, log2 Pb {})", batch, want, pl, want_pb);
            // Identity: cone with β = 0 and no normal term equals the table,
            // where the cone width is resolved (w ≥ 2^-20 scene units; its
            // step is 2^-32, see the module docs).
            #[cfg(feature = "cone")]
            {
                prop_assume!(st.cone.width >= Width::from_num(2f64.powi(-20)));
                let cone = cone_lod::<Accurate>(st.cone.width, pb.delta(&spread).unwrap(), None);
                prop_assert!((cone.to_num::<f64>() - got).abs() <= LOD_MAX_ERROR,
                    "cone {} vs table {}", cone, got);
            }
        }

        #[test]
        fn per_hit_code_equals_formula(p in any::<u64>(), s in 0u32..64, b in any::<i32>(), w in any::<i64>(), c in proptest::option::of(any::<u32>())) {
            let pl = PathLength::from_bits(p >> s);
            let pb = Log2Pb::from_bits(b);
            prop_assert_eq!(table_lod::<Accurate>(pl, pb), table_lod_formula(pl, pb));
            #[cfg(feature = "cone")]
            {
                let (w, d, c) = (Width::from_bits(w >> s), Delta::from_bits(b), c.map(U1F31::from_bits));
                prop_assert_eq!(cone_lod::<Accurate>(w, d, c), cone_lod_formula(w, d, c));
            }
            #[cfg(not(feature = "cone"))]
            let _ = (w, c);
        }

        #[test]
        fn table_lod_is_monotonic_in_pl(a in any::<u64>(), b in any::<u64>(), e in any::<i32>()) {
            let pb = Log2Pb::from_log2(I16F16::from_bits(e));
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            let l0 = table_lod::<Accurate>(PathLength::from_bits(lo), pb);
            let l1 = table_lod::<Accurate>(PathLength::from_bits(hi), pb);
            prop_assert!(l0 <= l1);
            // Neighbours too (the interesting case for table interpolation).
            let l2 = table_lod::<Accurate>(PathLength::from_bits(lo.saturating_add(1)), pb);
            prop_assert!(l0 <= l2);
        }

        #[test]
        #[cfg(feature = "cone")]
        fn cone_lod_never_panics_and_is_bounded(w in any::<i64>(), d in any::<i32>(), c in proptest::option::of(any::<u32>())) {
            let l = cone_lod::<Accurate>(Width::from_bits(w), Delta::from_bits(d), c.map(U1F31::from_bits));
            // f64 reference over the whole input range (a range check
            // `Lod::MIN <= l <= Lod::MAX` holds for every Lod, so it could
            // not fail): `w = 0` read as 2⁻³², |n·d| clamped to [2⁻¹⁶, 1], the sum
            // saturated to the Lod range. Two log2 errors and the output
            // rounding stay within LOD_MAX_ERROR.
            let lw = (w.unsigned_abs().max(1) as f64).log2() - 32.0;
            let lc = c.map_or(0.0, |c| (f64::from(c.clamp(1 << 15, 1 << 31)) / 2f64.powi(31)).log2());
            let want = (f64::from(d) / 65536.0 + lw - lc).clamp(Lod::MIN.to_num(), Lod::MAX.to_num());
            prop_assert!((l.to_num::<f64>() - want).abs() <= LOD_MAX_ERROR, "cone_lod = {} vs f64 {}", l, want);
            let c2 = clamp_lod(l, 13);
            prop_assert!(c2 >= Lod::ZERO && c2 <= Lod::from_num(12));
        }

        /// FAST table lod against f64 over the whole input range: every
        /// `Pl` bit pattern (octaves drawn uniformly), every textured entry
        /// the table can hold (incl. the degenerate markers); within one
        /// step of the ACCURATE path, and monotonic in `Pl`.
        #[test]
        fn fast_table_lod_matches_f64_over_the_whole_range(n in 0u32..64, m in any::<u64>(), e in (i32::MIN + 1)..) {
            let p = (1u64 << n) | (m & ((1u64 << n) - 1));
            let (pl, pb) = (PathLength::from_bits(p), Log2Pb::from_bits(e));
            let got = table_lod::<Fast>(pl, pb).unwrap();
            let want = (p as f64).log2() - 32.0 - pb.to_i16f16().to_num::<f64>();
            prop_assert!((got.to_num::<f64>() - want).abs() <= LOD_MAX_ERROR, "fast {} vs f64 {}", got, want);
            let acc = table_lod::<Accurate>(pl, pb).unwrap();
            prop_assert!((got.to_bits() - acc.to_bits()).abs() <= 1, "fast {} vs accurate {}", got, acc);
            prop_assert_eq!(table_lod_norm(NormPl::new(pl), pb), Some(got));
            // The batch's word, against f64 too.
            let mut w = [LodWord::UNTEXTURED];
            prop_assert_eq!(table_lod_norm_batch(&[(NormPl::new(pl), pb)], &mut w), 1);
            let word = w[0].get().unwrap();
            prop_assert!((word.to_num::<f64>() - want).abs() <= LOD_MAX_ERROR, "batch {} vs f64 {}", word, want);
            prop_assert_eq!(word, got);
            if p < u64::MAX {
                prop_assert!(table_lod::<Fast>(PathLength::from_bits(p + 1), pb).unwrap() >= got);
            }
        }

        /// FAST cone lod against f64 over the whole input range (as
        /// `cone_lod_never_panics_and_is_bounded` for the ACCURATE path).
        #[test]
        #[cfg(feature = "cone")]
        fn fast_cone_lod_matches_f64_over_the_whole_range(n in 0u32..64, m in any::<u64>(), neg in any::<bool>(), d in any::<i32>(), c in proptest::option::of(any::<u32>())) {
            let bits = ((1u64 << n) | (m & ((1u64 << n) - 1))) >> 1;
            let w = if neg { -(bits as i64) } else { bits as i64 };
            let l = cone_lod::<Fast>(Width::from_bits(w), Delta::from_bits(d), c.map(U1F31::from_bits));
            let lw = (w.unsigned_abs().max(1) as f64).log2() - 32.0;
            let lc = c.map_or(0.0, |c| (f64::from(c.clamp(1 << 15, 1 << 31)) / 2f64.powi(31)).log2());
            let want = (f64::from(d) / 65536.0 + lw - lc).clamp(Lod::MIN.to_num(), Lod::MAX.to_num());
            prop_assert!((l.to_num::<f64>() - want).abs() <= LOD_MAX_ERROR, "cone_lod::<Fast> = {} vs f64 {}", l, want);
            let acc = cone_lod::<Accurate>(Width::from_bits(w), Delta::from_bits(d), c.map(U1F31::from_bits));
            prop_assert!((l.to_bits() - acc.to_bits()).abs() <= 1, "fast {} vs accurate {}", l, acc);
        }

        /// The table batches (FAST, and ACCURATE against `table_lod`) equal
        /// the per-hit calls bit for bit over
        /// the whole input range: keys of every path length (octaves drawn
        /// uniformly, zero and the largest included), every table entry
        /// (the three markers, the finite extremes and any raw word),
        /// unequal lengths (words past `n` untouched). Against
        /// `table_lod::<Fast>`, whose arithmetic is separate (leading-zero
        /// count, the unshifted table).
        #[test]
        fn table_lod_norm_batch_equals_per_hit_calls(
            hits in proptest::collection::vec((0u32..66, any::<u64>(), 0u8..8, any::<i32>()), 0..40),
            extra in 0usize..3,
            longer in any::<bool>(),
        ) {
            let t: std::vec::Vec<_> = hits.iter().map(|&(n, m, sel, b)| {
                let p = match n {
                    64 => 0,
                    65 => u64::MAX,
                    n => (1u64 << n) | (m & ((1u64 << n) - 1)),
                };
                let pb = match sel {
                    0 => Log2Pb::UNTEXTURED,
                    1 => Log2Pb::DEGENERATE_GEOMETRY,
                    2 => Log2Pb::DEGENERATE_UV,
                    3 => Log2Pb::MIN,
                    4 => Log2Pb::MAX,
                    _ => Log2Pb::from_bits(b),
                };
                (PathLength::from_bits(p), pb)
            }).collect();
            let k: std::vec::Vec<_> = t.iter().map(|&(pl, pb)| (NormPl::new(pl), pb)).collect();
            const UNTOUCHED: i32 = 0x1234_5678;
            let len = if longer { t.len() + extra } else { t.len().saturating_sub(extra) };
            let mut out = std::vec![LodWord(UNTOUCHED); len];
            let n = table_lod_norm_batch(&k, &mut out);
            prop_assert_eq!(n, t.len().min(len));
            for (i, (o, &(pl, pb))) in out.iter().zip(&t).enumerate() {
                prop_assert_eq!(o.get(), table_lod::<Fast>(pl, pb), "hit {}: word {:#x}", i, o.0);
                prop_assert_eq!(o.get(), table_lod_norm(k[i].0, pb));
            }
            prop_assert!(out[n..].iter().all(|o| o.0 == UNTOUCHED));
            // The ACCURATE batch over the same hits and lengths.
            let mut acc = std::vec![Some(Lod::MIN); len];
            prop_assert_eq!(table_lod_batch::<Accurate>(&t, &mut acc), n);
            for (o, &(pl, pb)) in acc.iter().zip(&t) {
                prop_assert_eq!(*o, table_lod::<Accurate>(pl, pb));
            }
            prop_assert!(acc[n..].iter().all(|&o| o == Some(Lod::MIN)));
        }

        /// Keys from any raw word (clamped by `NormPl::from_bits`) stay
        /// out of the niche when textured and in it when untextured: the
        /// batch's word against f64 of the key's path length
        /// `2^e · (1 + i/1024)` (the table's midpoint is within the FAST
        /// log2 bound of it).
        #[test]
        fn table_lod_norm_batch_any_key_word(bits in any::<i32>(), sel in 0u8..6, b in any::<i32>()) {
            let key = NormPl::from_bits(bits);
            let (e, i) = (key.to_bits() >> 16, key.to_bits() & 1023);
            prop_assert!((-32..=31).contains(&e));
            prop_assert_eq!(key.to_bits() & 0xFC00, 0);
            let pb = match sel {
                0 => Log2Pb::UNTEXTURED,
                1 => Log2Pb::DEGENERATE_GEOMETRY,
                2 => Log2Pb::DEGENERATE_UV,
                _ => Log2Pb::from_bits(b),
            };
            let mut w = [LodWord(0)];
            table_lod_norm_batch(&[(key, pb)], &mut w);
            prop_assert_eq!(w[0].get(), table_lod_norm(key, pb));
            if pb.is_untextured() {
                prop_assert_eq!(w[0].get(), None);
                prop_assert!(w[0].0.unsigned_abs() >= 1 << 22, "{:#x}", w[0].0);
            } else {
                let got = w[0].get().unwrap().to_num::<f64>();
                let want = f64::from(e) + (1.0 + f64::from(i) / 1024.0).log2()
                    - pb.to_i16f16().to_num::<f64>();
                prop_assert!((got - want).abs() <= LOD_MAX_ERROR, "{:#x} {:?}: {} vs f64 {}", bits, pb, got, want);
                prop_assert!(w[0].0.abs() <= 32512);
            }
        }

        /// The cone batches (FAST and ACCURATE) equal the per-hit calls, also
        /// with unequal lengths.
        #[test]
        #[cfg(feature = "cone")]
        fn fast_cone_lod_batch_equals_per_hit_calls(hits in proptest::collection::vec((any::<i32>(), any::<i64>(), proptest::option::of(any::<u32>())), 0..40), extra in 0usize..3) {
            let c: std::vec::Vec<_> = hits.iter().map(|&(b, w, c)| (Width::from_bits(w), Delta::from_bits(b), c.map(U1F31::from_bits))).collect();
            let mut out = std::vec![Lod::MAX; c.len() + extra];
            prop_assert_eq!(cone_lod_batch::<Fast>(&c, &mut out), c.len());
            for (o, &(w, d, n)) in out.iter().zip(&c) {
                prop_assert_eq!(*o, cone_lod::<Fast>(w, d, n));
            }
            prop_assert!(out[c.len()..].iter().all(|&o| o == Lod::MAX));
            // The ACCURATE batch, with an output shorter than the hits too.
            let short = c.len().saturating_sub(extra);
            for len in [c.len() + extra, short] {
                let mut acc = std::vec![Lod::MIN; len];
                prop_assert_eq!(cone_lod_batch::<Accurate>(&c, &mut acc), c.len().min(len));
                for (o, &(w, d, n)) in acc.iter().zip(&c) {
                    prop_assert_eq!(*o, cone_lod::<Accurate>(w, d, n));
                }
                prop_assert!(acc[c.len().min(len)..].iter().all(|&o| o == Lod::MIN));
            }
        }

        #[test]
        fn clamp_lod_stays_in_stored_levels(bits in any::<i16>(), levels in any::<u8>()) {
            let lod = Lod::from_bits(bits);
            let c = clamp_lod(lod, levels);
            let top = f64::from(levels.clamp(1, 128) - 1);
            prop_assert!(c.to_num::<f64>() >= 0.0 && c.to_num::<f64>() <= top);
            // Inside the range it is the identity.
            if lod.to_num::<f64>() >= 0.0 && lod.to_num::<f64>() <= top {
                prop_assert_eq!(c, lod);
            }
        }
    }
}
