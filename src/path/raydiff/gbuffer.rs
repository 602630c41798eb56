//! G-buffer ray differentials ("RayDiffs GB"): a first hit's differentials
//! from its neighbouring pixels' first hits.
//!
//! The first hit's position and normal differentials come from the
//! neighbouring pixels' first hits instead of a transfer, the direction
//! differentials from the camera ([`super::RayDiff::primary`]). Per axis
//! the side whose hit distance differs less from the centre's is taken (the
//! neighbour across a silhouette is the one with the larger `|Δt|`): `∂P/∂x
//! = P₊ − P` or `P − P₋`, the same for the normal. A pixel without a
//! neighbour hit on either side of an axis has no differential in that axis
//! (zero).
//!
//! The G-buffer holds positions and distances as 32-bit integers in units
//! of `2^scale` scene units, one `scale` for the whole buffer (chosen at
//! set-up from the scene's extent, the largest `|coordinate|` below 2³⁰
//! units so that the difference of two positions fits), and unit normals
//! in I2F30: a differential is one 32-bit subtraction per component, exact.

use super::{Bfp3, Bfp3x2, DirDiff, EXP_MAX, EXP_MIN, PosDiff, RayDiff, UnitVec};

/// One pixel's first hit in the G-buffer: position and hit distance in
/// units of the buffer's `2^scale` scene units (positions below `2³⁰` in
/// magnitude), unit shading normal.
///
/// # Example
/// ```
/// use fixed::types::I2F30;
/// use raymip::path::raydiff::gbuffer::{GSample, first_hit};
/// use raymip::path::raydiff::RayDiff;
/// // A buffer at 2⁻²⁰ scene units: positions are x·2²⁰.
/// let scale = -20;
/// let q = |x: f64, y: f64| [(x * 1048576.0) as i32, (y * 1048576.0) as i32, -100 << 20];
/// let n = raymip::units::UnitVec([I2F30::ZERO, I2F30::ZERO, I2F30::ONE]);
/// let t = 100 << 20;
/// // The centre pixel's first hit and its neighbours' on the same wall,
/// // one eighth of a scene unit apart; the pixel above has no hit.
/// let centre = GSample { p: q(0.0, 0.0), n, t };
/// let (left, right) = (GSample { p: q(-0.125, 0.0), n, t }, GSample { p: q(0.125, 0.0), n, t });
/// let down = GSample { p: q(0.0, -0.125), n, t };
/// let mut diff = RayDiff::ZERO; // the camera's differentials of the pixel
/// let sides =
///     first_hit(&mut diff, &centre, [Some(&left), Some(&right), None, Some(&down)], scale);
/// // ∂P/∂x = P₊ − P = right − centre; in y (rows grow downwards) the
/// // one side there is, P₊ = down: ∂P/∂y = down − centre.
/// let v = |(m, e): ([i32; 3], i32)| m.map(|x| f64::from(x) * f64::from(e).exp2());
/// assert_eq!(v(diff.dox().parts()), [0.125, 0.0, 0.0]);
/// assert_eq!(v(diff.doy().parts()), [0.0, -0.125, 0.0]);
/// // One normal everywhere: no normal differentials (for a bounce).
/// let [dnx, _] = sides.normal_diffs();
/// assert_eq!(v(dnx.parts()), [0.0; 3]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct GSample {
    /// Hit position (`2^scale` scene units).
    pub p: [i32; 3],
    /// Unit shading normal.
    pub n: UnitVec,
    /// Hit distance from the camera (`2^scale` scene units).
    pub t: u32,
}

/// Differentials of one axis from the centre `c` and its neighbours
/// `minus`, `plus` (`None`: no hit there) of a buffer at `2^scale` scene
/// units: `(∂P, ∂n)` of the side with the smaller `|t − t_c|` (ties:
/// `plus`), zero when both are missing. Exact unless a position
/// difference leaves `i32` (positions beyond the documented `2³⁰`: it then
/// wraps) or two normals differ by 2 (saturated). Never panics.
#[must_use]
pub fn axis(
    c: &GSample,
    minus: Option<&GSample>,
    plus: Option<&GSample>,
    scale: i32,
) -> (PosDiff, DirDiff) {
    let (a, b) = pair(c, minus, plus);
    (PosDiff(pos_diff(a, b, scale)), DirDiff(normal_diff(a, b)))
}

