//! Per-triangle table: one `log2 Pb` per textured triangle, computed at
//! set-up in fixed point (float-free, so dynamic triangles can be updated by
//! an FPU-less controller).
//!
//! # Derivation of `Pb`
//!
//! A pinhole camera with vertical field of view `fov_y` and an image `H`
//! pixels high gives every pixel the spread angle
//! `γ = atan(2·tan(fov_y/2) / H)` (radians): at distance `d` a pixel covers a
//! footprint about `γ·d` wide.
//!
//! A textured triangle with world-space area `A` (scene units²) and UV-space
//! area `a_uv` on a `w × h` texture covers `N = a_uv·w·h` texels, so one texel
//! covers `A/N` scene units², i.e. it is `√(A/N)` scene units wide (for an
//! isotropic mapping).
//!
//! One texel covers one pixel when the pixel footprint equals the texel
//! width: `γ·d = √(A/N)`. That distance is
//!
//! ```text
//! Pb = √(A/N) / γ          log2 Pb = ½·log2(A/N) − log2 γ = −Δ − log2 γ
//! ```
//!
//! with the ray-cone triangle constant `Δ = ½·log2(N/A)` (Akenine-Möller et
//! al., Ray Tracing Gems ch. 20). At path length `Pl` the footprint is `Pl/Pb`
//! texels wide, so `lod = log2(Pl/Pb) = log2 Pl − log2 Pb`: 0 at `Pl = Pb`,
//! +1 per doubling. (The hardware paper prints `½·log2(T_XS/T_size)`, which
//! inverts the ratio and omits `γ`; with it the lod would change with the
//! scene's units. The fronto-parallel test in [`crate::lod`] checks the form
//! used here.)
//!
//! # Fixed-point evaluation
//!
//! Positions are [`Coord`], UVs [`TexCoord`], both I32F32. Edge vectors are formed exactly
//! in 128-bit integers; if an edge exceeds 2⁶² raw units (|edge| > 2³⁰ scene
//! units) all edges of that triangle are shifted right together so the cross
//! products cannot overflow. Then
//! `log2(A/N) = ½·log2|e₁×e₂|² − log2|uv₁×uv₂| − log2 w − log2 h`
//! needs no square root and no division. Each of the four logarithms is off
//! by at most [`LOG2_MAX_ERROR`](crate::log2::LOG2_MAX_ERROR), so an entry is
//! within [`TABLE_MAX_ERROR`] `= 2⁻¹⁰` level of the exact value.
//!
//! # Degenerate triangles (documented values, never a panic)
//!
//! | input | entry | effect on lod |
//! |---|---|---|
//! | untextured | [`Log2Pb::UNTEXTURED`] | [`table_lod`](crate::lod::table_lod) returns `None`; no table work |
//! | zero world area (collinear or duplicate vertices) | [`Log2Pb::DEGENERATE_GEOMETRY`] | lod saturates high → coarsest stored level |
//! | non-zero area, zero UV area | [`Log2Pb::DEGENERATE_UV`] | lod saturates low → level 0 |
//! | NaN/inf or out-of-range coordinate | [`TableError::NonFinite`] / [`TableError::OutOfRange`] from [`TexTriangle::from_f32`] | — |
//! | zero texture width or height | [`TableError::ZeroTextureSize`] | — |

use fixed::types::{I16F16, I32F32};

use crate::log2::{log2_bits_u128, log2_u32};
use crate::setup::camera::PixelSpread;
#[cfg(feature = "cone")]
use crate::units::Delta;
use crate::units::{Coord, Log2Pb, TexCoord};

/// Documented maximum absolute error of a table entry against exact
/// arithmetic, in levels: 2⁻¹⁰.
pub const TABLE_MAX_ERROR: f64 = 1.0 / 1024.0;

unit_error! {
    /// Errors at the set-up API edge.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[non_exhaustive]
    pub enum TableError {
        /// A coordinate was NaN or infinite.
        NonFinite => "coordinate is NaN or infinite",
        /// A coordinate does not fit I32F32 (|x| ≥ 2³¹).
        OutOfRange => "coordinate outside the I32F32 range (|x| >= 2^31)",
        /// Texture width or height was zero.
        ZeroTextureSize => "texture width or height is zero",
        /// More triangles than table entries (entries up to the end were written).
        TableFull => "more triangles than table entries",
    }
}

