//! The G-buffer of [`Method::Gbuffer`](super::Method::Gbuffer) ("RayDiffs
//! GB" of the ray-cone talk): one pass over the pixel centres stores each
//! pixel's first hit (position, unit shading normal facing the ray, hit
//! distance); the first hit of a path then takes its position and normal
//! differentials from the neighbouring pixels' entries instead of a
//! transfer, by the firmware's rule ([`raymip::path::raydiff::gbuffer`]) in fixed
//! precision and by [`axis_f64`], the same rule in f64, in float precision.
//! The entries are written in the render's precision (firmware
//! [`GSample`]s or f64 [`GHit`]s), never both.

use fixed::types::I2F30;
use raymip::path::raydiff::gbuffer::GSample;
use raymip::path::raydiff::{DirDiff, RayDiff};

use crate::scene::V3;
use raymip::units::UnitVec;

/// One pixel's first hit in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GHit {
    /// Hit position.
    pub p: V3,
    /// Unit shading normal, facing the primary ray.
    pub n: V3,
    /// Distance along the unit primary direction.
    pub t: f64,
}

impl GHit {
    /// The firmware's G-buffer entry of this hit in a buffer at `2^scale`
    /// scene units: position and distance as i32 / u32 in those units
    /// (rounded, saturating), normal as I2F30 (saturating; a non-finite
    /// value reads as 0).
    #[must_use]
    pub fn to_fixed(&self, scale: i32) -> GSample {
        let q = |x: f64| if x.is_finite() { x } else { 0.0 };
        let k = (-f64::from(scale)).exp2();
        GSample {
            p: self.p.to_array().map(|x| (q(x) * k).round() as i32),
            n: UnitVec(self.n.to_array().map(|x| I2F30::saturating_from_num(q(x)))),
            t: (q(self.t) * k).round() as u32,
        }
    }

    /// The scale of a G-buffer holding `hits`: the smallest `2^scale` at
    /// which every position and distance is below `2³⁰` units.
    #[must_use]
    pub fn scale_of<'a>(hits: impl IntoIterator<Item = &'a Self>) -> i32 {
        let top = hits
            .into_iter()
            .flat_map(|h| [h.p.x, h.p.y, h.p.z, h.t])
            .filter(|x| x.is_finite())
            .fold(0.0f64, |m, x| m.max(x.abs()));
        if top == 0.0 {
            0
        } else {
            top.log2().floor() as i32 + 1 - 30
        }
    }
}

/// A `width × height` G-buffer, row-major, `None` where the pixel's
/// primary ray leaves the scene.
#[derive(Clone, Debug)]
pub struct GBuffer<T> {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Entries, row-major.
    pub entries: Vec<Option<T>>,
}

impl<T> GBuffer<T> {
    /// The entry at `(x, y)` (`None` outside the image or on a miss).
    #[must_use]
    pub fn get(&self, x: i64, y: i64) -> Option<&T> {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return None;
        }
        self.entries
            .get((y * i64::from(self.width) + x) as usize)?
            .as_ref()
    }

    /// The entry at `(x, y)` and its neighbours `[left, right, up, down]`
    /// (rows grow downwards, as the camera's `∂D/∂y`).
    #[must_use]
    pub fn stencil(&self, x: u32, y: u32) -> Option<(&T, [Option<&T>; 4])> {
        let (x, y) = (i64::from(x), i64::from(y));
        Some((
            self.get(x, y)?,
            [
                self.get(x - 1, y),
                self.get(x + 1, y),
                self.get(x, y - 1),
                self.get(x, y + 1),
            ],
        ))
    }
}

/// The G-buffer of a render, in its precision.
#[derive(Clone, Debug)]
pub enum Frame {
    /// Firmware entries (fixed precision) at `2^scale` scene units.
    Fixed(GBuffer<GSample>, i32),
    /// f64 entries (float precision).
    Float(GBuffer<GHit>),
}

/// A first hit's differentials from the G-buffer, in the render's
/// precision.
#[derive(Clone, Copy, Debug)]
pub(crate) enum FirstHit {
    /// The firmware's [`raymip::path::raydiff::gbuffer::first_hit`]: the path's
    /// differential state at the hit and the normal differentials
    /// `[∂n/∂x, ∂n/∂y]`.
    Fixed(RayDiff, [DirDiff; 2]),
    /// f64: `[∂P/∂x, ∂P/∂y]` and `[∂n/∂x, ∂n/∂y]`.
    Float([V3; 2], [V3; 2]),
}

impl Frame {
    /// The differentials of pixel `(x, y)`'s first hit (`None` when its
    /// primary ray has no entry); `primary` is the camera's differential
    /// state of the path (fixed precision).
    pub(crate) fn first_hit(&self, x: u32, y: u32, primary: &RayDiff) -> Option<FirstHit> {
        match self {
            Self::Fixed(g, scale) => {
                let (c, nb) = g.stencil(x, y)?;
                let mut d = *primary;
                let dn =
                    raymip::path::raydiff::gbuffer::first_hit(&mut d, c, nb, *scale).normal_diffs();
                Some(FirstHit::Fixed(d, dn))
            }
            Self::Float(g) => {
                let (c, [l, r, u, d]) = g.stencil(x, y)?;
                let (dpx, dnx) = axis_f64(c, l, r);
                let (dpy, dny) = axis_f64(c, u, d);
                Some(FirstHit::Float([dpx, dpy], [dnx, dny]))
            }
        }
    }
}

