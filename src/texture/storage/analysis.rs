//! Set-up scene analysis: which MIP levels a scene can select, per texture.
//!
//! The table method makes the level of detail of a hit a function of two
//! numbers, `lod = log2 Pl − log2 Pb` ([`table_lod`]), monotonic
//! non-decreasing in the path length `Pl` and non-increasing in `log2 Pb`.
//! Given, per texture, the nearest and farthest path length any hit on it
//! can have ([`PathBounds`], from the caller: camera-to-bounding-box
//! distances for primary rays; for paths with bounces, the straight-line
//! distance from the camera is still a lower bound, and a scene diameter
//! per segment gives an upper bound), every hit's lod lies in
//!
//! ```text
//! [ min over the texture's triangles of table_lod::<Accurate>(nearest, Pb),
//!   max over the texture's triangles of table_lod::<Accurate>(farthest, Pb) ]
//! ```
//!
//! computed here with the very function the per-hit path uses, so the range
//! is exact for the bounds given, never too tight ([`analyse`]). From it
//! [`LodRange::levels`] gives the stored levels a sampler can read for a
//! filter mode, after the sampler's clamp to `[0, levels − 1]`:
//!
//! * nearest-level modes read level `floor(lod + ½)`: levels
//!   `floor(min + ½) ..= floor(max + ½)`;
//! * linear-level modes read `floor(lod)` and, when `frac(lod) ≠ 0`,
//!   `floor(lod) + 1`: levels `floor(min) ..= ceil(max)`.
//!
//! A pyramid that stores only those levels
//! ([`Geometry::trimmed`](crate::texture::storage::mip::Geometry::trimmed),
//! [`Pyramid::trim`](crate::texture::storage::mip::Pyramid::trim)) gives bit-identical
//! samples. A texture whose triangles no hit can reach (the caller gives no
//! bounds), or that no textured triangle uses, needs no levels at all;
//! [`mark_skipped`] turns the table entries of the triangles of such
//! textures into [`Log2Pb::UNTEXTURED`], so any hit on them skips the
//! texture path.
//!
//! # Ray cones
//!
//! The cone lod is `Δ + log2|w| − log2|n·d|`. With flat surfaces only
//! (surface spread `β = 0` at every bounce) the cone width is `γ·Pl`, so
//! without the normal term the cone lod equals the table lod within
//! 2⁻⁸ level each (tested in `lod`), and the normal term only adds (it lies
//! in `[0, 16]`): the cone lod is at least the table range's `min − 2/256`
//! (for cone widths of at least 2⁻²⁰ scene units, where the width is
//! resolved), but has no useful upper bound (grazing hits go up to 16
//! levels coarser). [`LodRange::for_cones`] gives that range. With curved
//! reflectors or refractors (`β ≠ 0`) the width is not a function of `Pl`
//! and nothing can be trimmed: store full pyramids.
//!
//! Set-up only: integer arithmetic, no allocation (caller slices), never
//! panics.

use core::fmt;

use crate::lod::{clamp_lod, table_lod};
use crate::texture::mode::Mode;
use crate::units::{Accurate, Lod, Log2Pb, PathLength};

/// The nearest and farthest accumulated path length `Pl` (scene units)
/// any hit on a texture can have. `nearest ≤ farthest` is not required
/// (they are ordered on use).
///
/// Example: [`analyse`] (with [`TextureUse`], [`LodRange`], [`LevelRange`]
/// and [`AnalysisStats`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathBounds {
    /// Lower bound of `Pl` over every hit on the texture.
    pub nearest: PathLength,
    /// Upper bound of `Pl` over every hit on the texture.
    pub farthest: PathLength,
}

/// An inclusive range of [`Lod`] values (`min ≤ max`). Example: [`analyse`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LodRange {
    /// Smallest lod any hit can have.
    pub min: Lod,
    /// Largest lod any hit can have.
    pub max: Lod,
}