/// A textured triangle as the table needs it: world positions, UVs and the
/// size of its texture's level 0.
///
/// # Example
/// ```
/// use raymip::{TableError, TexTriangle};
/// let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
/// let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// assert!(TexTriangle::from_f32(p, uv, 256, 256).is_ok());
/// assert_eq!(TexTriangle::from_f32(p, uv, 0, 256), Err(TableError::ZeroTextureSize));
/// let far = [[3e9, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// assert_eq!(TexTriangle::from_f32(far, uv, 8, 8), Err(TableError::OutOfRange));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TexTriangle {
    p: [[Coord; 3]; 3],
    uv: [[TexCoord; 2]; 3],
    width: u32,
    height: u32,
}

impl TexTriangle {
    /// From fixed-point positions (scene units), UVs (texture repeats) and
    /// texture size in texels (each ≥ 1).
    pub fn new(
        p: [[Coord; 3]; 3],
        uv: [[TexCoord; 2]; 3],
        width: u32,
        height: u32,
    ) -> Result<Self, TableError> {
        if width == 0 || height == 0 {
            return Err(TableError::ZeroTextureSize);
        }
        Ok(Self {
            p,
            uv,
            width,
            height,
        })
    }

    /// From `f32` positions and UVs (set-up edge): NaN/inf →
    /// [`TableError::NonFinite`], |x| ≥ 2³¹ → [`TableError::OutOfRange`].
    pub fn from_f32(
        p: [[f32; 3]; 3],
        uv: [[f32; 2]; 3],
        width: u32,
        height: u32,
    ) -> Result<Self, TableError> {
        let conv = |x: f32| -> Result<I32F32, TableError> {
            if !x.is_finite() {
                return Err(TableError::NonFinite);
            }
            I32F32::checked_from_num(x).ok_or(TableError::OutOfRange)
        };
        let mut fp = [[Coord::ZERO; 3]; 3];
        let mut fuv = [[TexCoord::ZERO; 2]; 3];
        for (dst, src) in fp.iter_mut().zip(p.iter()) {
            for (d, &s) in dst.iter_mut().zip(src.iter()) {
                *d = Coord::from_fixed(conv(s)?);
            }
        }
        for (dst, src) in fuv.iter_mut().zip(uv.iter()) {
            for (d, &s) in dst.iter_mut().zip(src.iter()) {
                *d = TexCoord::from_fixed(conv(s)?);
            }
        }
        Self::new(fp, fuv, width, height)
    }

    /// `log2` of twice the world area (`log2 |e₁×e₂|`), or `None` for zero area.
    /// Positions, UVs and texture size (ray-differential set-up).
    #[cfg(feature = "raydiff")]
    pub(crate) fn parts(&self) -> ([[Coord; 3]; 3], [[TexCoord; 2]; 3], u32, u32) {
        (self.p, self.uv, self.width, self.height)
    }

    fn log2_twice_area(&self) -> Option<I16F16> {
        let d = |a: Coord, b: Coord| i128::from(b.to_bits()) - i128::from(a.to_bits());
        let [p0, p1, p2] = self.p;
        let mut e = [[0i128; 3]; 2];
        for k in 0..3 {
            e[0][k] = d(p0[k], p1[k]);
            e[1][k] = d(p0[k], p2[k]);
        }
        // Edges are < 2^64 raw; shift so each is < 2^62 and the products fit.
        let s = shift_to_fit(e.iter().flatten().copied(), 62);
        for v in e.iter_mut().flatten() {
            *v >>= s;
        }
        let [a, b] = e;
        let c = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        // |c| < 2^125; shift so each is < 2^63 and the sum of squares fits.
        let t = shift_to_fit(c.iter().copied(), 63);
        let sum: u128 = c
            .iter()
            .map(|&x| {
                let m = (x.unsigned_abs() >> t) as u64;
                u128::from(m) * u128::from(m)
            })
            .sum();
        if sum == 0 {
            return None;
        }
        // |c|² = sum · 2^(2t) in units of 2^(−2·(64 − 2s)).
        let l = log2_bits_u128(sum, 0);
        let adj = 2 * t as i32 + 4 * s as i32 - 128;
        Some(half(l.saturating_add(int(adj))))
    }

