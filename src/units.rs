//! The vocabulary: every quantity the API passes, as its own type, and the
//! precision tiers.
//!
//! Each quantity is a `#[repr(transparent)]` newtype over the `fixed` type
//! that stores it, so it costs nothing at run time and has the same layout
//! (a C caller passes its raw bits). Two quantities with the same storage
//! do not mix: a [`Width`] (scene units) does not pass as a [`TexCoord`]
//! (texture repeats), and a [`Lod`] (texture levels) is not a [`GeomLod`]
//! (mesh levels). Within one quantity the arithmetic is the storage
//! type's: `+`, `-`, comparisons, the `saturating_`, `checked_` and
//! `wrapping_` forms, `from_num` / `to_num`, the raw `from_bits` /
//! `to_bits`. Crossing into raw fixed point is explicit
//! (`X::from_fixed`, `x.to_fixed()`); where two quantities combine into a
//! third, the function that does it says so (the cone update
//! [`RayCone::advance`](crate::path::raystack::RayCone::advance): a
//! width plus an angle times a length).
//!
//! | quantity | type | storage | unit | range |
//! |---|---|---|---|---|
//! | path length `Pl`, hit distance `t` | [`PathLength`] | U32F32 | scene units | `[0, 2³²)` |
//! | ray-cone width `w` | [`Width`] | I32F32 | scene units | `[−2³¹, 2³¹)` |
//! | spread angle `γ`, `β` | [`Spread`] | I2F30 | radians | `[−2, 2)` |
//! | unit vector (direction, normal) | [`UnitVec`] | `[I2F30; 3]` | – | `[−2, 2)` per component |
//! | world-space position coordinate | [`Coord`] | I32F32 | scene units | `[−2³¹, 2³¹)` |
//! | texture coordinate `u`, `v` | [`TexCoord`] | I32F32 | texture repeats (1 = the width or height) | `[−2³¹, 2³¹)` |
//! | texture level of detail | [`Lod`] | I8F8 | levels | `[−128, 128)` |
//! | ray-cone triangle constant `Δ` | [`Delta`] | I16F16 | levels | `[−2¹⁵, 2¹⁵)` |
//! | camera-space depth of an instance | [`Depth`] | I32F32 | scene units | `[−2³¹, 2³¹)` |
//! | geometric (mesh) LOD parameter | [`GeomLod`] | U16F16 | mesh levels | `[0, 2¹⁶)` |
//! | geometric LOD bias | [`LodBias`] | I16F16 | mesh levels | `[−2¹⁵, 2¹⁵)` |
//! | geometric LOD transition interval | [`Transition`] | U16F16 | fraction of a level | `[0, 1]` used |
//!
//! The precision tiers are the types [`Accurate`] (the default; bit-identical
//! to the documented bounds on every target) and [`Fast`] (fewer
//! instructions, GPU precision, its own documented bounds), used the same
//! way by both halves: `table_lod::<Fast>` on the lod side,
//! `Cfg<U, V, C, Fast>` on the texture side. [`Precision`] is the tier as
//! a value (tables, the C ABI).

use core::fmt;
use core::ops::{Add, AddAssign, Index, IndexMut, Neg, Sub, SubAssign};

use fixed::traits::{FromFixed, ToFixed};
use fixed::types::{I2F30, I8F8, I16F16, I32F32, U1F31, U16F16, U32F32};