/// An inclusive range of MIP levels (`first ≤ last`). Example: [`analyse`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelRange {
    /// Finest level read.
    pub first: u8,
    /// Coarsest level read.
    pub last: u8,
}

impl LevelRange {
    /// Number of levels in the range.
    #[must_use]
    pub const fn count(&self) -> u8 {
        self.last.saturating_sub(self.first).saturating_add(1)
    }
}

/// One texture's part of the analysis. Example: [`analyse`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TextureUse {
    /// Textured triangles that use the texture (entries other than
    /// [`Log2Pb::UNTEXTURED`]).
    pub triangles: u32,
    /// Lod range of every hit on the texture; `None` when no hit can sample
    /// it (no triangle uses it, or the caller gave no bounds).
    pub lod: Option<LodRange>,
}

/// Counts of an [`analyse`] pass (example there).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AnalysisStats {
    /// Triangles with a texture entry.
    pub textured: u32,
    /// Triangles without one ([`Log2Pb::UNTEXTURED`]).
    pub untextured: u32,
    /// Textures some hit can sample.
    pub textures_sampled: u32,
    /// Textures no hit can sample.
    pub textures_skipped: u32,
}

/// Errors of the analysis (bad caller slices).
///
/// # Example
/// ```
/// use raymip::texture::storage::analysis::{AnalysisError, PathBounds, TextureUse, analyse};
/// use raymip::{Log2Pb, PathLength};
/// let entries = [Log2Pb::from_bits(0); 3];
/// let bounds = [Some(PathBounds { nearest: PathLength::ONE, farthest: PathLength::ONE })];
/// let mut out = [TextureUse::default()];
/// // Three table entries but texture ids for only two of them.
/// let err = analyse(&entries, &[0, 0], &bounds, &mut out).unwrap_err();
/// assert_eq!(err, AnalysisError::TextureIdsTooShort);
/// assert_eq!(err.to_string(), "fewer texture ids than table entries");
/// // Triangle 2 names texture 1, but `out` has room for texture 0 only.
/// let err = analyse(&entries, &[0, 0, 1], &bounds, &mut out).unwrap_err();
/// assert_eq!(err, AnalysisError::BadTexture { triangle: 2 });
/// assert_eq!(err.to_string(), "triangle 2 names a texture that does not exist");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum AnalysisError {
    /// `texture_of` is shorter than the table.
    TextureIdsTooShort,
    /// `bounds` and `out` differ in length.
    LengthMismatch,
    /// A textured triangle names a texture `≥ out.len()`.
    BadTexture {
        /// The triangle.
        triangle: usize,
    },
}

impl fmt::Display for AnalysisError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TextureIdsTooShort => f.write_str("fewer texture ids than table entries"),
            Self::LengthMismatch => f.write_str("bounds and output differ in length"),
            Self::BadTexture { triangle } => {
                write!(f, "triangle {triangle} names a texture that does not exist")
            }
        }
    }
}

impl core::error::Error for AnalysisError {}