    /// `log2` of twice the UV area in texels (`log2(|uv₁×uv₂|·w·h)`), or
    /// `None` for zero UV area.
    fn log2_twice_texels(&self) -> Option<I16F16> {
        let d = |a: TexCoord, b: TexCoord| i128::from(b.to_bits()) - i128::from(a.to_bits());
        let [q0, q1, q2] = self.uv;
        let mut e = [
            d(q0[0], q1[0]),
            d(q0[1], q1[1]),
            d(q0[0], q2[0]),
            d(q0[1], q2[1]),
        ];
        let s = shift_to_fit(e.iter().copied(), 62);
        for v in e.iter_mut() {
            *v >>= s;
        }
        let c = (e[0] * e[3] - e[1] * e[2]).unsigned_abs();
        if c == 0 {
            return None;
        }
        // c in units of 2^(−2·(32 − s)).
        let l = log2_bits_u128(c, 0).saturating_add(int(2 * s as i32 - 64));
        Some(
            l.saturating_add(log2_u32(self.width))
                .saturating_add(log2_u32(self.height)),
        )
    }
}

/// Right shift that brings the largest magnitude below `2^bits`.
fn shift_to_fit(vals: impl Iterator<Item = i128>, bits: u32) -> u32 {
    let max = vals.map(i128::unsigned_abs).max().unwrap_or(0);
    (128 - max.leading_zeros()).saturating_sub(bits)
}

fn int(n: i32) -> I16F16 {
    I16F16::from_bits(n.clamp(-32768, 32767) << 16)
}

fn half(x: I16F16) -> I16F16 {
    I16F16::from_bits(x.to_bits() >> 1)
}

/// The set-up of a [`Log2Pb`] (the type is a quantity of [`crate::units`]):
/// computing an entry from a triangle and a camera, and the ray-cone
/// constant `Δ` of an entry.
impl Log2Pb {
    /// Computes the entry of one textured triangle (see the module docs).
    #[must_use]
    pub fn compute(tri: &TexTriangle, spread: &PixelSpread) -> Self {
        let Some(la) = tri.log2_twice_area() else {
            return Self::DEGENERATE_GEOMETRY;
        };
        let Some(ln) = tri.log2_twice_texels() else {
            return Self::DEGENERATE_UV;
        };
        // log2 Pb = ½·(log2 2A − log2 2N) − log2 γ
        let v = half(la.saturating_sub(ln)).saturating_sub(spread.log2());
        Self::from_log2(v)
    }

    /// The ray-cone triangle constant `Δ = ½·log2(N/A) = −log2 Pb − log2 γ`
    /// (I16F16, saturating; `None` when untextured). Feature `cone`.
    #[cfg(feature = "cone")]
    #[must_use]
    pub fn delta(self, spread: &PixelSpread) -> Option<Delta> {
        if self.is_untextured() {
            return None;
        }
        Some(Delta::from_fixed(
            self.to_i16f16()
                .saturating_neg()
                .saturating_sub(spread.log2()),
        ))
    }
}

/// What a build or update wrote.
///
/// # Example
/// ```
/// use raymip::setup::table::BuildStats;
/// use raymip::units::{Coord, TexCoord};
/// use raymip::{Log2Pb, PbTable, PixelSpread, TexTriangle};
/// let spread = PixelSpread::from_fov_y(1.0, 240)?;
/// let c = |x: i32| Coord::from_num(x);
/// let t = |x: i32| TexCoord::from_num(x);
/// let uv = [[t(0), t(0)], [t(1), t(0)], [t(0), t(1)]];
/// let p = [[c(0), c(0), c(0)], [c(1), c(0), c(0)], [c(0), c(1), c(0)]];
/// let good = TexTriangle::new(p, uv, 16, 16)?;
/// // Three collinear vertices: zero world area.
/// let line = [[c(0), c(0), c(0)], [c(1), c(0), c(0)], [c(2), c(0), c(0)]];
/// let flat = TexTriangle::new(line, uv, 16, 16)?;
/// // All three UVs equal: zero UV area.
/// let no_uv = TexTriangle::new(p, [[t(0), t(0)]; 3], 16, 16)?;
/// let mut entries = [Log2Pb::UNTEXTURED; 4];
/// let stats = PbTable::new(&mut entries).build([Some(good), Some(flat), Some(no_uv), None], &spread)?;
/// assert_eq!(stats, BuildStats { textured: 1, untextured: 1, degenerate_geometry: 1, degenerate_uv: 1 });
/// assert_eq!(entries[1], Log2Pb::DEGENERATE_GEOMETRY);
/// assert_eq!(entries[2], Log2Pb::DEGENERATE_UV);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildStats {
    /// Entries computed for textured triangles.
    pub textured: u32,
    /// Untextured markers written (no table work).
    pub untextured: u32,
    /// Textured triangles with zero world area.
    pub degenerate_geometry: u32,
    /// Textured triangles with zero UV area.
    pub degenerate_uv: u32,
}