/// The API shared by every quantity newtype: constants, raw bits,
/// conversions and the arithmetic of one quantity with itself.
macro_rules! quantity {
    ($name:ident, $fixed:ty, $bits:ty) => {
        impl $name {
            /// Zero.
            pub const ZERO: Self = Self(<$fixed>::ZERO);
            /// One unit.
            pub const ONE: Self = Self(<$fixed>::ONE);
            /// The largest value.
            pub const MAX: Self = Self(<$fixed>::MAX);
            /// The smallest value.
            pub const MIN: Self = Self(<$fixed>::MIN);
            /// The step: one raw unit.
            pub const DELTA: Self = Self(<$fixed>::DELTA);

            /// The value whose raw bits are `bits`.
            #[inline]
            #[must_use]
            pub const fn from_bits(bits: $bits) -> Self {
                Self(<$fixed>::from_bits(bits))
            }

            /// The raw bits.
            #[inline]
            #[must_use]
            pub const fn to_bits(self) -> $bits {
                self.0.to_bits()
            }

            /// The value of the decimal, binary (`0b`), octal (`0o`) or
            /// hexadecimal (`0x`) literal `src`, rounded to the nearest
            /// step; usable in constants (a literal that does not fit
            /// fails to compile there). As `fixed`'s `lit`.
            #[inline]
            #[must_use]
            #[track_caller]
            pub const fn lit(src: &str) -> Self {
                Self(<$fixed>::lit(src))
            }

            /// The quantity stored in the fixed-point value `v` (same bits).
            #[inline]
            #[must_use]
            pub const fn from_fixed(v: $fixed) -> Self {
                Self(v)
            }

            /// The stored fixed-point value (same bits).
            #[inline]
            #[must_use]
            pub const fn to_fixed(self) -> $fixed {
                self.0
            }

            /// `src` (an integer, float or fixed-point number, in this
            /// quantity's unit) converted as `fixed` converts: a float
            /// rounded to the nearest step (ties to even), a fixed-point
            /// number with more fraction bits truncated towards −∞, an
            /// integer exact. Panics when it does not fit, as `fixed`'s `from_num` (set-up and tests; the
            /// per-hit path uses the checked and saturating forms).
            #[inline]
            #[must_use]
            #[track_caller]
            pub fn from_num<Src: ToFixed>(src: Src) -> Self {
                Self(<$fixed>::from_num(src))
            }

            /// `src` converted as by `from_num` (floats rounded, finer
            /// fixed-point truncated towards −∞), or `None` when it does
            /// not fit (NaN included).
            #[inline]
            #[must_use]
            pub fn checked_from_num<Src: ToFixed>(src: Src) -> Option<Self> {
                match <$fixed>::checked_from_num(src) {
                    Some(v) => Some(Self(v)),
                    None => None,
                }
            }

            /// `src` converted as by `from_num` (floats rounded, finer
            /// fixed-point truncated towards −∞), clamped to the range.
            #[inline]
            #[must_use]
            pub fn saturating_from_num<Src: ToFixed>(src: Src) -> Self {
                Self(<$fixed>::saturating_from_num(src))
            }

            /// `src` converted as by `from_num` (floats rounded, finer
            /// fixed-point truncated towards −∞), wrapped into the range.
            #[inline]
            #[must_use]
            pub fn wrapping_from_num<Src: ToFixed>(src: Src) -> Self {
                Self(<$fixed>::wrapping_from_num(src))
            }

            /// The value as another number type (in this quantity's unit).
            #[inline]
            #[must_use]
            pub fn to_num<Dst: FromFixed>(self) -> Dst {
                self.0.to_num()
            }

            /// `self + rhs`, clamped to the range.
            #[inline]
            #[must_use]
            pub const fn saturating_add(self, rhs: Self) -> Self {
                Self(self.0.saturating_add(rhs.0))
            }

            /// `self − rhs`, clamped to the range.
            #[inline]
            #[must_use]
            pub const fn saturating_sub(self, rhs: Self) -> Self {
                Self(self.0.saturating_sub(rhs.0))
            }

            /// `self + rhs`, or `None` on overflow.
            #[inline]
            #[must_use]
            pub const fn checked_add(self, rhs: Self) -> Option<Self> {
                match self.0.checked_add(rhs.0) {
                    Some(v) => Some(Self(v)),
                    None => None,
                }
            }

            /// `self − rhs`, or `None` on overflow.
            #[inline]
            #[must_use]
            pub const fn checked_sub(self, rhs: Self) -> Option<Self> {
                match self.0.checked_sub(rhs.0) {
                    Some(v) => Some(Self(v)),
                    None => None,
                }
            }

            /// `self + rhs`, wrapped into the range.
            #[inline]
            #[must_use]
            pub const fn wrapping_add(self, rhs: Self) -> Self {
                Self(self.0.wrapping_add(rhs.0))
            }

            /// `self − rhs`, wrapped into the range.
            #[inline]
            #[must_use]
            pub const fn wrapping_sub(self, rhs: Self) -> Self {
                Self(self.0.wrapping_sub(rhs.0))
            }

            /// `self · n` for an integer `n`, clamped to the range.
            #[inline]
            #[must_use]
            pub const fn saturating_mul_int(self, n: $bits) -> Self {
                Self(self.0.saturating_mul_int(n))
            }

            /// The integer part (rounded towards −∞), as this quantity.
            #[inline]
            #[must_use]
            pub const fn int(self) -> Self {
                Self(self.0.int())
            }

            /// The fractional part, `self − self.int()`.
            #[inline]
            #[must_use]
            pub const fn frac(self) -> Self {
                Self(self.0.frac())
            }

            /// Rounded towards −∞.
            #[inline]
            #[must_use]
            pub const fn floor(self) -> Self {
                Self(self.0.floor())
            }

            /// Rounded to the nearest integer, ties away from zero.
            #[inline]
            #[must_use]
            pub const fn round(self) -> Self {
                Self(self.0.round())
            }

            /// True for zero.
            #[inline]
            #[must_use]
            pub const fn is_zero(self) -> bool {
                self.0.is_zero()
            }
        }

        impl Add for $name {
            type Output = Self;
            #[inline]
            fn add(self, rhs: Self) -> Self {
                Self(self.0 + rhs.0)
            }
        }

        impl Sub for $name {
            type Output = Self;
            #[inline]
            fn sub(self, rhs: Self) -> Self {
                Self(self.0 - rhs.0)
            }
        }

        impl AddAssign for $name {
            #[inline]
            fn add_assign(&mut self, rhs: Self) {
                self.0 += rhs.0;
            }
        }

        impl SubAssign for $name {
            #[inline]
            fn sub_assign(&mut self, rhs: Self) {
                self.0 -= rhs.0;
            }
        }

        /// As the stored number (`1.5`, not `Lod(1.5)`), so logs and
        /// reports read the same with the quantity's type.
        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Debug::fmt(&self.0, f)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Display::fmt(&self.0, f)
            }
        }
    };
}