/// The two samples whose difference is the axis's differential (`a − b`):
/// `(plus, c)` or `(c, minus)`, the side with the smaller `|t − t_c|`
/// (ties: `plus`); `(c, c)` when both are missing (a zero difference, so
/// the differentials are zero without a test of their own).
#[inline(always)]
fn pair<'a>(
    c: &'a GSample,
    minus: Option<&'a GSample>,
    plus: Option<&'a GSample>,
) -> (&'a GSample, &'a GSample) {
    let dt = |s: &GSample| s.t.abs_diff(c.t);
    match (minus, plus) {
        (Some(m), Some(p)) if dt(m) < dt(p) => (c, m),
        (_, Some(p)) => (p, c),
        (Some(m), None) => (c, m),
        (None, None) => (c, c),
    }
}

/// `a.p − b.p` in units of the buffer (wrapping beyond the documented
/// positions).
#[inline(always)]
fn pos_delta(a: &GSample, b: &GSample) -> [i32; 3] {
    core::array::from_fn(|k| a.p[k].wrapping_sub(b.p[k]))
}

/// `scale` clamped to `[EXP_MIN + 31, EXP_MAX]` = `[−16353, 16383]` (far
/// beyond every scene): there no normalised exponent leaves the
/// representable range, so no clamp is needed after the normalisation.
#[inline(always)]
fn unit_exponent(scale: i32) -> i32 {
    scale.clamp(EXP_MIN + 31, EXP_MAX)
}

/// `a.p − b.p` at `2^scale`, normalised.
#[inline(always)]
fn pos_diff(a: &GSample, b: &GSample, scale: i32) -> Bfp3 {
    Bfp3::new_in_range(pos_delta(a, b), unit_exponent(scale))
}

/// `a.n − b.n` in I2F30 (saturated at ±2).
#[inline(always)]
fn normal_diff(a: &GSample, b: &GSample) -> Bfp3 {
    let dn = core::array::from_fn(|k| a.n[k].to_bits().saturating_sub(b.n[k].to_bits()));
    Bfp3::new_in_range(dn, -30)
}

/// The neighbours a first hit's differentials are taken from
/// ([`first_hit`]): per axis the two samples whose difference is the
/// differential (`a − b`, see [`axis`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GSides<'a> {
    x: (&'a GSample, &'a GSample),
    y: (&'a GSample, &'a GSample),
}

impl GSides<'_> {
    /// The normal differentials `[∂n/∂x, ∂n/∂y]` of the first hit (exact,
    /// as [`axis`]), what [`RayDiff::reflect`] and [`RayDiff::refract`]
    /// take: needed only for a reflected or refracted continuation, not
    /// for the hit's footprint. Per bounce; never panics.
    #[must_use]
    #[inline]
    pub fn normal_diffs(&self) -> [DirDiff; 2] {
        [self.x, self.y].map(|(a, b)| DirDiff(normal_diff(a, b)))
    }
}