/// The per-triangle table in caller-provided storage (one [`Log2Pb`],
/// 4 bytes, per triangle).
///
/// # Example
/// ```
/// use raymip::{Log2Pb, PbTable, PixelSpread, TexTriangle};
/// let spread = PixelSpread::from_fov_y(60f64.to_radians(), 480)?;
/// let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let tri = TexTriangle::from_f32([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], uv, 64, 64)?;
/// // Caller memory: 4 bytes per triangle, built once at set-up.
/// let mut entries = [Log2Pb::UNTEXTURED; 2];
/// let mut table = PbTable::new(&mut entries);
/// let stats = table.build([Some(tri), None], &spread)?;
/// assert_eq!((stats.textured, stats.untextured), (1, 1));
/// assert_eq!(table.get(1), Some(Log2Pb::UNTEXTURED));
/// assert_eq!(table.get(2), None); // out of range
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct PbTable<'a> {
    entries: &'a mut [Log2Pb],
}

impl<'a> PbTable<'a> {
    /// Wraps caller storage; entries are not touched until `build`.
    pub fn new(entries: &'a mut [Log2Pb]) -> Self {
        Self { entries }
    }

    /// Fills the table from the start: one item per triangle, `None` for an
    /// untextured one. Static scenes build once.
    pub fn build(
        &mut self,
        tris: impl IntoIterator<Item = Option<TexTriangle>>,
        spread: &PixelSpread,
    ) -> Result<BuildStats, TableError> {
        self.update(0, tris, spread)
    }

    /// Recomputes entries `start..start + n` for `n` items (dynamic
    /// triangles); other entries are untouched. Items past the end of the
    /// table give [`TableError::TableFull`] after the ones that fit are written.
    pub fn update(
        &mut self,
        start: usize,
        tris: impl IntoIterator<Item = Option<TexTriangle>>,
        spread: &PixelSpread,
    ) -> Result<BuildStats, TableError> {
        let mut stats = BuildStats::default();
        let mut slots = self.entries.iter_mut().skip(start);
        for tri in tris {
            let slot = slots.next().ok_or(TableError::TableFull)?;
            *slot = match tri {
                None => {
                    stats.untextured += 1;
                    Log2Pb::UNTEXTURED
                }
                Some(t) => {
                    let e = Log2Pb::compute(&t, spread);
                    if e == Log2Pb::DEGENERATE_GEOMETRY {
                        stats.degenerate_geometry += 1;
                    } else if e == Log2Pb::DEGENERATE_UV {
                        stats.degenerate_uv += 1;
                    } else {
                        stats.textured += 1;
                    }
                    e
                }
            };
        }
        Ok(stats)
    }

    /// The entry of triangle `i` (`None` out of range).
    #[inline]
    #[must_use]
    pub fn get(&self, i: usize) -> Option<Log2Pb> {
        self.entries.get(i).copied()
    }

    /// All entries.
    #[must_use]
    pub fn entries(&self) -> &[Log2Pb] {
        self.entries
    }
}

#[cfg(test)]
mod tests {
    use crate::units::{Log2Pb, Spread};
    extern crate std;
    use super::*;
    use fixed::types::I2F30;
    use proptest::prelude::*;

    /// The harness's independent f64 reference of log2 Pb.
    fn reference(p: [[f64; 3]; 3], uv: [[f64; 2]; 3], w: f64, h: f64, gamma: f64) -> f64 {
        raymip_reference::pb::log2_pb_f64(&p, &uv, w, h, gamma)
    }