/// The signed quantities add sign operations to [`quantity`].
macro_rules! signed_quantity {
    ($name:ident, $fixed:ty, $bits:ty) => {
        quantity!($name, $fixed, $bits);

        impl $name {
            /// The absolute value (panics in debug builds for `MIN`, as
            /// `fixed`'s `abs`; see [`saturating_abs`](Self::saturating_abs)).
            #[inline]
            #[must_use]
            pub const fn abs(self) -> Self {
                Self(self.0.abs())
            }

            /// The absolute value, `MIN` giving `MAX`.
            #[inline]
            #[must_use]
            pub const fn saturating_abs(self) -> Self {
                Self(self.0.saturating_abs())
            }

            /// `−self`, `MIN` giving `MAX`.
            #[inline]
            #[must_use]
            pub const fn saturating_neg(self) -> Self {
                Self(self.0.saturating_neg())
            }

            /// True below zero.
            #[inline]
            #[must_use]
            pub const fn is_negative(self) -> bool {
                self.0.is_negative()
            }
        }

        impl Neg for $name {
            type Output = Self;
            #[inline]
            fn neg(self) -> Self {
                Self(-self.0)
            }
        }
    };
}

/// The unsigned quantities add the distance between two values.
macro_rules! unsigned_quantity {
    ($name:ident, $fixed:ty, $bits:ty) => {
        quantity!($name, $fixed, $bits);

        impl $name {
            /// `|self − other|`.
            #[inline]
            #[must_use]
            pub const fn abs_diff(self, other: Self) -> Self {
                Self(self.0.abs_diff(other.0))
            }
        }
    };
}

