//! LOD per hit: table, cone, cone + normal term and ray differentials in
//! every precision, timed per call and compared with f64 over the same
//! inputs (error in levels).

use fixed::types::{I16F16, I32F32, U1F31, U32F32};
use raymip::baseline_f32::{cone_lod_f32, table_lod_f32};
use raymip::lod::raydiff::{RayDiffFootprint, RayDiffTriangle};
use raymip::lod::{cone_lod, table_lod};
use raymip::path::raydiff::{DirDiff, PosDiff, RayDiff};
use raymip::setup::table::TexTriangle;
use raymip::units::{Accurate, Delta, Fast, Lod, Log2Pb, PathLength, TexCoord, Width};

use super::log2fx::{self, Log2Fx, Log2Tables};
use super::timing::measure;
use super::{Row, Settings, Stage, error_stats};
use raymip::rng::XorShift64;
use raymip_reference::Draw;
use raymip_reference::lod as reference;

/// One hit's inputs, exactly representable in the firmware's formats.
#[derive(Clone, Copy, Debug)]
struct Hit {
    pl: f64,
    log2_pb: f64,
    width: f64,
    delta: f64,
    cos: f64,
    /// Ray-differential footprint axes in level-0 texels (x and y) of a
    /// [`RAYDIFF_TEXELS`]² texture.
    axes: [[f64; 2]; 2],
}

/// Texture size (texels per side) of the ray-differential hits: the
/// firmware footprint is in normalized texture coordinates, the f64 axes
/// in texels.
const RAYDIFF_TEXELS: u32 = 256;

/// The hits: path lengths 2⁻⁸..2¹², `log2 Pb` in [−4, 12), cone widths
/// `Pl·10⁻³`, `|n·d|` in [0.05, 1), footprint axes up to ±64 texels; every
/// value rounded to its fixed-point format first, so all precisions see
/// the same numbers.
fn hits(n: usize) -> Vec<Hit> {
    let mut r = XorShift64(0x2545_F491_4F6C_DD1D);
    (0..n)
        .map(|_| {
            let pl = U32F32::from_num(2f64.powf(r.range(-8.0, 12.0)));
            let pb = I16F16::from_num(r.range(-4.0, 12.0));
            let w = I32F32::from_num(pl.to_num::<f64>() * 1e-3);
            let d = I16F16::from_num(-pb.to_num::<f64>() - 10.0);
            let c = U1F31::from_num(r.range(0.05, 1.0));
            let texels = f64::from(RAYDIFF_TEXELS);
            let mut texel =
                || TexCoord::from_num(r.range(-64.0, 64.0) / texels).to_num::<f64>() * texels;
            let mut ax = || [texel(), texel()];
            Hit {
                pl: pl.to_num(),
                log2_pb: pb.to_num(),
                width: w.to_num(),
                delta: d.to_num(),
                cos: c.to_num(),
                axes: [ax(), ax()],
            }
        })
        .collect()
}

/// The three LOD formulas of the firmware.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Formula {
    Table,
    Cone,
    ConeNormal,
}

impl Formula {
    fn name(self) -> &'static str {
        match self {
            Self::Table => "table",
            Self::Cone => "cone",
            Self::ConeNormal => "cone+normal",
        }
    }

    fn exact(self, h: &Hit) -> f64 {
        match self {
            Self::Table => reference::table(h.pl, h.log2_pb),
            Self::Cone => reference::cone(h.delta, h.width, None),
            Self::ConeNormal => reference::cone(h.delta, h.width, Some(h.cos)),
        }
    }

    /// The BUDGETS.md call that counts this formula's firmware path
    /// (accurate, or FAST when `fast`).
    fn budget_call(self, fast: bool) -> Option<&'static str> {
        match (self, fast) {
            (Self::Table, false) => Some("table lod"),
            (Self::Table, true) => Some("table lod FAST"),
            (Self::Cone, _) => None,
            (Self::ConeNormal, false) => Some("cone lod (with n·d)"),
            (Self::ConeNormal, true) => Some("cone lod FAST (with n·d)"),
        }
    }
}

type FixedHit = (PathLength, Log2Pb, Width, Delta, U1F31);