    fn tri(p: [[f64; 3]; 3], uv: [[f64; 2]; 3], w: u32, h: u32) -> TexTriangle {
        let c = |x: f64| Coord::from_num(x);
        TexTriangle::new(
            p.map(|v| v.map(c)),
            uv.map(|v| v.map(TexCoord::from_num)),
            w,
            h,
        )
        .unwrap()
    }

    fn spread(g: f64) -> PixelSpread {
        PixelSpread::from_angle(Spread::from_num(g)).unwrap()
    }

    #[test]
    fn unit_square_half() {
        // Right triangle with legs 1 covering half a 256x256 texture:
        // A = 0.5, N = 0.5·65536 → log2(A/N) = −16; γ = 2^-10 → log2 Pb = −8 + 10 = 2.
        let t = tri(UNIT_P, UNIT_UV, 256, 256);
        let e = Log2Pb::compute(&t, &spread(1.0 / 1024.0));
        assert_eq!(e.to_i16f16(), I16F16::from_num(2));
        #[cfg(feature = "cone")]
        assert_eq!(e.delta(&spread(1.0 / 1024.0)), Some(Delta::from_num(8)));
    }

    /// The unit right triangle in xy and its UVs.
    const UNIT_P: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    const UNIT_UV: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

    #[test]
    fn degenerate_triangles_get_their_markers() {
        for (name, p, uv, want) in [
            (
                "collinear",
                [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
                UNIT_UV,
                Log2Pb::DEGENERATE_GEOMETRY,
            ),
            (
                "duplicate vertices",
                [[3.0, 1.0, 2.0], [3.0, 1.0, 2.0], [0.0, 1.0, 0.0]],
                UNIT_UV,
                Log2Pb::DEGENERATE_GEOMETRY,
            ),
            (
                "all vertices equal",
                [[5.0; 3]; 3],
                UNIT_UV,
                Log2Pb::DEGENERATE_GEOMETRY,
            ),
            (
                "zero uv area",
                UNIT_P,
                [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]],
                Log2Pb::DEGENERATE_UV,
            ),
        ] {
            let e = Log2Pb::compute(&tri(p, uv, 64, 64), &spread(0.001));
            assert_eq!(e, want, "{name}");
        }
    }