/// The G-buffer rule in f64 (the reference of
/// [`raymip::path::raydiff::gbuffer::axis`]): `(∂P, ∂n)` of one axis from the
/// centre `c` and its neighbours, the side whose `|t − t_c|` is smaller
/// (ties: `plus`), `plus − c` or `c − minus`; zero without a neighbour.
#[must_use]
pub fn axis_f64(c: &GHit, minus: Option<&GHit>, plus: Option<&GHit>) -> (V3, V3) {
    let dt = |s: &GHit| (s.t - c.t).abs();
    let (a, b) = match (minus, plus) {
        (Some(m), Some(p)) if dt(m) < dt(p) => (c, m),
        (_, Some(p)) => (p, c),
        (Some(m), None) => (c, m),
        (None, None) => return (V3::ZERO, V3::ZERO),
    };
    (a.p - b.p, a.n - b.n)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(x: f64, t: f64) -> GHit {
        GHit {
            p: V3::new(x, 2.0 * x, -1.0),
            n: V3::new(0.0, 0.6, 0.8),
            t,
        }
    }

    /// The firmware's G-buffer rule against [`axis_f64`] on every pixel of
    /// rendered G-buffers (the f64 entries and the firmware's, written
    /// from them at the buffer's `2^scale`): the same side wherever the two
    /// `|Δt|` differ by more than the entries' rounding (half a unit each,
    /// so 2 units for the comparison), and then `∂P` within one unit per
    /// component (the rounding of two positions; the difference itself is
    /// exact) and `∂n` within 2⁻³⁰ (I2F30).
    #[test]
    fn the_firmware_rule_matches_the_f64_rule_on_rendered_g_buffers() {
        use crate::render::{Prepared, tracer::gbuffer_pass};
        use crate::scene::builtin;
        for name in ["hall", "mirrors", "glass"] {
            let prep = Prepared::new(builtin::by_name(name).unwrap(), Some((80, 48))).unwrap();
            let (Frame::Float(g), Frame::Fixed(q, scale)) =
                (gbuffer_pass(&prep, false), gbuffer_pass(&prep, true))
            else {
                panic!("{name}: G-buffers in the wrong precision");
            };
            let unit = f64::from(scale).exp2();
            let (mut compared, mut misses) = (0, 0);
            for y in 0..g.height {
                for x in 0..g.width {
                    let (Some((c, [l, r, u, d])), Some((cq, [lq, rq, uq, dq]))) =
                        (g.stencil(x, y), q.stencil(x, y))
                    else {
                        assert!(g.stencil(x, y).is_none() && q.stencil(x, y).is_none());
                        misses += 1;
                        continue;
                    };
                    for (m, p, mq, pq) in [(l, r, lq, rq), (u, d, uq, dq)] {
                        let near_tie = match (m, p) {
                            (Some(m), Some(p)) => {
                                ((m.t - c.t).abs() - (p.t - c.t).abs()).abs() <= 2.0 * unit
                            }
                            _ => false,
                        };
                        if near_tie {
                            continue;
                        }
                        let (dp, dn) = axis_f64(c, m, p);
                        let (dpq, dnq) = raymip::path::raydiff::gbuffer::axis(cq, mq, pq, scale);
                        let (dpq, dnq) = (dpq.to_f64(), dnq.to_f64());
                        for k in 0..3 {
                            let e = (dpq[k] - dp[k]).abs();
                            assert!(e <= unit, "{name} ({x}, {y}) ∂P[{k}]: {e:e}");
                            let e = (dnq[k] - dn[k]).abs();
                            assert!(e <= 2f64.powi(-30), "{name} ({x}, {y}) ∂n[{k}]: {e:e}");
                        }
                        compared += 1;
                    }
                }
            }
            assert!(compared > 5000, "{name}: {compared} axes compared");
            println!(
                "{name}: {compared} axes, {misses} pixels without a first hit (scale 2^{scale})"
            );
        }
    }

    #[test]
    fn the_stencil_reads_the_four_neighbours_and_stops_at_the_edges() {
        let g = GBuffer {
            width: 3,
            height: 2,
            entries: (0..6).map(Some).collect(),
        };
        assert_eq!(
            g.stencil(0, 0),
            Some((&0, [None, Some(&1), None, Some(&3)]))
        );
        assert_eq!(
            g.stencil(1, 1),
            Some((&4, [Some(&3), Some(&5), Some(&1), None]))
        );
        assert_eq!(g.stencil(3, 0), None);
        let holes = GBuffer {
            width: 2,
            height: 1,
            entries: vec![None, Some(7)],
        };
        assert_eq!(holes.stencil(0, 0), None);
        assert_eq!(holes.stencil(1, 0), Some((&7, [None, None, None, None])));
    }

    #[test]
    fn the_f64_rule_takes_the_side_with_the_smaller_distance_step() {
        let c = hit(1.0, 10.0);
        let (l, r) = (hit(0.5, 10.1), hit(1.5, 50.0));
        assert_eq!(axis_f64(&c, Some(&l), Some(&r)).0, V3::new(0.5, 1.0, 0.0));
        assert_eq!(axis_f64(&c, None, Some(&r)).0, V3::new(0.5, 1.0, 0.0));
        let near = hit(1.25, 10.0);
        // A tie takes `plus`.
        assert_eq!(
            axis_f64(&c, Some(&hit(0.75, 10.0)), Some(&near)).0,
            V3::new(0.25, 0.5, 0.0)
        );
        assert_eq!(axis_f64(&c, None, None), (V3::ZERO, V3::ZERO));
    }
}