/// Accumulated path length `Pl` or one hit distance `t`: U32F32 scene units
/// (range `[0, 2³²)`, step 2⁻³²). Example: [`PathState`](crate::PathState).
///
/// # Example
/// ```
/// use raymip::PathLength;
/// // 100.5 scene units: integer part in the high 32 bits, 0.5 = 2³¹ in the low.
/// assert_eq!(PathLength::from_num(100.5).to_bits(), (100 << 32) | (1 << 31));
/// // Lengths add saturating: past 2³² − 2⁻³² the sum sticks at the top.
/// assert_eq!(PathLength::MAX.saturating_add(PathLength::ONE), PathLength::MAX);
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct PathLength(U32F32);
unsigned_quantity!(PathLength, U32F32, u64);

/// Ray-cone width: I32F32 scene units (range `[−2³¹, 2³¹)`, step 2⁻³²;
/// signed: a concave surface can make a cone shrink through zero, the lod
/// uses `|w|`). Example: [`RayCone`](crate::path::raystack::RayCone).
///
/// # Example
/// ```
/// use raymip::Width;
/// // A cone 0.25 scene units wide: 0.25 · 2³² in bits.
/// assert_eq!(Width::from_num(0.25).to_bits(), 1 << 30);
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Width(I32F32);
signed_quantity!(Width, I32F32, i64);

/// Ray-cone spread angle: I2F30 radians (range `[−2, 2)`, step 2⁻³⁰).
/// Example: [`RayCone`](crate::path::raystack::RayCone).
///
/// # Example
/// ```
/// use raymip::Spread;
/// // A flat mirror adds no spread (β = 0); 2⁻¹⁰ rad is 2²⁰ in bits.
/// assert_eq!(Spread::ZERO.to_bits(), 0);
/// assert_eq!(Spread::from_num(1.0 / 1024.0).to_bits(), 1 << 20);
/// // Angles of 2 rad or more do not fit.
/// assert!(Spread::checked_from_num(2.0).is_none());
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Spread(I2F30);
signed_quantity!(Spread, I2F30, i32);

/// World-space position coordinate: I32F32 scene units (range `±2³¹`,
/// step 2⁻³²). Example: [`TexTriangle`](crate::TexTriangle).
///
/// # Example
/// ```
/// use raymip::units::Coord;
/// assert_eq!(Coord::from_num(-1.5).to_bits(), -(3 << 31));
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Coord(I32F32);
signed_quantity!(Coord, I32F32, i64);

/// A normalized texture coordinate: I32F32 texture repeats (range
/// `[−2³¹, 2³¹)`, step 2⁻³²). `u = 0` is the left edge, `u = 1` the right
/// edge of every level; texel `i` of a level `w` wide has its centre at
/// `(i + ½)/w`.
///
/// # Example
/// ```
/// use raymip::{Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
/// // A 4×1 texture whose texels are 0, 1, 2, 3.
/// let texels = [0u32, 1, 2, 3];
/// let mut sampler = Sampler::wrap(Pyramid::new(Geometry::new(4, 1, 1)?, &texels)?);
/// let v = TexCoord::from_num(0.5);
/// // Texel 2's centre is (2 + ½)/4 = 0.625; nearest returns texel 2.
/// let u = TexCoord::from_num(0.625);
/// assert_eq!(sampler.sample(u, v, Lod::ZERO, Mode::Nearest), 2);
/// // Wrap: u = 1.625 addresses the same texel.
/// let u = TexCoord::from_num(1.625);
/// assert_eq!(sampler.sample(u, v, Lod::ZERO, Mode::Nearest), 2);
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct TexCoord(I32F32);
signed_quantity!(TexCoord, I32F32, i64);