/// Lod ranges per texture: for every table entry `i` (textured ones only)
/// with texture `texture_of[i]`, widens `out[texture]` by
/// `table_lod::<Accurate>(nearest, Pb)` and `table_lod::<Accurate>(farthest, Pb)` of that texture's
/// `bounds` (`None`: no hit can reach the texture; its triangles count but
/// give no range). `out` is overwritten.
///
/// # Errors
/// [`AnalysisError::TextureIdsTooShort`], [`AnalysisError::LengthMismatch`]
/// (`bounds.len() != out.len()`), [`AnalysisError::BadTexture`] (`out` is
/// left partly written).
///
/// # Example
/// ```
/// use raymip::texture::storage::analysis::{AnalysisStats, LevelRange, LodRange, PathBounds, TextureUse, analyse};
/// use raymip::{Lod, Log2Pb, Mode, PathLength};
/// // Texture 0 on two triangles, log2 Pb = 0 and 1; triangle 2 untextured;
/// // triangle 3 uses texture 1, which the caller knows no hit can reach.
/// let entries = [
///     Log2Pb::from_bits(0),
///     Log2Pb::from_bits(1 << 16), // I16F16 bits of 1.0
///     Log2Pb::UNTEXTURED,
///     Log2Pb::from_bits(0),
/// ];
/// let texture_of = [0, 0, 0, 1];
/// let bounds = [
///     Some(PathBounds { nearest: PathLength::from_num(4), farthest: PathLength::from_num(16) }),
///     None,
/// ];
/// let mut usage = [TextureUse::default(); 2];
/// let stats = analyse(&entries, &texture_of, &bounds, &mut usage)?;
/// assert_eq!(
///     stats,
///     AnalysisStats { textured: 3, untextured: 1, textures_sampled: 1, textures_skipped: 1 }
/// );
/// // lod = log2 Pl − log2 Pb: nearest log2 4 − 1 = 1, farthest log2 16 − 0 = 4.
/// let range = usage[0].lod.ok_or("texture 0 is reached")?;
/// assert_eq!(range, LodRange { min: Lod::from_num(1), max: Lod::from_num(4) });
/// assert_eq!(usage[0].triangles, 2);
/// assert_eq!(usage[1], TextureUse { triangles: 1, lod: None });
/// // An 8-level pyramid: trilinear reads floor(1) ..= ceil(4), nearest-level
/// // floor(1 + ½) ..= floor(4 + ½): levels 1 to 4 either way, 4 of 8 stored.
/// let levels = range.levels(Mode::Trilinear, 8);
/// assert_eq!(levels, LevelRange { first: 1, last: 4 });
/// assert_eq!(levels.count(), 4);
/// assert_eq!(range.levels(Mode::BilinearNearestLevel, 8), levels);
/// // A 3-level pyramid clamps lods to [0, 2]: levels 1 to 2.
/// assert_eq!(range.levels(Mode::Trilinear, 3), LevelRange { first: 1, last: 2 });
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn analyse(
    entries: &[Log2Pb],
    texture_of: &[u16],
    bounds: &[Option<PathBounds>],
    out: &mut [TextureUse],
) -> Result<AnalysisStats, AnalysisError> {
    if texture_of.len() < entries.len() {
        return Err(AnalysisError::TextureIdsTooShort);
    }
    if bounds.len() != out.len() {
        return Err(AnalysisError::LengthMismatch);
    }
    out.fill(TextureUse::default());
    let mut stats = AnalysisStats::default();
    for (triangle, (&pb, &tex)) in entries.iter().zip(texture_of).enumerate() {
        if pb.is_untextured() {
            stats.untextured += 1;
            continue;
        }
        stats.textured += 1;
        let t = usize::from(tex);
        let (Some(slot), Some(b)) = (out.get_mut(t), bounds.get(t)) else {
            return Err(AnalysisError::BadTexture { triangle });
        };
        slot.triangles += 1;
        let Some(b) = b else { continue };
        let (near, far) = (b.nearest.min(b.farthest), b.nearest.max(b.farthest));
        // `table_lod` is `Some` for every textured entry.
        let (Some(lo), Some(hi)) = (
            table_lod::<Accurate>(near, pb),
            table_lod::<Accurate>(far, pb),
        ) else {
            continue;
        };
        slot.lod = Some(match slot.lod {
            None => LodRange { min: lo, max: hi },
            Some(r) => LodRange {
                min: r.min.min(lo),
                max: r.max.max(hi),
            },
        });
    }
    for u in out.iter() {
        if u.lod.is_some() {
            stats.textures_sampled += 1;
        } else {
            stats.textures_skipped += 1;
        }
    }
    Ok(stats)
}

