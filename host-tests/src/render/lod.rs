//! The LOD flow of a textured hit: `hit_lod` takes the chosen [`Method`]'s
//! lod in the arithmetic of the render's texture unit (its precision: the
//! firmware [`Lod`] from the firmware call to the firmware sampler, or f64
//! to the f64 one) and `UnitLod::sample` samples there. Imports run one
//! way: the tracer uses this module, this module the texture units.

use fixed::types::U1F31;
use raymip::lod::{clamp_lod, cone_lod, table_lod};
use raymip::path::raystack::PathState;
use raymip::rng::Rng;
use raymip::units::{Accurate, Footprint, Lod};
use raymip_reference::lod as reference;

use super::options::Method;
use super::setup::Prepared;
use super::texunit::{FetchLog, Filter, FirmwareUnit, FloatUnit, MipTexture, Unit};

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

/// A textured hit's lod in the arithmetic of the texture unit that
/// samples it, paired with that unit: the firmware unit only ever receives
/// fixed-point lods and footprints, the f64 unit only f64 ones.
pub(crate) enum UnitLod<'u, 'a> {
    /// Fixed precision: the firmware's lod and, for ray differentials, the
    /// firmware footprint it was taken from.
    Fixed {
        /// The firmware unit.
        unit: &'u mut FirmwareUnit<'a>,
        /// The method's lod (unclamped).
        lod: Lod,
        /// The footprint axes (ray differentials only).
        footprint: Option<Footprint>,
    },
    /// Float precision: the f64 lod and, for ray differentials, its axes.
    Float {
        /// The f64 unit.
        unit: &'u FloatUnit<'a>,
        /// The method's lod (unclamped).
        lod: f64,
        /// The footprint axes `[(du/dx, dv/dx), (du/dy, dv/dy)]`
        /// (ray differentials only).
        axes: Option<[[f64; 2]; 2]>,
    },
}

/// The lod of a textured hit for `method`, in the arithmetic of `unit` (the
/// render's precision); `None` when the method has no lod for this triangle
/// (untextured Pb entry or ray-differential triangle).
pub(crate) fn hit_lod<'u, 'a>(
    unit: &'u mut Unit<'a>,
    prep: &Prepared,
    method: Method,
    q: &LodQuery,
) -> Option<UnitLod<'u, 'a>> {
    match unit {
        Unit::Firmware(unit) => {
            let (lod, footprint) = fixed_lod(prep, method, q)?;
            Some(UnitLod::Fixed {
                unit,
                lod,
                footprint,
            })
        }
        Unit::Float(unit) => {
            let (lod, axes) = float_lod(prep, method, q);
            Some(UnitLod::Float { unit, lod, axes })
        }
    }
}

/// The firmware lod of a hit (and the firmware footprint for ray
/// differentials: those carried by the path state, transferred to the hit).
fn fixed_lod(prep: &Prepared, method: Method, q: &LodQuery) -> Option<(Lod, Option<Footprint>)> {
    let pbx = prep.pb_fixed[q.tri];
    match method {
        Method::Mip0 | Method::Truth => Some((Lod::ZERO, None)),
        Method::Table => table_lod::<Accurate>(q.state.pl, pbx).map(|l| (l, None)),
        Method::Cone => pbx.delta(&prep.spread).map(|delta| {
            let nd = U1F31::saturating_from_num(q.n_dot_d);
            (
                cone_lod::<Accurate>(q.state.cone.width, delta, Some(nd)),
                None,
            )
        }),
        Method::Raydiff | Method::Gbuffer => {
            let t = prep.rd_tris[q.tri]?;
            let fp = t.footprint(q.state.diff.dodx, q.state.diff.dody);
            Some((t.lod(&fp), Some(fp)))
        }
    }
}

/// The f64 lod of a hit (and the f64 footprint axes for ray differentials).
fn float_lod(prep: &Prepared, method: Method, q: &LodQuery) -> (f64, Option<[[f64; 2]; 2]>) {
    let pbf = prep.pb_float[q.tri];
    match method {
        Method::Mip0 | Method::Truth => (0.0, None),
        Method::Table => (reference::table(q.pl, pbf), None),
        Method::Cone => {
            let delta = -pbf - prep.cam.gamma.log2();
            (reference::cone(delta, q.width, Some(q.n_dot_d)), None)
        }
        Method::Raydiff | Method::Gbuffer => {
            let axes = raydiff_axes(q);
            let size = (f64::from(q.tex.width), f64::from(q.tex.height));
            (reference::footprint(axes, size), Some(axes))
        }
    }
}

impl UnitLod<'_, '_> {
    /// The lod as the counters read it.
    pub(crate) fn lod(&self) -> HitLod {
        match self {
            Self::Fixed { lod, .. } => HitLod::Fixed(*lod),
            Self::Float { lod, .. } => HitLod::Float(*lod),
        }
    }

    /// One sample of texture `tex` at `(u, v)` (texture repeats) as linear
    /// RGB in 0..1: anisotropic over the footprint when `aniso` and the
    /// method gave one, else isotropic at the lod with `filter` (a
    /// stochastic filter draws its 32 bits from `rng`). Counts the sample
    /// and the lod it was given in `log`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn sample(
        self,
        tex: usize,
        u: f64,
        v: f64,
        filter: Filter,
        aniso: bool,
        rng: &mut Rng,
        log: &mut FetchLog,
    ) -> [f64; 3] {
        let lod = self.lod();
        match self {
            Self::Fixed {
                unit,
                footprint: Some(fp),
                ..
            } if aniso => {
                log.aniso_samples += 1;
                unit.sample_aniso_rgb(tex, u, v, &fp, log)
            }
            Self::Float {
                unit,
                axes: Some(axes),
                ..
            } if aniso => {
                log.aniso_samples += 1;
                unit.sample_aniso(tex, u, v, axes, log)
            }
            iso => {
                log.samples += 1;
                log.lod_sum_256 += lod.q256();
                let bits = match filter {
                    Filter::Stochastic(_) => rng.next_u32(),
                    _ => 0,
                };
                match iso {
                    Self::Fixed { unit, lod, .. } => {
                        unit.sample_rgb(tex, u, v, lod, filter, bits, log)
                    }
                    Self::Float { unit, lod, .. } => unit.sample(tex, u, v, lod, filter, log),
                }
            }
        }
    }
}

/// The pixel footprint's two axes in normalized texture coordinates from
/// the f64 ray differentials (pbrt): `[(du/dx, dv/dx), (du/dy, dv/dy)]`.
fn raydiff_axes(q: &LodQuery) -> [[f64; 2]; 2] {
    let uv = q.uv;
    let axis = |(a, b): (f64, f64)| {
        [
            a * (uv[1][0] - uv[0][0]) + b * (uv[2][0] - uv[0][0]),
            a * (uv[1][1] - uv[0][1]) + b * (uv[2][1] - uv[0][1]),
        ]
    };
    [axis(q.dbx), axis(q.dby)]
}