/// A MIP level of detail in levels: I8F8 (range `[−128, 128)`, step 1/256
/// level). Level `n` is `2ⁿ` times coarser than level 0.
///
/// # Example
/// ```
/// use raymip::lod::table_lod;
/// use raymip::units::Accurate;
/// use raymip::{Lod, Log2Pb, PathLength};
/// // Level 2.5 is 2.5 · 256 = 640 in bits; the step is 1/256 level.
/// assert_eq!(Lod::from_num(2.5).to_bits(), 640);
/// assert_eq!(Lod::DELTA, Lod::from_num(1.0 / 256.0));
/// // Integer part 2, half a level towards level 3.
/// assert_eq!(Lod::from_num(2.5).frac(), Lod::from_num(0.5));
/// // The table method gives lod = log2 Pl − log2 Pb: Pl = 8, log2 Pb = 1 → 3 − 1 = 2.
/// let pb = Log2Pb::from_bits(1 << 16);
/// let lod = table_lod::<Accurate>(PathLength::from_num(8), pb).ok_or("untextured")?;
/// assert!((lod.to_num::<f64>() - 2.0).abs() <= raymip::lod::LOD_MAX_ERROR);
/// # Ok::<(), &str>(())
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Lod(I8F8);
signed_quantity!(Lod, I8F8, i16);

/// The ray-cone triangle constant `Δ = ½·log2(N/A)` (levels, I16F16;
/// see [`Log2Pb::delta`](crate::Log2Pb::delta)), the cone method's
/// per-triangle input.
///
/// # Example
/// ```
/// use raymip::{Delta, Log2Pb, PixelSpread, TexTriangle};
/// use raymip::setup::table::TABLE_MAX_ERROR;
/// let spread = PixelSpread::from_fov_y(60f64.to_radians(), 480)?;
/// // World area A = ½·2·2 = 2; UV area ½ on a 64×64 texture: N = 2048
/// // texels; Δ = ½·log2(N/A) = ½·log2 1024 = 5 levels (no camera term).
/// let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
/// let tri = TexTriangle::from_f32(p, [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], 64, 64)?;
/// let delta: Delta = Log2Pb::compute(&tri, &spread).delta(&spread).ok_or("textured")?;
/// assert!((delta - Delta::from_num(5)).abs().to_num::<f64>() <= TABLE_MAX_ERROR);
/// assert_eq!(Log2Pb::UNTEXTURED.delta(&spread), None);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Delta(I16F16);
signed_quantity!(Delta, I16F16, i32);

/// Camera-space depth of an instance (its reference point): I32F32 scene
/// units. Example: [`Selector`](crate::geomlod::Selector).
///
/// # Example
/// ```
/// use raymip::units::Depth;
/// assert_eq!(Depth::from_num(2).to_bits(), 2 << 32);
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Depth(I32F32);
signed_quantity!(Depth, I32F32, i64);

/// Geometric (mesh) LOD parameter `l`: U16F16 mesh levels, in
/// `[0, L − 1]` for a mesh of `L` LODs. Example:
/// [`Selector`](crate::geomlod::Selector).
///
/// # Example
/// ```
/// use raymip::units::GeomLod;
/// assert_eq!(GeomLod::from_num(1.5).to_bits(), 3 << 15);
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct GeomLod(U16F16);
unsigned_quantity!(GeomLod, U16F16, u32);

/// Geometric LOD bias: I16F16 mesh levels (added before clamping). Example:
/// [`Selector`](crate::geomlod::Selector).
///
/// # Example
/// ```
/// use raymip::units::LodBias;
/// assert_eq!(LodBias::from_num(-0.5).to_bits(), -(1 << 15));
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct LodBias(I16F16);
signed_quantity!(LodBias, I16F16, i32);

/// Geometric LOD transition interval `t`: U16F16, the fraction of a level
/// in `[0, 1]` over which two LODs cross-dissolve (0 = a discrete step, 1 =
/// the whole interval). Example: [`Selector`](crate::geomlod::Selector).
///
/// # Example
/// ```
/// use raymip::units::Transition;
/// assert_eq!(Transition::from_num(0.25).to_bits(), 1 << 14);
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Transition(U16F16);
unsigned_quantity!(Transition, U16F16, u32);

