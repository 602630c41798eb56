//! The LOD choice at a textured hit, per [`Method`] and [`Precision`]. A
//! fixed-point render keeps the firmware's [`Lod`] from the firmware call to
//! the sampler; a float render keeps f64.

use fixed::types::U1F31;
use raymip::lod::{Lod, clamp_lod, cone_lod, table_lod};
use raymip::raydiff::footprint::RayDiffTriangle;
use raymip::raystack::PathState;
use raymip::texture::sampler::aniso::Footprint;

use super::texunit::MipTexture;
use super::tracer::Ctx;
use super::{Method, Precision};

/// A hit's level of detail in the arithmetic of the render (unclamped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HitLod {
    /// Firmware fixed point.
    Fixed(Lod),
    /// f64 reference.
    Float(f64),
}

impl HitLod {
    /// Integer level selected in a texture of `levels` levels (clamped, floor).
    #[must_use]
    pub fn level(self, levels: u8) -> usize {
        match self {
            Self::Fixed(l) => clamp_lod(l, levels).to_num::<usize>(),
            Self::Float(l) => {
                let level = l.clamp(0.0, f64::from(levels - 1));
                if level.is_nan() {
                    0
                } else {
                    level.floor() as usize
                }
            }
        }
    }

    /// The value in 1/256 level (exact for [`HitLod::Fixed`], rounded for
    /// [`HitLod::Float`]; NaN reads as 0): what the renderer's counters sum
    /// on both sides of the texture unit ([`Counters::lod_sum_256`](super::Counters::lod_sum_256)).
    #[must_use]
    pub fn q256(self) -> i64 {
        match self {
            Self::Fixed(l) => i64::from(l.to_bits()),
            Self::Float(l) if l.is_nan() => 0,
            Self::Float(l) => (l * 256.0).round().clamp(-1e15, 1e15) as i64,
        }
    }

    /// The value (exact for [`HitLod::Fixed`]).
    #[must_use]
    pub fn to_f64(self) -> f64 {
        match self {
            Self::Fixed(l) => l.to_num(),
            Self::Float(l) => l,
        }
    }
}

/// What the LOD methods read at a hit.
pub(crate) struct LodQuery<'a> {
    /// Triangle index (Pb tables).
    pub tri: usize,
    /// The triangle's texture.
    pub tex: &'a MipTexture,
    /// The triangle's UVs.
    pub uv: &'a [[f64; 2]; 3],
    /// Firmware path state (fixed-point Pl and cone), advanced to the hit.
    pub state: &'a PathState,
    /// f64 path length at the hit.
    pub pl: f64,
    /// f64 cone width at the hit.
    pub width: f64,
    /// |n·d| with the geometric normal.
    pub n_dot_d: f64,
    /// Barycentric (b1, b2) differentials per pixel in x and y.
    pub dbx: (f64, f64),
    /// The same in y.
    pub dby: (f64, f64),
}

impl Ctx<'_> {
    /// The hit's lod; `None` when the method has no lod for this triangle
    /// (untextured Pb entry).
    pub(crate) fn hit_lod(&self, q: &LodQuery) -> Option<HitLod> {
        let prep = self.prep;
        let fixed = self.opts.precision == Precision::Fixed;
        let pbf = prep.pb_float[q.tri];
        let pbx = prep.pb_fixed[q.tri];
        match self.opts.method {
            Method::Mip0 | Method::Truth if fixed => Some(HitLod::Fixed(Lod::ZERO)),
            Method::Mip0 | Method::Truth => Some(HitLod::Float(0.0)),
            Method::Table if fixed => table_lod(q.state.pl, pbx).map(HitLod::Fixed),
            Method::Table => Some(HitLod::Float(q.pl.log2() - pbf)),
            Method::Cone if fixed => pbx.delta(&prep.spread).map(|delta| {
                let nd = U1F31::saturating_from_num(q.n_dot_d);
                HitLod::Fixed(cone_lod(q.state.cone.width, delta, Some(nd)))
            }),
            Method::Cone => {
                let delta = -pbf - prep.cam.gamma.log2();
                let w = if q.width == 0.0 {
                    2f64.powi(-32)
                } else {
                    q.width.abs()
                };
                let nd = q.n_dot_d.clamp(2f64.powi(-16), 1.0);
                Some(HitLod::Float(delta + w.log2() - nd.log2()))
            }
            // Fixed: the firmware ray differentials carried by the path
            // state (transferred to this hit), footprint and lod in fixed
            // point; float: the f64 ones.
            Method::Raydiff if fixed => {
                let t = prep.rd_tris[q.tri]?;
                Some(HitLod::Fixed(t.lod(&fixed_footprint(&t, q.state))))
            }
            Method::Raydiff => Some(HitLod::Float(raydiff_lod(q))),
        }
    }
}

/// The firmware footprint of a hit (normalized texture coordinates per
/// pixel) from the fixed-point ray differentials of `state`, transferred to
/// the hit.
pub(crate) fn fixed_footprint(t: &RayDiffTriangle, state: &PathState) -> Footprint {
    t.footprint(state.diff.dodx, state.diff.dody)
}

/// The pixel footprint's two axes in normalized texture coordinates from
/// the f64 ray differentials (pbrt): `[(du/dx, dv/dx), (du/dy, dv/dy)]`.
pub(crate) fn raydiff_axes(q: &LodQuery) -> [[f64; 2]; 2] {
    let uv = q.uv;
    let axis = |(a, b): (f64, f64)| {
        [
            a * (uv[1][0] - uv[0][0]) + b * (uv[2][0] - uv[0][0]),
            a * (uv[1][1] - uv[0][1]) + b * (uv[2][1] - uv[0][1]),
        ]
    };
    [axis(q.dbx), axis(q.dby)]
}

/// Ray-differential lod (Igehy 1999): log2 of the larger texel-space
/// footprint edge per pixel.
fn raydiff_lod(q: &LodQuery) -> f64 {
    let (tw, th) = (f64::from(q.tex.width), f64::from(q.tex.height));
    let len = |a: [f64; 2]| ((a[0] * tw).powi(2) + (a[1] * th).powi(2)).sqrt();
    let [x, y] = raydiff_axes(q);
    len(x).max(len(y)).max(1e-300).log2()
}