fn fixed_hit(h: &Hit) -> FixedHit {
    (
        PathLength::from_num(h.pl),
        Log2Pb::from_log2(I16F16::from_num(h.log2_pb)),
        Width::from_num(h.width),
        Delta::from_num(h.delta),
        U1F31::from_num(h.cos),
    )
}

/// `(ns per call, lods)` of one firmware path: its `table` and `cone`
/// functions (`table_lod`/`cone_lod` in one tier: ACCURATE, or FAST with
/// the 1024-entry log2 table without interpolation), passed as function items so each is
/// timed with its calls inlined as the firmware compiles them.
fn firmware(
    f: Formula,
    inp: &[FixedHit],
    reps: usize,
    table: impl Fn(PathLength, Log2Pb) -> Option<Lod>,
    cone: impl Fn(Width, Delta, Option<U1F31>) -> Lod,
) -> (f64, Vec<f64>) {
    let l = |x: Lod| x.to_num::<f64>();
    match f {
        Formula::Table => measure(
            inp,
            reps,
            |(pl, pb, ..)| table(pl, pb),
            |o| o.map_or(f64::NAN, l),
        ),
        Formula::Cone => measure(inp, reps, |(_, _, w, d, _)| cone(w, d, None), l),
        Formula::ConeNormal => measure(inp, reps, |(_, _, w, d, c)| cone(w, d, Some(c)), l),
    }
}

/// `(ns per call, lods)` of a [`Log2Fx`] variant: the same formula with
/// the variant's `log2`, rounded to I8F8 like the firmware.
fn variant(
    f: Formula,
    v: Log2Fx,
    t: &Log2Tables,
    inp: &[FixedHit],
    reps: usize,
) -> (f64, Vec<f64>) {
    let round = |bits: i32| f64::from((bits + 0x80) >> 8) / 256.0;
    match f {
        Formula::Table => measure(
            inp,
            reps,
            |(pl, pb, ..)| t.log2(v, pl.to_bits()) - pb.to_bits(),
            round,
        ),
        Formula::Cone => measure(
            inp,
            reps,
            |(_, _, w, d, _)| d.to_bits() + t.log2(v, w.to_bits().unsigned_abs()),
            round,
        ),
        Formula::ConeNormal => measure(
            inp,
            reps,
            |(_, _, w, d, c)| {
                d.to_bits() + t.log2(v, w.to_bits().unsigned_abs())
                    - t.log2(v, u64::from(c.to_bits()) << 1)
            },
            round,
        ),
    }
}

type FloatHit = (f32, f32, f32, f32, f32);

/// `(ns per call, lods)` in f32 with `libm` (the firmware's `float`
/// module) or with `micromath`.
fn float32(f: Formula, micro: bool, inp: &[FloatHit], reps: usize) -> (f64, Vec<f64>) {
    use micromath::F32Ext;
    let m = |x: f32| F32Ext::log2(x);
    let c = f64::from;
    match (f, micro) {
        (Formula::Table, false) => measure(inp, reps, |(pl, pb, ..)| table_lod_f32(pl, pb), c),
        (Formula::Table, true) => measure(inp, reps, |(pl, pb, ..)| m(pl) - pb, c),
        (Formula::Cone, false) => measure(inp, reps, |(_, _, w, d, _)| cone_lod_f32(w, d, None), c),
        (Formula::Cone, true) => measure(inp, reps, |(_, _, w, d, _)| d + m(F32Ext::abs(w)), c),
        (Formula::ConeNormal, false) => {
            measure(inp, reps, |(_, _, w, d, n)| cone_lod_f32(w, d, Some(n)), c)
        }
        (Formula::ConeNormal, true) => measure(
            inp,
            reps,
            |(_, _, w, d, n)| d + m(F32Ext::abs(w)) - m(n.clamp(1.0 / 65536.0, 1.0)),
            c,
        ),
    }
}

/// `(ns per call, lods)` in f64 (the reference formula itself).
fn float64(f: Formula, hits: &[Hit], reps: usize) -> (f64, Vec<f64>) {
    measure(hits, reps, |h| f.exact(&h), |x| x)
}