/// One table entry: `log2 Pb` in I16F16 (log2 of scene units), limited to
/// `[−64, 64]` (Pb from 5·10⁻²⁰ to 1.8·10¹⁹ scene units), or one of three
/// markers. The limit keeps `log2 Pl − log2 Pb` inside the [`Lod`] range
/// without saturating arithmetic on the per-hit path. Computed at set-up
/// by [`Log2Pb::compute`] ([`crate::setup::table`]), stored in a
/// [`PbTable`](crate::PbTable), read per hit by
/// [`table_lod`](crate::lod::table_lod).
///
/// # Example
/// ```
/// use raymip::lod::table_lod;
/// use raymip::units::Accurate;
/// use raymip::{Log2Pb, PathLength};
/// // Entries round-trip through their raw bits (C tables, flash images).
/// let e = Log2Pb::from_bits(-3 << 16); // log2 Pb = −3: Pb = 1/8 scene unit
/// assert_eq!(Log2Pb::from_bits(e.to_bits()), e);
/// // lod = log2 Pl − log2 Pb: at Pl = 1, three levels.
/// assert_eq!(table_lod::<Accurate>(PathLength::ONE, e).map(|l| l.to_num::<f64>()), Some(3.0));
/// // An untextured triangle has no lod.
/// assert_eq!(table_lod::<Accurate>(PathLength::ONE, Log2Pb::UNTEXTURED), None);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Log2Pb(I16F16);

impl Log2Pb {
    /// Marker for an untextured triangle.
    pub const UNTEXTURED: Self = Self(I16F16::MIN);
    /// Zero world area: `Pb = 0`, stored as `log2 Pb = −95`: every lod is
    /// ≥ 63, so the coarsest stored level is used.
    pub const DEGENERATE_GEOMETRY: Self = Self(I16F16::from_bits(-95 << 16));
    /// Zero UV area: `Pb = ∞`, stored as `log2 Pb = +95`: every lod is
    /// ≤ −63, so level 0 is used.
    pub const DEGENERATE_UV: Self = Self(I16F16::from_bits(95 << 16));
    /// Smallest finite entry: −64.
    pub const MIN: Self = Self(I16F16::from_bits(-64 << 16));
    /// Largest finite entry: +64.
    pub const MAX: Self = Self(I16F16::from_bits(64 << 16));

    /// An entry from a given `log2 Pb`, clamped to [`Log2Pb::MIN`]`..=`[`Log2Pb::MAX`].
    #[must_use]
    pub fn from_log2(v: I16F16) -> Self {
        Self(v.clamp(Self::MIN.0, Self::MAX.0))
    }

    /// An entry from raw I16F16 bits as stored by [`Log2Pb::to_bits`]
    /// (C tables, `static` data): the three markers are kept, any other
    /// value is clamped to [`Log2Pb::MIN`]`..=`[`Log2Pb::MAX`]. Never panics.
    #[must_use]
    pub const fn from_bits(bits: i32) -> Self {
        let markers = [
            Self::UNTEXTURED.0.to_bits(),
            Self::DEGENERATE_GEOMETRY.0.to_bits(),
            Self::DEGENERATE_UV.0.to_bits(),
        ];
        if bits == markers[0] || bits == markers[1] || bits == markers[2] {
            return Self(I16F16::from_bits(bits));
        }
        let (lo, hi) = (Self::MIN.0.to_bits(), Self::MAX.0.to_bits());
        let v = if bits < lo {
            lo
        } else if bits > hi {
            hi
        } else {
            bits
        };
        Self(I16F16::from_bits(v))
    }

    /// The raw value (markers included).
    #[must_use]
    pub const fn to_i16f16(self) -> I16F16 {
        self.0
    }

    /// The raw I16F16 bits (markers included): the inverse of
    /// [`Log2Pb::from_bits`] for every entry this type holds.
    #[must_use]
    pub const fn to_bits(self) -> i32 {
        self.0.to_bits()
    }

    /// True for [`Log2Pb::UNTEXTURED`].
    #[must_use]
    pub const fn is_untextured(self) -> bool {
        self.0.to_bits() == i32::MIN
    }
}