impl LodRange {
    /// The stored levels a sampler over a texture of `levels` levels can
    /// read for lods in this range with filter `mode` (module docs; the
    /// sampler's clamp to `[0, levels − 1]` included).
    #[must_use]
    pub fn levels(&self, mode: Mode, levels: u8) -> LevelRange {
        let top = levels.saturating_sub(1).min(127);
        // Clamped lods are in [0, top]: bits in [0, 127·256].
        let lo = clamp_lod(self.min.min(self.max), levels)
            .to_bits()
            .unsigned_abs();
        let hi = clamp_lod(self.max.max(self.min), levels)
            .to_bits()
            .unsigned_abs();
        let level = |bits: u16| u8::try_from(bits >> 8).unwrap_or(top).min(top);
        let linear = match mode {
            Mode::BilinearNearestLevel | Mode::Nearest => false,
            #[cfg(feature = "trilinear")]
            Mode::Trilinear | Mode::NearestTexelLinearLevel => true,
        };
        if linear {
            LevelRange {
                first: level(lo),
                last: level(hi.saturating_add(0xFF)),
            }
        } else {
            LevelRange {
                first: level(lo.saturating_add(0x80)),
                last: level(hi.saturating_add(0x80)),
            }
        }
    }

    /// The range a ray-cone lod can take on a scene with flat surfaces only
    /// (module docs): `min − 2/256` up to [`Lod::MAX`]. Valid where the cone
    /// width at the nearest bound is at least 2⁻²⁰ scene units.
    #[must_use]
    pub fn for_cones(&self) -> Self {
        Self {
            min: self.min.min(self.max).saturating_sub(Lod::from_bits(2)),
            max: Lod::MAX,
        }
    }
}

/// Marks the triangles of textures no hit can sample (`usage[t].lod` is
/// `None`) as untextured, so the per-hit path skips their texture fetch.
/// Entries with a texture id outside `usage` are left alone. Returns the
/// number of entries changed.
pub fn mark_skipped(entries: &mut [Log2Pb], texture_of: &[u16], usage: &[TextureUse]) -> u32 {
    let mut n = 0;
    for (e, &t) in entries.iter_mut().zip(texture_of) {
        if !e.is_untextured() && usage.get(usize::from(t)).is_some_and(|u| u.lod.is_none()) {
            *e = Log2Pb::UNTEXTURED;
            n += 1;
        }
    }
    n
}

#[cfg(test)]
mod tests {
    use crate::units::Accurate;
    extern crate std;
    use super::*;
    use crate::texture::Sampler;
    use crate::texture::storage::mip::Geometry;
    use crate::texture::storage::mip::Pyramid;
    use fixed::types::I16F16;
    use proptest::prelude::*;
    use std::vec::Vec;

    fn pb(x: f64) -> Log2Pb {
        Log2Pb::from_log2(I16F16::from_num(x))
    }

    fn pl(x: f64) -> PathLength {
        PathLength::from_num(x)
    }

    #[test]
    fn ranges_per_texture_and_skips() {
        // Texture 0: two triangles; texture 1: one triangle, no bounds;
        // texture 2: unused.
        let entries = [pb(0.0), pb(1.0), Log2Pb::UNTEXTURED, pb(-2.0)];
        let texture_of = [0u16, 0, 5, 1];
        let bounds = [
            Some(PathBounds {
                nearest: pl(4.0),
                farthest: pl(16.0),
            }),
            None,
            Some(PathBounds {
                nearest: pl(1.0),
                farthest: pl(1.0),
            }),
        ];
        let mut out = [TextureUse::default(); 3];
        let s = analyse(&entries, &texture_of, &bounds, &mut out).unwrap();
        assert_eq!(
            s,
            AnalysisStats {
                textured: 3,
                untextured: 1,
                textures_sampled: 1,
                textures_skipped: 2
            }
        );
        // lod = log2 Pl − log2 Pb: min log2 4 − 1 = 1, max log2 16 − 0 = 4.
        assert_eq!(
            out[0],
            TextureUse {
                triangles: 2,
                lod: Some(LodRange {
                    min: Lod::from_num(1),
                    max: Lod::from_num(4)
                })
            }
        );
        assert_eq!(
            out[1],
            TextureUse {
                triangles: 1,
                lod: None
            }
        );
        assert_eq!(out[2], TextureUse::default());
        let mut e = entries;
        assert_eq!(mark_skipped(&mut e, &texture_of, &out), 1);
        assert_eq!(
            e,
            [pb(0.0), pb(1.0), Log2Pb::UNTEXTURED, Log2Pb::UNTEXTURED]
        );
        // Errors.
        assert_eq!(
            analyse(&entries, &texture_of[..2], &bounds, &mut out),
            Err(AnalysisError::TextureIdsTooShort)
        );
        assert_eq!(
            analyse(&entries, &texture_of, &bounds[..2], &mut out),
            Err(AnalysisError::LengthMismatch)
        );
        assert_eq!(
            analyse(&entries, &[0, 0, 0, 3], &bounds, &mut out),
            Err(AnalysisError::BadTexture { triangle: 3 })
        );
        assert!(std::format!("{}", AnalysisError::BadTexture { triangle: 3 }).contains('3'));
    }