    #[test]
    fn from_f32_rejects_non_finite_out_of_range_and_zero_size() {
        let p = UNIT_P.map(|v| v.map(|x| x as f32));
        let uv = UNIT_UV.map(|v| v.map(|x| x as f32));
        let mut cases = std::vec::Vec::new();
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 3.0e9] {
            let mut q = p;
            q[1][2] = bad;
            let want = if bad.is_finite() {
                TableError::OutOfRange
            } else {
                TableError::NonFinite
            };
            cases.push((q, uv, 8, 8, want));
        }
        let mut uvb = uv;
        uvb[2][0] = f32::NAN;
        cases.push((p, uvb, 8, 8, TableError::NonFinite));
        cases.push((p, uv, 0, 8, TableError::ZeroTextureSize));
        cases.push((p, uv, 8, 0, TableError::ZeroTextureSize));
        for (p, uv, w, h, want) in cases {
            assert_eq!(
                TexTriangle::from_f32(p, uv, w, h),
                Err(want),
                "{p:?} {uv:?} {w}×{h}"
            );
        }
    }

    #[test]
    fn extreme_coordinates_do_not_overflow() {
        // Edges near 2^32 scene units (raw near 2^64): the shift path.
        let big = 2.0e9;
        let p = [[-big, -big, -big], [big, -big, -big], [-big, big, big]];
        let uv = [[-1.0e9, -1.0e9], [1.0e9, -1.0e9], [-1.0e9, 1.0e9]];
        let t = tri(p, uv, 4096, 4096);
        let got = Log2Pb::compute(&t, &spread(0.5))
            .to_i16f16()
            .to_num::<f64>();
        let want = reference(p, uv, 4096.0, 4096.0, I2F30::from_num(0.5).to_num());
        assert!((got - want).abs() <= TABLE_MAX_ERROR, "{got} vs {want}");
        // Tiny triangle: edges of 2^-30 units.
        let e = 2f64.powi(-30);
        let p = [[0.0, 0.0, 0.0], [e, 0.0, 0.0], [0.0, e, 0.0]];
        let uv = [[0.0, 0.0], [e, 0.0], [0.0, e]];
        let t = tri(p, uv, 1, 1);
        let got = Log2Pb::compute(&t, &spread(1.0))
            .to_i16f16()
            .to_num::<f64>();
        let want = reference(p, uv, 1.0, 1.0, 1.0);
        assert!((got - want).abs() <= TABLE_MAX_ERROR, "{got} vs {want}");
    }

    #[test]
    fn build_and_update() {
        let a = tri(UNIT_P, UNIT_UV, 256, 256);
        let s = spread(1.0 / 1024.0);
        let mut store = [Log2Pb::DEGENERATE_UV; 4];
        let mut table = PbTable::new(&mut store);
        let st = table.build([Some(a), None, Some(a)], &s).unwrap();
        assert_eq!((st.textured, st.untextured), (2, 1));
        assert_eq!(table.get(1), Some(Log2Pb::UNTEXTURED));
        assert_eq!(table.get(3), Some(Log2Pb::DEGENERATE_UV), "untouched");
        assert_eq!(table.get(4), None);
        table.update(1, [Some(a)], &s).unwrap();
        assert_eq!(table.get(1), table.get(0));
        assert_eq!(
            table.update(3, [None, None], &s),
            Err(TableError::TableFull)
        );
        assert_eq!(
            table.get(3),
            Some(Log2Pb::UNTEXTURED),
            "what fits is written"
        );
        assert_eq!(table.update(9, [None], &s), Err(TableError::TableFull));
    }

    fn coord() -> impl Strategy<Value = f64> {
        prop_oneof![-1.0e4..1.0e4f64, -1.0..1.0f64, -1.0e-3..1.0e-3f64]
    }

    proptest! {
        #[test]
        fn from_bits_keeps_markers_and_clamps(bits in any::<i32>()) {
            let e = Log2Pb::from_bits(bits);
            let markers = [Log2Pb::UNTEXTURED, Log2Pb::DEGENERATE_GEOMETRY, Log2Pb::DEGENERATE_UV];
            if markers.iter().any(|m| m.to_i16f16().to_bits() == bits) {
                prop_assert_eq!(e.to_i16f16().to_bits(), bits);
            } else {
                let want = i64::from(bits).clamp(-64 << 16, 64 << 16);
                prop_assert_eq!(i64::from(e.to_i16f16().to_bits()), want);
            }
            // Round trip of every stored value.
            prop_assert_eq!(Log2Pb::from_bits(e.to_i16f16().to_bits()), e);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5_000))]
        #[test]
        fn entry_matches_f64(
            p in [[coord(), coord(), coord()], [coord(), coord(), coord()], [coord(), coord(), coord()]],
            uv in [[-300.0..300.0f64, -300.0..300.0f64], [-300.0..300.0f64, -300.0..300.0f64], [-300.0..300.0f64, -300.0..300.0f64]],
            wl in 0u32..13, hl in 0u32..13, wodd in 0u32..3,
            g in 1.0e-5..1.0f64,
        ) {
            let (w, h) = ((1u32 << wl) + wodd, 1u32 << hl);
            // Quantise inputs first so both sides see the same triangle.
            let q = |x: f64| Coord::from_num(x).to_num::<f64>();
            let p = p.map(|v| v.map(q));
            let uv = uv.map(|v| v.map(q));
            let gq = I2F30::from_num(g);
            let want = reference(p, uv, f64::from(w), f64::from(h), gq.to_num());
            let e = Log2Pb::compute(&tri(p, uv, w, h), &PixelSpread::from_angle(Spread::from_fixed(gq)).unwrap());
            if want.is_finite() && want.abs() < 63.9 {
                let got = e.to_i16f16().to_num::<f64>();
                prop_assert!((got - want).abs() <= TABLE_MAX_ERROR,
                    "log2 Pb {} vs f64 {} (error {:e})", got, want, (got - want).abs());
            } else {
                prop_assert!(e == Log2Pb::DEGENERATE_GEOMETRY || e == Log2Pb::DEGENERATE_UV
                    || e == Log2Pb::MIN || e == Log2Pb::MAX, "{:?} for f64 {}", e, want);
            }
        }
    }
}