/// The first hit's differential state from the G-buffer (positions at
/// `2^scale` scene units), in place: `s` holds the camera's differentials
/// of the pixel ([`RayDiff::primary`]); its `∂D` is kept and its `∂O` (at
/// the hit, no transfer needed) set from [`axis`] in x (`left`, `right`)
/// and y (`up`, `down`): all a textured hit's footprint needs. Returns
/// the chosen sides, whose [`GSides::normal_diffs`] a reflection or
/// refraction at the hit takes. Per first hit; never panics.
#[inline]
pub fn first_hit<'a>(
    s: &mut RayDiff,
    c: &'a GSample,
    [left, right, up, down]: [Option<&'a GSample>; 4],
    scale: i32,
) -> GSides<'a> {
    // Both position differentials exact at 2^scale: one normalisation for
    // the pair.
    let (x, y) = (pair(c, left, right), pair(c, up, down));
    s.set_pair(
        0,
        Bfp3x2::new_in_range(
            [pos_delta(x.0, x.1), pos_delta(y.0, y.1)],
            unit_exponent(scale),
        ),
    );
    GSides { x, y }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixed::types::I2F30;

    fn sample(p: [i32; 3], n: [i32; 3], t: u32) -> GSample {
        GSample {
            p,
            n: UnitVec(n.map(I2F30::from_bits)),
            t,
        }
    }

    fn value(m: [i32; 3], e: i32) -> [f64; 3] {
        m.map(|x| f64::from(x) * f64::from(e).exp2())
    }

    #[test]
    fn the_side_with_the_smaller_distance_step() {
        let one = 1 << 30;
        let c = sample([0, 0, 0], [0, 0, one], 100);
        // |Δt| = 10, 3, 10 (a tie with `m`) and 20.
        let m = sample([-4, 0, 0], [1 << 20, 0, one], 90);
        let p = sample([0, 6, 0], [0, 1 << 21, one], 103);
        let tie = sample([0, 0, 8], [0, -(1 << 22), one], 110);
        let far = sample([0, 0, 2], [0, 0, one], 120);
        let pos = |r: (PosDiff, DirDiff)| {
            let (m, e) = r.0.parts();
            value(m, e)
        };
        let nrm = |r: (PosDiff, DirDiff)| {
            let (m, e) = r.1.parts();
            value(m, e)
        };
        // `plus` nearer: P₊ − P, n₊ − n.
        let r = axis(&c, Some(&m), Some(&p), 0);
        assert_eq!(pos(r), [0.0, 6.0, 0.0]);
        assert_eq!(nrm(r), [0.0, 1.0 / 512.0, 0.0]);
        // `minus` nearer: P − P₋, n − n₋.
        let r = axis(&c, Some(&m), Some(&far), 0);
        assert_eq!(pos(r), [4.0, 0.0, 0.0]);
        assert_eq!(nrm(r), [-1.0 / 1024.0, 0.0, 0.0]);
        // A tie: `plus`.
        let r = axis(&c, Some(&m), Some(&tie), 0);
        assert_eq!(pos(r), [0.0, 0.0, 8.0]);
        assert_eq!(nrm(r), [0.0, -1.0 / 256.0, 0.0]);
        // One side only, or none.
        assert_eq!(pos(axis(&c, Some(&m), None, 0)), [4.0, 0.0, 0.0]);
        assert_eq!(pos(axis(&c, None, Some(&m), 0)), [-4.0, 0.0, 0.0]);
        assert_eq!(axis(&c, None, None, 0), (PosDiff::ZERO, DirDiff::ZERO));
        // The first hit: the same choice per axis, positions at 2^scale
        // stored in the state (its ∂D kept), normals returned.
        let dd = DirDiff::new([1, 2, 3], -20);
        let mut s = RayDiff::new(PosDiff::ZERO, PosDiff::ZERO, dd, dd);
        let [nx, ny] =
            first_hit(&mut s, &c, [Some(&m), Some(&p), Some(&far), Some(&m)], -2).normal_diffs();
        assert_eq!(s.dox(), axis(&c, Some(&m), Some(&p), -2).0);
        assert_eq!(s.doy(), axis(&c, Some(&far), Some(&m), -2).0);
        assert_eq!(value(s.dox().parts().0, s.dox().parts().1), [0.0, 1.5, 0.0]);
        assert_eq!(
            value(s.doy().parts().0, s.doy().parts().1),
            [-1.0, 0.0, 0.0]
        );
        assert_eq!((s.ddx(), s.ddy()), (dd, dd));
        assert_eq!(nx, axis(&c, Some(&m), Some(&p), 0).1);
        assert_eq!(ny, axis(&c, Some(&far), Some(&m), 0).1);
        assert_ne!(nx, DirDiff::ZERO);
        // No neighbour in y: no differential there.
        let [_, ny] = first_hit(&mut s, &c, [None, Some(&p), None, None], -2).normal_diffs();
        assert_eq!((s.doy(), ny), (PosDiff::ZERO, DirDiff::ZERO));
    }

    /// The buffer's scale is clamped to `[EXP_MIN + 31, EXP_MAX]`: a unit
    /// difference at the lowest scale normalises to `2³⁰·2^(EXP_MIN + 1)`,
    /// the largest mantissa at the highest keeps `EXP_MAX`; zero stays the
    /// canonical zero at every scale.
    #[test]
    fn scale_clamped_to_its_range() {
        let one = 1 << 30;
        let c = sample([0, 0, 0], [0, 0, one], 100);
        let m = sample([-1, 0, 0], [0, 0, one], 100);
        let big = sample([0, -one, 0], [0, 0, one], 100);
        for low in [i32::MIN, EXP_MIN - 1, EXP_MIN, EXP_MIN + 31] {
            assert_eq!(
                axis(&c, Some(&m), None, low).0.parts(),
                ([one, 0, 0], EXP_MIN + 1)
            );
        }
        assert_eq!(
            axis(&c, Some(&m), None, EXP_MIN + 32).0.parts(),
            ([one, 0, 0], EXP_MIN + 2)
        );
        for high in [EXP_MAX, EXP_MAX + 1, i32::MAX] {
            assert_eq!(
                axis(&c, Some(&big), None, high).0.parts(),
                ([0, one, 0], EXP_MAX)
            );
        }
        assert_eq!(
            axis(&c, Some(&big), None, EXP_MAX - 1).0.parts(),
            ([0, one, 0], EXP_MAX - 1)
        );
        for scale in [i32::MIN, 0, i32::MAX] {
            assert_eq!(axis(&c, Some(&c), None, scale).0, PosDiff::ZERO);
        }
    }
}