    #[test]
    fn level_ranges_per_mode() {
        let r = |a: f64, b: f64| LodRange {
            min: Lod::from_num(a),
            max: Lod::from_num(b),
        };
        let lr = |first, last| LevelRange { first, last };
        assert_eq!(r(1.0, 4.0).levels(Mode::Nearest, 9), lr(1, 4));
        assert_eq!(r(1.4, 3.5).levels(Mode::BilinearNearestLevel, 9), lr(1, 4));
        assert_eq!(r(1.5, 3.49).levels(Mode::Nearest, 9), lr(2, 3));
        assert_eq!(r(-7.0, 99.0).levels(Mode::Nearest, 9), lr(0, 8));
        assert_eq!(r(20.0, 30.0).levels(Mode::Nearest, 9), lr(8, 8));
        assert_eq!(r(-30.0, -20.0).levels(Mode::Nearest, 9), lr(0, 0));
        #[cfg(feature = "trilinear")]
        {
            assert_eq!(r(1.0, 4.0).levels(Mode::Trilinear, 9), lr(1, 4));
            assert_eq!(r(1.9, 4.01).levels(Mode::Trilinear, 9), lr(1, 5));
            assert_eq!(
                r(1.9, 7.5).levels(Mode::NearestTexelLinearLevel, 9),
                lr(1, 8)
            );
            assert_eq!(r(1.9, 8.5).levels(Mode::Trilinear, 9), lr(1, 8));
            assert_eq!(r(-3.0, -1.0).levels(Mode::Trilinear, 9), lr(0, 0));
        }
        assert_eq!(r(-3.0, -1.0).levels(Mode::Nearest, 1), lr(0, 0));
        assert_eq!(r(2.0, 1.0).levels(Mode::Nearest, 0), lr(0, 0));
        assert_eq!(lr(2, 5).count(), 4);
        let c = r(1.0, 2.0).for_cones();
        assert_eq!(
            (c.min, c.max),
            (Lod::from_num(1) - Lod::from_bits(2), Lod::MAX)
        );
    }

    /// The level a sampler reads for a lod, written out from the filter
    /// docs (independent of `LodRange::levels`): `(level, second level)`.
    fn read_levels(lod: Lod, mode: Mode, levels: u8) -> (u8, Option<u8>) {
        let top = f64::from(levels - 1);
        let l = lod.to_num::<f64>().clamp(0.0, top);
        let linear = match mode {
            Mode::BilinearNearestLevel | Mode::Nearest => false,
            #[cfg(feature = "trilinear")]
            _ => true,
        };
        if linear {
            let lower = l.floor();
            (lower as u8, (l != lower).then_some(lower as u8 + 1))
        } else {
            ((l + 0.5).floor().min(top) as u8, None)
        }
    }