/// A pixel's footprint: the two axis vectors in normalized texture
/// coordinates (change of `(u, v)` per pixel step in x and in y). Any
/// values are accepted (huge ones saturate).
///
/// # Example
/// ```
/// use raymip::texture::sampler::aniso::{Probes, probes};
/// use raymip::units::Footprint;
/// use raymip::texture::storage::mip::pyramid_len;
/// use raymip::texture::SamplerDesc;
/// use raymip::{Geometry, Lod, Pyramid, Sampler, SamplerState, TexCoord};
/// let t = |texels: f64| TexCoord::from_num(texels / 256.0); // on a 256×256 texture
/// // A pixel 16 texels long along u and 2 wide along v: ratio 8.
/// let fp = Footprint { x: [t(16.0), t(0.0)], y: [t(0.0), t(2.0)] };
/// // 8 probes, lod log2 2 = 1, spaced 16/8 = 2 texels, the first at
/// // t₀·a = (1 − 8)/16 · 16 = −7 texels from the sample point.
/// let expected = Probes { count: 8, lod: Lod::ONE, first: [t(-7.0), t(0.0)], step: [t(2.0), t(0.0)] };
/// assert_eq!(probes(&fp, 256, 256, 16), expected);
/// // At most 4 probes: the minor axis widens to 16/4 = 4 texels, lod 2.
/// let capped = probes(&fp, 256, 256, 4);
/// assert_eq!((capped.count, capped.lod), (4, Lod::from_num(2)));
/// // Sampling: the mean of the probes of a uniform texture is its colour.
/// let texels = [0xFF20_4080u32; pyramid_len(4, 4, 3)];
/// let state = SamplerState::new(SamplerDesc { max_anisotropy: 4, ..SamplerDesc::default() })?;
/// let pyramid = Pyramid::new(Geometry::new(4, 4, 3)?, &texels)?;
/// let mut sampler: Sampler<_> = Sampler::with_state(pyramid, state)?; // wrap, linear, ACCURATE
/// let half = TexCoord::from_num(0.5);
/// assert_eq!(sampler.sample_aniso(half, half, &fp), 0xFF20_4080);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Footprint {
    /// `(du/dx, dv/dx)`.
    pub x: [TexCoord; 2],
    /// `(du/dy, dv/dy)`.
    pub y: [TexCoord; 2],
}

/// A unit vector (ray direction, surface normal): three I2F30 components
/// (range `[−2, 2)` per component, step 2⁻³⁰); `v[k]` reads component
/// `k`. Used by the ray differentials and the environment map.
///
/// # Example
/// ```
/// use fixed::types::I2F30;
/// use raymip::units::UnitVec;
/// let z = UnitVec::new([I2F30::ZERO, I2F30::ZERO, I2F30::ONE]);
/// assert_eq!(z[2], I2F30::ONE);
/// assert_eq!(UnitVec::from_f64([0.0, 0.0, -1.0]), Some(-z));
/// ```
#[derive(Clone, Copy, Default, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub struct UnitVec(pub [I2F30; 3]);

/// Smallest cosine between unit vectors the lods use: the clamp of `|n·d|`
/// in the cone lod's normal term, and of `|D·n|` and `cos θₜ` in the ray
/// differentials' transfer and refraction: 2⁻¹⁶ (U1F31 raw `1 << 15`).
pub const MIN_COS: U1F31 = U1F31::from_bits(1 << 15);

/// As the component array.
impl fmt::Debug for UnitVec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.0, f)
    }
}

impl UnitVec {
    /// The vector with components `v`.
    #[inline]
    #[must_use]
    pub const fn new(v: [I2F30; 3]) -> Self {
        Self(v)
    }

    /// The components.
    #[inline]
    #[must_use]
    pub const fn to_array(self) -> [I2F30; 3] {
        self.0
    }

    /// The components mapped by `f` (for example to `f64`).
    #[inline]
    #[must_use]
    pub fn map<U>(self, f: impl FnMut(I2F30) -> U) -> [U; 3] {
        self.0.map(f)
    }

