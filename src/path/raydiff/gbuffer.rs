//! G-buffer ray differentials ("RayDiffs GB"): the first hit's position
//! and normal differentials from the neighbouring pixels' first hits
//! instead of a transfer, the direction differentials from the camera
//! ([`super::RayDiff::primary`]). Per axis the side whose hit distance
//! differs less from the centre's is taken (the neighbour across a
//! silhouette is the one with the larger `|Δt|`): `∂P/∂x = P₊ − P` or
//! `P − P₋`, the same for the normal. A pixel without a neighbour hit on
//! either side of an axis has no differential in that axis (zero).

use fixed::types::I2F30;

use super::{DirDiff, PosDiff, RayDiff, sat32, sat64};
use crate::units::{PathLength, UnitVec};

/// One pixel's first hit in the G-buffer: position (scene units, I32F32
/// as [`PosDiff`]), unit shading normal and hit distance.
///
/// # Example
/// ```
/// use raymip::PathLength;
/// use raymip::path::raydiff::gbuffer::{GSample, first_hit};
/// use raymip::path::raydiff::{DirDiff, PosDiff, RayDiff};
/// use raymip::units::UnitVec;
/// let q = |x: f64, y: f64| [PosDiff::from_num(x), PosDiff::from_num(y), PosDiff::from_num(-100)];
/// let n = UnitVec::new([DirDiff::ZERO, DirDiff::ZERO, DirDiff::ONE]);
/// let t = PathLength::from_num(100);
/// // The centre pixel's first hit and its neighbours' on the same wall,
/// // one eighth of a scene unit apart; the pixel above has no hit.
/// let centre = GSample { p: q(0.0, 0.0), n, t };
/// let (left, right) = (GSample { p: q(-0.125, 0.0), n, t }, GSample { p: q(0.125, 0.0), n, t });
/// let down = GSample { p: q(0.0, -0.125), n, t };
/// let (diff, [dndx, dndy], sat) =
///     first_hit(&RayDiff::ZERO, &centre, [Some(&left), Some(&right), None, Some(&down)]);
/// // ∂P/∂x = P₊ − P = right − centre; in y (rows grow downwards) the
/// // one side there is, P₊ = down: ∂P/∂y = down − centre.
/// assert_eq!(diff.dodx, [PosDiff::from_num(0.125), PosDiff::ZERO, PosDiff::ZERO]);
/// assert_eq!(diff.dody, [PosDiff::ZERO, PosDiff::from_num(-0.125), PosDiff::ZERO]);
/// // One normal everywhere: no normal differentials; nothing saturated.
/// assert_eq!((dndx, dndy, sat), ([DirDiff::ZERO; 3], [DirDiff::ZERO; 3], false));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct GSample {
    /// Hit position (scene units).
    pub p: [PosDiff; 3],
    /// Unit shading normal.
    pub n: UnitVec,
    /// Hit distance from the camera.
    pub t: PathLength,
}

/// Differentials of one axis from the centre `c` and its neighbours
/// `minus`, `plus` (`None`: no hit there): `(∂P, ∂n)` of the side with the
/// smaller `|t − t_c|` (ties: `plus`), saturating (flag); zero when both
/// are missing. Never panics.
#[must_use]
pub fn axis(
    c: &GSample,
    minus: Option<&GSample>,
    plus: Option<&GSample>,
) -> ([PosDiff; 3], [DirDiff; 3], bool) {
    let dt = |s: &GSample| s.t.abs_diff(c.t);
    let (a, b) = match (minus, plus) {
        (Some(m), Some(p)) if dt(m) < dt(p) => (c, m),
        (_, Some(p)) => (p, c),
        (Some(m), None) => (c, m),
        (None, None) => return ([PosDiff::ZERO; 3], [DirDiff::ZERO; 3], false),
    };
    let mut sat = false;
    let dp = core::array::from_fn(|k| {
        PosDiff::from_bits(sat64(
            i128::from(a.p[k].to_bits()) - i128::from(b.p[k].to_bits()),
            &mut sat,
        ))
    });
    let dn = core::array::from_fn(|k| {
        I2F30::from_bits(sat32(
            i128::from(a.n[k].to_bits()) - i128::from(b.n[k].to_bits()),
            &mut sat,
        ))
    });
    (dp, dn, sat)
}

/// The first hit's differential state from the G-buffer: `∂O` (at the
/// hit, no transfer needed) from [`axis`] in x (`left`, `right`) and y
/// (`up`, `down`), `∂D` from the camera's `primary`; also the normal
/// differentials `(∂n/∂x, ∂n/∂y)` that [`RayDiff::reflect`] and
/// [`RayDiff::refract`] take, and the saturation flag.
#[must_use]
pub fn first_hit(
    primary: &RayDiff,
    c: &GSample,
    [left, right, up, down]: [Option<&GSample>; 4],
) -> (RayDiff, [[DirDiff; 3]; 2], bool) {
    let (dodx, dndx, sx) = axis(c, left, right);
    let (dody, dndy, sy) = axis(c, up, down);
    (
        RayDiff {
            dodx,
            dody,
            ..*primary
        },
        [dndx, dndy],
        sx | sy,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(x: f64, t: f64) -> GSample {
        GSample {
            p: [x, 0.0, 0.0].map(PosDiff::from_num),
            n: UnitVec([0.0, x / 8.0, 1.0 - x / 8.0].map(I2F30::from_num)),
            t: PathLength::from_num(t),
        }
    }

    #[test]
    fn the_side_with_the_smaller_distance_step_wins() {
        let c = s(1.0, 10.0);
        let (l, r) = (s(0.5, 10.1), s(1.5, 50.0)); // r is across a silhouette
        let (dp, dn, sat) = axis(&c, Some(&l), Some(&r));
        assert!(!sat);
        assert_eq!(dp[0].to_num::<f64>(), 0.5);
        assert_eq!(dn[1], c.n[1] - l.n[1]);
        let (l, r) = (s(0.5, 30.0), s(1.25, 10.5));
        assert_eq!(axis(&c, Some(&l), Some(&r)).0[0].to_num::<f64>(), 0.25);
        assert_eq!(axis(&c, None, Some(&r)).0[0].to_num::<f64>(), 0.25);
        assert_eq!(axis(&c, Some(&l), None).0[0].to_num::<f64>(), 0.5);
        assert_eq!(axis(&c, None, None).0, [PosDiff::ZERO; 3]);
        // Extremes saturate with the flag.
        let mut hi = c;
        hi.p = [PosDiff::MAX; 3];
        let mut lo = c;
        lo.p = [PosDiff::MIN; 3];
        assert!(axis(&lo, None, Some(&hi)).2);
        let prim = RayDiff::ZERO;
        let (d, [nx, ny], sat) = first_hit(&prim, &c, [Some(&l), Some(&r), None, None]);
        assert!(!sat);
        assert_eq!(d.dodx[0].to_num::<f64>(), 0.25);
        assert_eq!(d.dody, [PosDiff::ZERO; 3]);
        assert_eq!(ny, [DirDiff::ZERO; 3]);
        assert_eq!(nx[1], r.n[1] - c.n[1]);
    }
}