    fn modes() -> Vec<Mode> {
        (0..4).filter_map(Mode::from_index).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3_000))]
        /// Never too tight: every hit of random triangles and path lengths
        /// within the bounds reads only levels inside the computed range;
        /// and exact at the bounds: the extreme hits reach both ends.
        #[test]
        fn conservative_against_brute_force(
            pbs in proptest::collection::vec(-70.0..70.0f64, 1..6),
            a in 0u64..=u64::MAX,
            b in 0u64..=u64::MAX,
            ts in proptest::collection::vec(0.0..1.0f64, 1..20),
            levels in 1u8..=16,
        ) {
            let entries: Vec<Log2Pb> = pbs.iter().map(|&x| pb(x)).collect();
            let ids = std::vec![0u16; entries.len()];
            let (near, far) = (PathLength::from_bits(a.min(b)), PathLength::from_bits(a.max(b)));
            let mut out = [TextureUse::default()];
            // Bounds given in either order.
            analyse(&entries, &ids, &[Some(PathBounds { nearest: far, farthest: near })], &mut out).unwrap();
            let range = out[0].lod.unwrap();
            for mode in modes() {
                let lr = range.levels(mode, levels);
                prop_assert!(lr.first <= lr.last && lr.last < levels);
                let mut seen = (u8::MAX, 0u8);
                for &e in &entries {
                    // Hits anywhere in [near, far], the ends included.
                    let span = (far.to_bits() - near.to_bits()) as f64;
                    let pls = ts.iter().map(|&t| near.to_bits() + (t * span) as u64)
                        .chain([near.to_bits(), far.to_bits()]);
                    for bits in pls {
                        let bits = bits.clamp(near.to_bits(), far.to_bits());
                        let lod = table_lod::<Accurate>(PathLength::from_bits(bits), e).unwrap();
                        let (l0, l1) = read_levels(lod, mode, levels);
                        // The sampler's own level split agrees.
                        let g = Geometry::new(1 << (levels - 1), 1, levels).unwrap();
                        let texels = std::vec![0; g.len()];
                        let s = Sampler::wrap(Pyramid::new(g, &texels).unwrap());
                        let sampler = s.levels(lod, mode);
                        prop_assert_eq!(sampler, (l0, l1));
                        for l in core::iter::once(l0).chain(l1) {
                            prop_assert!(lr.first <= l && l <= lr.last,
                                "{mode:?}: level {l} of lod {lod} outside {lr:?}");
                            seen = (seen.0.min(l), seen.1.max(l));
                        }
                    }
                }
                prop_assert_eq!(seen.0, lr.first, "{:?}: first level not reached", mode);
                prop_assert!(lr.last <= seen.1 + 1, "{:?}: range wider than the reads", mode);
            }
        }

        /// The lod range against an f64 evaluation of log2(Pl/Pb): within
        /// the table method's error bound of the exact extremes.
        #[test]
        fn lod_range_matches_f64(
            pbs in proptest::collection::vec(-60.0..60.0f64, 1..6),
            near in 1.0e-3..1.0e4f64,
            k in 1.0..1.0e3f64,
        ) {
            let entries: Vec<Log2Pb> = pbs.iter().map(|&x| pb(x)).collect();
            let ids = std::vec![0u16; entries.len()];
            let far = near * k;
            let mut out = [TextureUse::default()];
            analyse(&entries, &ids, &[Some(PathBounds { nearest: pl(near), farthest: pl(far) })], &mut out).unwrap();
            let r = out[0].lod.unwrap();
            let q = |x: f64| I16F16::from_num(x).to_num::<f64>();
            let lo = pbs.iter().map(|&p| pl(near).to_num::<f64>().log2() - q(p)).fold(f64::INFINITY, f64::min);
            let hi = pbs.iter().map(|&p| pl(far).to_num::<f64>().log2() - q(p)).fold(f64::NEG_INFINITY, f64::max);
            prop_assert!((r.min.to_num::<f64>() - lo).abs() <= crate::lod::LOD_MAX_ERROR, "{} vs {lo}", r.min);
            prop_assert!((r.max.to_num::<f64>() - hi).abs() <= crate::lod::LOD_MAX_ERROR, "{} vs {hi}", r.max);
        }
    }
}