fn row(method: &str, precision: &str, (ns, got): (f64, Vec<f64>), exact: &[f64]) -> Row {
    let (max, rms) = error_stats(got.iter().zip(exact).map(|(g, e)| g - e));
    Row {
        time_ns: Some(ns),
        ..Row::new(Stage::Lod, method, precision, max, rms, "levels")
    }
}

/// Every LOD row (the firmware rows carry BUDGETS.md instruction counts,
/// added by the caller). `tick` is called after each row.
pub fn rows(s: &Settings, tick: &dyn Fn()) -> Vec<Row> {
    let hits = hits(s.lod_inputs);
    let fx: Vec<FixedHit> = hits.iter().map(fixed_hit).collect();
    let fl: Vec<FloatHit> = hits
        .iter()
        .map(|h| {
            (
                h.pl as f32,
                h.log2_pb as f32,
                h.width as f32,
                h.delta as f32,
                h.cos as f32,
            )
        })
        .collect();
    let tables = Log2Tables::default();
    let reps = s.repeats;
    let mut out = Vec::new();
    for f in [Formula::Table, Formula::Cone, Formula::ConeNormal] {
        let exact: Vec<f64> = hits.iter().map(|h| f.exact(h)).collect();
        for (fast, precision) in [(false, "fixed accurate"), (true, "fixed fast")] {
            let lods = if fast {
                firmware(f, &fx, reps, table_lod::<Fast>, cone_lod::<Fast>)
            } else {
                firmware(f, &fx, reps, table_lod::<Accurate>, cone_lod::<Accurate>)
            };
            out.push(Row {
                budget_call: f.budget_call(fast).map(|c| (c.to_string(), false)),
                ..row(f.name(), precision, lods, &exact)
            });
        }
        for v in [Log2Fx::Lut16Lerp, Log2Fx::Lut256, Log2Fx::Mitchell] {
            out.push(row(
                f.name(),
                log2fx::name(v),
                variant(f, v, &tables, &fx, reps),
                &exact,
            ));
        }
        let mut libm = row(f.name(), "f32 libm", float32(f, false, &fl, reps), &exact);
        libm.budget_call = f.budget_call(false).map(|c| (c.to_string(), true));
        out.push(libm);
        out.push(row(
            f.name(),
            "f32 micromath",
            float32(f, true, &fl, reps),
            &exact,
        ));
        out.push(row(f.name(), "f64", float64(f, &hits, reps), &exact));
        tick();
    }
    // The axes are in texels already.
    let raydiff = |h: Hit| reference::footprint(h.axes, (1.0, 1.0));
    let exact: Vec<f64> = hits.iter().map(|&h| raydiff(h)).collect();
    // The firmware lod of the same footprints (`RayDiffFootprint::lod`, the
    // per-hit step after the footprint's dot products) on a triangle of the
    // RAYDIFF_TEXELS² texture whose UVs are its x and y: ∂P = axis/texels.
    let tri = raydiff_triangle();
    let texels = f64::from(RAYDIFF_TEXELS);
    let fps: Vec<RayDiffFootprint> = hits
        .iter()
        .map(|h| {
            let p = |a: [f64; 2]| PosDiff::from_f64([a[0] / texels, a[1] / texels, 0.0]);
            let s = RayDiff::new(p(h.axes[0]), p(h.axes[1]), DirDiff::ZERO, DirDiff::ZERO);
            tri.footprint(&s)
        })
        .collect();
    out.push(Row {
        budget_call: Some(("lod from the footprint (larger axis)".to_string(), false)),
        ..row(
            "raydiff",
            "fixed accurate",
            measure(&fps, reps, |fp| fp.lod(), |l| l.to_num::<f64>()),
            &exact,
        )
    });
    out.push(row(
        "raydiff",
        "f64",
        measure(&hits, reps, raydiff, |x| x),
        &exact,
    ));
    tick();
    out
}

/// A right triangle with unit legs and UVs on a [`RAYDIFF_TEXELS`]² texture
/// (the firmware lod reads only the texture size and degeneracy).
fn raydiff_triangle() -> RayDiffTriangle {
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let t = TexTriangle::from_f32(p, uv, RAYDIFF_TEXELS, RAYDIFF_TEXELS)
        .expect("a unit right triangle on a 256² texture is valid");
    RayDiffTriangle::new(&t)
}