    /// `v` rounded to I2F30 per component, `None` when one does not fit
    /// (`|v[k]| ≥ 2` or NaN). Set-up and tests.
    #[must_use]
    pub fn from_f64(v: [f64; 3]) -> Option<Self> {
        Some(Self([
            I2F30::checked_from_num(v[0])?,
            I2F30::checked_from_num(v[1])?,
            I2F30::checked_from_num(v[2])?,
        ]))
    }
}

impl Index<usize> for UnitVec {
    type Output = I2F30;
    #[inline]
    fn index(&self, k: usize) -> &I2F30 {
        &self.0[k]
    }
}

impl IndexMut<usize> for UnitVec {
    #[inline]
    fn index_mut(&mut self, k: usize) -> &mut I2F30 {
        &mut self.0[k]
    }
}

impl Neg for UnitVec {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self(self.0.map(|c| -c))
    }
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Accurate {}
    impl Sealed for super::Fast {}
}

/// Precision tier ACCURATE (the default): each stage's documented
/// bound with its full arithmetic (the 64-entry interpolated logarithm of
/// the lods, 12-bit position weights in the filters), bit-identical on
/// every target.
///
/// Example: [`Tier`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Accurate;

/// Precision tier FAST: fewer instructions per hit at GPU precision (the
/// 1024-entry logarithm without interpolation in the lods, D3D11's 8
/// sub-texel and 8 lod fraction bits in the filters), each stage with its
/// own documented, f64-tested bound; bit-identical on every target too.
///
/// Example: [`Tier`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fast;

/// A precision tier, as a type: [`Accurate`] or [`Fast`] (sealed). Every
/// per-hit stage with two tiers takes it as a type parameter.
///
/// # Example
/// ```
/// use raymip::lod::table_lod;
/// use raymip::units::{Accurate, Fast, Precision, Tier};
/// use raymip::{Log2Pb, PathLength};
/// assert_eq!(Fast::PRECISION, Precision::Fast);
/// let pb = Log2Pb::from_bits(-3 << 16);
/// let acc = table_lod::<Accurate>(PathLength::from_num(1.7), pb).ok_or("untextured")?;
/// let fast = table_lod::<Fast>(PathLength::from_num(1.7), pb).ok_or("untextured")?;
/// // Both within 2⁻⁸ level of log2(1.7·8) = 3.766; here one step apart.
/// assert!((acc - fast).abs().to_bits() <= 1);
/// # Ok::<(), &str>(())
/// ```
pub trait Tier: sealed::Sealed + Copy + Default + fmt::Debug + 'static {
    /// The tier as a value.
    const PRECISION: Precision;
}

impl Tier for Accurate {
    const PRECISION: Precision = Precision::Accurate;
}

impl Tier for Fast {
    const PRECISION: Precision = Precision::Fast;
}

/// The precision tier as a value (run-time tables, the C ABI).
///
/// Example: [`Tier`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Precision {
    /// [`Accurate`].
    #[default]
    Accurate = 0,
    /// [`Fast`].
    Fast = 1,
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// Each of the three markers survives `from_bits` (they lie outside the
    /// clamp range, so a lost marker would be clamped to `MIN` or `MAX`).
    #[test]
    fn from_bits_keeps_each_marker() {
        for m in [
            Log2Pb::UNTEXTURED,
            Log2Pb::DEGENERATE_GEOMETRY,
            Log2Pb::DEGENERATE_UV,
        ] {
            assert_eq!(Log2Pb::from_bits(m.to_bits()), m);
        }
    }

    /// A unit vector prints as its component array.
    #[test]
    fn unit_vec_debug_is_the_components() {
        let c = [
            I2F30::ZERO,
            I2F30::from_bits(1 << 29),
            I2F30::from_bits(-1 << 30),
        ];
        assert_eq!(std::format!("{:?}", UnitVec::new(c)), std::format!("{c:?}"));
    }
}
