//! `raymip-host stress`: every class of bad input at every API edge of the
//! firmware (and of its C ABI and the harness's scene loader), one row per
//! case with what came back, checked against what the API documents.
//!
//! Classes: NaN, ±inf, ±subnormal, ±0 and ±10³⁰ / ±10⁻³⁰ at the float
//! edges (camera, table triangles, sampler coordinates and lods, the f32
//! baselines); extreme fixed-point bit patterns at the fixed-point edges
//! (table and cone lod, sampler, path state); zero-area, collinear and
//! zero-UV triangles; `Pl` at the top of its range for 10+ bounces; grazing
//! `n·d`; ray-stack overflow; 1×1, 1×4096, 4096×1 and maximum-side
//! textures; pyramid storage one texel too small; bad pointers, sizes,
//! modes and stack lengths through the C ABI; non-finite numbers in a scene
//! file.
//!
//! Each case runs under [`std::panic::catch_unwind`]; its outcome is an
//! error value, a clamp (saturated, clamped or a documented marker) or a
//! plain value, and it *misbehaves* when that outcome is not the documented
//! one (an independent f64 or bit-level expectation) or when data that
//! must survive (table entries, level 0, a too-short buffer, stack
//! entries) changed. [`run`] returns the rows; the command exits non-zero
//! when anything panicked or misbehaved.

use std::fmt::{self, Write as _};
use std::panic::{self, AssertUnwindSafe};
use std::path::Path;

use fixed::types::{I2F30, I8F8, I16F16, U1F31};
use raymip::baseline_f32::{SamplerF32, cone_lod_f32, table_lod_f32};
use raymip::ffi::{
    self, RM_UNTEXTURED, RmAddressBits, RmModeBits, RmPathState, RmRayStack, RmSampler, RmStatus,
    RmTexture,
};
use raymip::lod::{MIN_COS, clamp_lod, cone_lod, table_lod};
use raymip::path::raystack::{DEFAULT_CAPACITY, PathState, RayStack};
use raymip::setup::camera::{CameraError, PixelSpread};
use raymip::setup::table::{PbTable, TableError, TexTriangle};
use raymip::texture::storage::mip::{
    self, Geometry, MAX_SIZE, MipError, Pyramid, Texel, generate, pyramid_len,
};
use raymip::texture::{AddressMode, FilterError, Mode, Sampler};
use raymip::units::{Accurate, Coord, Delta, Lod, Log2Pb, PathLength, Spread, TexCoord, Width};

use super::output::{OutputError, write_between_markers};

/// What a case returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An error value (Rust `Err`, C status, loader error).
    Error,
    /// A saturated, clamped or marker value (documented).
    Clamp,
    /// An ordinary value.
    Value,
}

/// One case of the table.
#[derive(Clone, Debug)]
pub struct Row {
    /// Input class (NaN, zero-area triangle, …).
    pub class: String,
    /// API edge.
    pub edge: &'static str,
    /// The result: `Ok((kind, what came back))`, or `Err(why)` when it was
    /// not the documented outcome or a panic (`panicked` set).
    pub result: Result<(Kind, String), Misbehaviour>,
    /// True when the case panicked.
    pub panicked: bool,
}

/// Totals of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Totals {
    /// Cases run.
    pub cases: usize,
    /// Cases answered with an error value.
    pub errors: usize,
    /// Cases answered with a clamp, saturation or marker.
    pub clamps: usize,
    /// Cases answered with an ordinary value.
    pub values: usize,
    /// Cases whose outcome was not the documented one (or lost data).
    pub misbehaved: usize,
    /// Cases that panicked.
    pub panicked: usize,
}

impl Totals {
    /// Adds up the rows.
    #[must_use]
    pub fn of(rows: &[Row]) -> Self {
        let mut t = Self {
            cases: rows.len(),
            ..Self::default()
        };
        for r in rows {
            match (&r.result, r.panicked) {
                (_, true) => t.panicked += 1,
                (Err(_), false) => t.misbehaved += 1,
                (Ok((Kind::Error, _)), _) => t.errors += 1,
                (Ok((Kind::Clamp, _)), _) => t.clamps += 1,
                (Ok((Kind::Value, _)), _) => t.values += 1,
            }
        }
        t
    }

    /// True when nothing panicked or misbehaved.
    #[must_use]
    pub fn clean(&self) -> bool {
        self.misbehaved == 0 && self.panicked == 0
    }
}

type Outcome = Result<(Kind, String), Misbehaviour>;

/// A case whose outcome was not the documented one (or that panicked):
/// what came back instead.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Misbehaviour(pub String);

impl fmt::Display for Misbehaviour {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Misbehaviour {}

impl From<String> for Misbehaviour {
    fn from(s: String) -> Self {
        Self(s)
    }
}

impl From<&str> for Misbehaviour {
    fn from(s: &str) -> Self {
        Self(s.to_string())
    }
}

/// Why `stress` failed.
#[derive(Debug)]
pub enum StressError {
    /// Cases panicked or misbehaved.
    Misbehaved {
        /// Cases whose outcome was not the documented one.
        misbehaved: usize,
        /// Cases that panicked.
        panicked: usize,
        /// Each such case: `edge / class: what came back`.
        cases: Vec<String>,
    },
    /// The docs/reliability.md block could not be written (names the file).
    Output(OutputError),
}

impl fmt::Display for StressError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Misbehaved {
                misbehaved,
                panicked,
                cases,
            } => write!(
                f,
                "stress: {misbehaved} misbehaved, {panicked} panicked:\n{}",
                cases.join("\n")
            ),
            Self::Output(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for StressError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Misbehaved { .. } => None,
            Self::Output(e) => Some(e),
        }
    }
}

impl From<OutputError> for StressError {
    fn from(e: OutputError) -> Self {
        Self::Output(e)
    }
}

/// A case's failure: `what` came back instead of the documented outcome.
fn bad<T>(what: impl Into<String>) -> Result<T, Misbehaviour> {
    Err(Misbehaviour(what.into()))
}

fn err(s: impl Into<String>) -> Outcome {
    Ok((Kind::Error, s.into()))
}
fn clamp(s: impl Into<String>) -> Outcome {
    Ok((Kind::Clamp, s.into()))
}
fn value(s: impl Into<String>) -> Outcome {
    Ok((Kind::Value, s.into()))
}
/// `err(what)` when a C ABI call returned the documented refusal `want`
/// and `untouched` holds, else a failure naming the status.
fn refused(s: RmStatus, want: RmStatus, untouched: bool, what: &str) -> Outcome {
    if s == want && untouched {
        err(what)
    } else {
        bad(format!("{s:?}"))
    }
}
/// `value(ok)` when `got` is within `tol` of the f64 reference `want`, else
/// a failure naming `what` and both numbers.
fn near(what: &str, got: f64, want: f64, tol: f64, ok: String) -> Outcome {
    if (got - want).abs() <= tol {
        value(ok)
    } else {
        bad(format!("{what}{got} vs f64 {want}"))
    }
}

#[derive(Default)]
struct Runner {
    rows: Vec<Row>,
}

impl Runner {
    fn case(&mut self, class: impl Into<String>, edge: &'static str, f: impl FnOnce() -> Outcome) {
        let r = panic::catch_unwind(AssertUnwindSafe(f));
        let (result, panicked) = match r {
            Ok(o) => (o, false),
            Err(p) => {
                let msg = p
                    .downcast_ref::<&str>()
                    .map(|s| (*s).to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "panic".into());
                (bad(format!("panicked: {msg}")), true)
            }
        };
        self.rows.push(Row {
            class: class.into(),
            edge,
            result,
            panicked,
        });
    }
}

/// The float classes: name, f64 value, f32 value (the f32 subnormal is
/// its own: an f64 subnormal is 0 in f32).
pub const FLOAT_CLASSES: [(&str, f64, f32); 11] = [
    ("NaN", f64::NAN, f32::NAN),
    ("+inf", f64::INFINITY, f32::INFINITY),
    ("-inf", f64::NEG_INFINITY, f32::NEG_INFINITY),
    ("+subnormal", 1.0e-310, 1.0e-40),
    ("-subnormal", -1.0e-310, -1.0e-40),
    ("+0", 0.0, 0.0),
    ("-0", -0.0, -0.0),
    ("+1e30", 1.0e30, 1.0e30),
    ("-1e30", -1.0e30, -1.0e30),
    ("+1e-30", 1.0e-30, 1.0e-30),
    ("-1e-30", -1.0e-30, -1.0e-30),
];

/// Runs every case (quiet panic hook while running) and returns the rows.
#[must_use]
pub fn run() -> Vec<Row> {
    let hook = panic::take_hook();
    panic::set_hook(Box::new(|_| {}));
    let mut r = Runner::default();
    camera(&mut r);
    table(&mut r);
    table_geometry(&mut r);
    table_limits(&mut r);
    lods(&mut r);
    cone_lods(&mut r);
    lods_float(&mut r);
    sampler(&mut r);
    path(&mut r);
    textures(&mut r);
    texture_limits(&mut r);
    c_abi(&mut r);
    c_abi_lod(&mut r);
    c_abi_sample(&mut r);
    c_abi_stack(&mut r);
    scene_file(&mut r);
    render_degenerate(&mut r);
    panic::set_hook(hook);
    r.rows
}

fn spread() -> PixelSpread {
    PixelSpread::from_fov_y(60f64.to_radians(), 480).expect("60° over 480 rows")
}

fn camera(r: &mut Runner) {
    for (name, x, _) in FLOAT_CLASSES {
        r.case(name, "camera: PixelSpread::from_fov_y(fov, 480)", || {
            match PixelSpread::from_fov_y(x, 480) {
                Err(CameraError::NonFinite) if !x.is_finite() => err("NonFinite"),
                // Finite but not a usable angle: ≤ 0, ≥ π, or γ below the
                // I2F30 step (fov ≤ 10⁻³⁰).
                Err(CameraError::BadAngle)
                    if x.is_finite() && !(1e-6..=std::f64::consts::PI).contains(&x) =>
                {
                    err("BadAngle")
                }
                other => bad(format!("{other:?}")),
            }
        });
    }
    r.case(
        "0 rows",
        "camera: PixelSpread::from_fov_y(1, 0)",
        || match PixelSpread::from_fov_y(1.0, 0) {
            Err(CameraError::ZeroImageHeight) => err("ZeroImageHeight"),
            o => bad(format!("{o:?}")),
        },
    );
    r.case(
        "u32::MAX rows",
        "camera: PixelSpread::from_fov_y(1, u32::MAX)",
        || {
            // γ ≈ 2.5·10⁻¹⁰ rad, under half the I2F30 step: no usable angle.
            match PixelSpread::from_fov_y(1.0, u32::MAX) {
                Err(CameraError::BadAngle) => err("BadAngle"),
                o => bad(format!("{o:?}")),
            }
        },
    );
    for (name, a) in [
        ("I2F30 MIN", I2F30::MIN),
        ("0", I2F30::ZERO),
        ("1 bit", I2F30::DELTA),
        ("I2F30 MAX", I2F30::MAX),
    ] {
        r.case(name, "camera: PixelSpread::from_angle", || {
            match (
                PixelSpread::from_angle(Spread::from_fixed(a)),
                a > I2F30::ZERO,
            ) {
                (Err(CameraError::BadAngle), false) => err("BadAngle"),
                (Ok(s), true) => {
                    let want = a.to_num::<f64>().log2();
                    let got = s.log2().to_num::<f64>();
                    near("log2 γ ", got, want, 1e-4, format!("log2 γ = {got:.4}"))
                }
                (o, _) => bad(format!("{o:?}")),
            }
        });
    }
}

const TRI_P: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
const TRI_UV: [[f32; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

/// Builds a 3-entry table whose entries 0 and 2 hold a sentinel and entry
/// 1 the triangle; fails when a sentinel changed.
fn entry_of(tri: TexTriangle) -> Result<(Log2Pb, u32), Misbehaviour> {
    let sentinel = Log2Pb::from_bits(0x1234_5678 & 0x003F_FFFF);
    let mut storage = [sentinel; 3];
    let mut t = PbTable::new(&mut storage);
    let st = t
        .update(1, [Some(tri)], &spread())
        .map_err(|e| format!("update: {e}"))?;
    if storage[0] != sentinel || storage[2] != sentinel {
        return bad("an entry beside the updated one changed");
    }
    let n = st.textured + st.untextured + st.degenerate_geometry + st.degenerate_uv;
    Ok((storage[1], n))
}

fn check_entry(e: Log2Pb) -> Outcome {
    let v = e.to_i16f16().to_num::<f64>();
    if e == Log2Pb::DEGENERATE_GEOMETRY {
        clamp("DEGENERATE_GEOMETRY")
    } else if e == Log2Pb::DEGENERATE_UV {
        clamp("DEGENERATE_UV")
    } else if (-64.0..=64.0).contains(&v) {
        value(format!("log2 Pb = {v:.4}"))
    } else {
        bad(format!("entry {v} outside [-64, 64]"))
    }
}

fn table(r: &mut Runner) {
    for (name, _, x) in FLOAT_CLASSES {
        for (edge, at_uv) in [
            ("table: TexTriangle::from_f32 position", false),
            ("table: TexTriangle::from_f32 uv", true),
        ] {
            r.case(name, edge, || {
                let (mut p, mut uv) = (TRI_P, TRI_UV);
                if at_uv {
                    uv[1][0] = x;
                } else {
                    p[1][0] = x;
                }
                match TexTriangle::from_f32(p, uv, 256, 256) {
                    Err(TableError::NonFinite) if !x.is_finite() => err("NonFinite"),
                    Err(TableError::OutOfRange) if x.is_finite() && x.abs() >= 2.0e9 => {
                        err("OutOfRange")
                    }
                    Ok(t) if x.is_finite() && x.abs() < 2.0e9 => {
                        let (e, n) = entry_of(t)?;
                        if n != 1 {
                            return bad(format!("stats count {n} entries"));
                        }
                        // x = ±0, subnormal or 10⁻³⁰ (0 in I32F32): the
                        // edge collapses, zero area in that space.
                        let want = if at_uv {
                            Log2Pb::DEGENERATE_UV
                        } else {
                            Log2Pb::DEGENERATE_GEOMETRY
                        };
                        if e == want {
                            clamp(format!("{want:?}"))
                        } else {
                            bad(format!("entry {e:?}, want {want:?}"))
                        }
                    }
                    o => bad(format!("{o:?}")),
                }
            });
        }
    }
}

fn table_geometry(r: &mut Runner) {
    let geo = |name: &str, p: [[f32; 3]; 3], uv: [[f32; 2]; 3], want: Option<Log2Pb>| {
        let name = name.to_string();
        move || -> Outcome {
            let t = TexTriangle::from_f32(p, uv, 256, 256).map_err(|e| e.to_string())?;
            let (e, _) = entry_of(t)?;
            match want {
                Some(w) if e != w => bad(format!("{name}: {e:?}, want {w:?}")),
                _ => check_entry(e),
            }
        }
    };
    let z = [0.0f32; 3];
    r.case(
        "zero-area triangle (3 equal points)",
        "table: PbTable::update",
        geo("zero", [z, z, z], TRI_UV, Some(Log2Pb::DEGENERATE_GEOMETRY)),
    );
    r.case(
        "collinear triangle",
        "table: PbTable::update",
        geo(
            "collinear",
            [[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
            TRI_UV,
            Some(Log2Pb::DEGENERATE_GEOMETRY),
        ),
    );
    r.case(
        "collinear UVs",
        "table: PbTable::update",
        geo(
            "uv",
            TRI_P,
            [[0.0, 0.0], [0.5, 0.5], [1.0, 1.0]],
            Some(Log2Pb::DEGENERATE_UV),
        ),
    );
    r.case(
        "sliver: area 2^-33 (one I32F32 step high)",
        "table: PbTable::update",
        || {
            let h = 2f64.powi(-32);
            let p = [[0i64; 3], [1 << 32, 0, 0], [0, 1, 0]].map(|v| v.map(Coord::from_bits));
            let uv = TRI_UV.map(|v| v.map(TexCoord::from_num));
            let t = TexTriangle::new(p, uv, 256, 256).map_err(|e| e.to_string())?;
            let (e, _) = entry_of(t)?;
            // Pb = sqrt(A_world/A_tex)/γ with A_world = h/2, A_tex = 256²/2.
            let want = ((h / 65536.0).sqrt() / spread().angle().to_num::<f64>()).log2();
            let got = e.to_i16f16().to_num::<f64>();
            let ok = format!("log2 Pb = {got:.4} (f64 {want:.4})");
            near("log2 Pb ", got, want, 1.0 / 512.0, ok)
        },
    );
}

fn table_limits(r: &mut Runner) {
    r.case(
        "largest coordinates (±(2^31 − 2^-32))",
        "table: PbTable::update",
        || {
            let m = Coord::MAX;
            let n = Coord::MIN;
            let p = [[n, n, n], [m, n, n], [n, m, n]];
            let uv = TRI_UV.map(|v| v.map(TexCoord::from_num));
            let t = TexTriangle::new(p, uv, 1, 1).map_err(|e| e.to_string())?;
            let (e, _) = entry_of(t)?;
            // Edges 2^32: A_world = 2^63, A_tex = 1/2: Pb = 2^32/γ.
            let want = 32.0 - spread().angle().to_num::<f64>().log2();
            let got = e.to_i16f16().to_num::<f64>();
            let ok = format!("log2 Pb = {got:.4} (f64 {want:.4}), no overflow");
            near("log2 Pb ", got, want, 1.0 / 512.0, ok)
        },
    );
    for (name, w, h) in [("0×256 texture", 0, 256), ("256×0 texture", 256, 0)] {
        r.case(
            name,
            "table: TexTriangle::from_f32",
            move || match TexTriangle::from_f32(TRI_P, TRI_UV, w, h) {
                Err(TableError::ZeroTextureSize) => err("ZeroTextureSize"),
                o => bad(format!("{o:?}")),
            },
        );
    }
    r.case(
        "u32::MAX × u32::MAX texture",
        "table: PbTable::update",
        || {
            let t = TexTriangle::from_f32(TRI_P, TRI_UV, u32::MAX, u32::MAX)
                .map_err(|e| e.to_string())?;
            let (e, _) = entry_of(t)?;
            check_entry(e)
        },
    );
    r.case(
        "update past the end (4 entries, 4 triangles at 2)",
        "table: PbTable::update",
        || {
            let sentinel = Log2Pb::from_bits(7 << 16);
            let mut storage = [sentinel; 4];
            let tri = TexTriangle::from_f32(TRI_P, TRI_UV, 256, 256).map_err(|e| e.to_string())?;
            let res = PbTable::new(&mut storage).update(2, [Some(tri); 4], &spread());
            let want = Log2Pb::compute(&tri, &spread());
            match res {
                Err(TableError::TableFull)
                    if storage[..2] == [sentinel; 2] && storage[2..] == [want; 2] =>
                {
                    err("TableFull; entries 0-1 untouched, 2-3 written")
                }
                o => bad(format!("{o:?}, entries {storage:?}")),
            }
        },
    );
}

fn lod_ref(l: f64) -> f64 {
    l.clamp(Lod::MIN.to_num(), Lod::MAX.to_num())
}

fn lods(r: &mut Runner) {
    let pls = [
        ("Pl 0", PathLength::ZERO),
        ("Pl 2^-32", PathLength::DELTA),
        ("Pl 1", PathLength::ONE),
        ("Pl MAX", PathLength::MAX),
    ];
    let pbs = [
        ("UNTEXTURED", Log2Pb::UNTEXTURED),
        ("DEGENERATE_GEOMETRY", Log2Pb::DEGENERATE_GEOMETRY),
        ("DEGENERATE_UV", Log2Pb::DEGENERATE_UV),
        ("MIN", Log2Pb::MIN),
        ("MAX", Log2Pb::MAX),
        ("raw i32::MAX", Log2Pb::from_bits(i32::MAX)),
    ];
    for (pn, pl) in pls {
        for (bn, pb) in pbs {
            r.case(format!("{pn}, entry {bn}"), "lod: table_lod", move || {
                match table_lod::<Accurate>(pl, pb) {
                    None if pb.is_untextured() => clamp("None (untextured)"),
                    Some(l) if !pb.is_untextured() => {
                        // Pl = 0 reads as its smallest step, 2^-32.
                        let lp = pl.to_num::<f64>().max(2f64.powi(-32)).log2();
                        let want = lod_ref(lp - pb.to_i16f16().to_num::<f64>());
                        let got = l.to_num::<f64>();
                        near("", got, want, 2.0 / 256.0, format!("{got:.4}"))
                    }
                    o => bad(format!("{o:?}")),
                }
            });
        }
    }
    for (levels, l) in [
        (0u8, Lod::MAX),
        (1, Lod::MIN),
        (16, Lod::MAX),
        (255, Lod::MAX),
    ] {
        r.case(
            format!("lod {l}, {levels} levels"),
            "lod: clamp_lod",
            move || {
                let got = clamp_lod(l, levels).to_num::<f64>();
                // Top level min(levels − 1, 127): Lod ends below 128.
                let top = f64::from((levels.max(1) - 1).min(127));
                let want = l.to_num::<f64>().clamp(0.0, top);
                if got == want {
                    clamp(format!("{got}"))
                } else {
                    bad(format!("{got} vs {want}"))
                }
            },
        );
    }
}

fn cone_lods(r: &mut Runner) {
    let widths = [
        ("w 0", Width::ZERO),
        ("w 2^-32", Width::DELTA),
        ("w -2^-32", -Width::DELTA),
        ("w MAX", Width::MAX),
        ("w MIN", Width::MIN),
    ];
    let deltas = [
        ("Δ MIN", I16F16::MIN),
        ("Δ 0", I16F16::ZERO),
        ("Δ MAX", I16F16::MAX),
    ];
    let cosines = [
        ("no n·d", None),
        ("n·d 0 (grazing)", Some(U1F31::ZERO)),
        ("n·d 2^-31", Some(U1F31::DELTA)),
        ("n·d MAX", Some(U1F31::MAX)),
    ];
    for (wn, w) in widths {
        for (dn, d) in deltas {
            for (cn, c) in cosines {
                r.case(format!("{wn}, {dn}, {cn}"), "lod: cone_lod", move || {
                    let got = cone_lod::<Accurate>(w, Delta::from_fixed(d), c).to_num::<f64>();
                    let lw = w.to_num::<f64>().abs().max(2f64.powi(-32)).log2();
                    let ln = c.map_or(0.0, |c| {
                        c.to_num::<f64>().clamp(MIN_COS.to_num(), 1.0).log2()
                    });
                    let raw = d.to_num::<f64>() + lw - ln;
                    let want = lod_ref(raw);
                    let within = near("", got, want, 2.0 / 256.0, format!("{got:.4}"))?;
                    if want != raw {
                        clamp(format!("{got:.4} (saturated)"))
                    } else {
                        Ok(within)
                    }
                });
            }
        }
    }
}

fn lods_float(r: &mut Runner) {
    r.case(
        "grazing: n·d 0 and 2^-17 equal the 2^-16 clamp",
        "lod: cone_lod",
        || {
            let w = Width::from_num(0.01);
            let d = I16F16::from_num(3);
            let at = |c: U1F31| cone_lod::<Accurate>(w, Delta::from_fixed(d), Some(c));
            let (a, b, m) = (at(U1F31::ZERO), at(U1F31::from_bits(1 << 14)), at(MIN_COS));
            if a == m && b == m && at(U1F31::from_bits(1 << 16)) < m {
                clamp(format!("{m} levels (normal term 16)"))
            } else {
                bad(format!("{a} / {b} / {m}"))
            }
        },
    );
    for (name, _, x) in FLOAT_CLASSES {
        r.case(
            name,
            "lod: table_lod_f32(pl, 0) (float baseline)",
            move || {
                let got = table_lod_f32(x, 0.0);
                let want = libm::log2f(x);
                if got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()) {
                    value(format!("{got} (documented: no check)"))
                } else {
                    bad(format!("{got} vs {want}"))
                }
            },
        );
        r.case(
            name,
            "lod: cone_lod_f32(1, 0, n·d) (float baseline)",
            move || {
                let got = cone_lod_f32(1.0, 0.0, Some(x));
                // |n·d| clamped to [2^-16, 1]: the normal term in [0, 16];
                // NaN passes through.
                if got.is_nan() == x.is_nan() && (x.is_nan() || (0.0..=16.0).contains(&got)) {
                    if x.is_nan() {
                        value("NaN (documented: no check)")
                    } else {
                        clamp(format!("{got}"))
                    }
                } else {
                    bad(format!("{got}"))
                }
            },
        );
    }
}

/// Level-0 texels with channels in `[10, 200]` and their channel range.
fn texels_for(g: &Geometry) -> Vec<Texel> {
    let mut buf = vec![0; g.len()];
    let (w, h) = g.level_size(0);
    for y in 0..h {
        for x in 0..w {
            let c = |k: u32| 10 + ((x * 7 + y * 13 + k * 29) % 191) as u8;
            buf[g.texel_index(0, x, y)] = u32::from_le_bytes([c(0), c(1), c(2), c(3)]);
        }
    }
    buf
}

/// True when every channel of `t` lies in the range of the level-0 texels
/// (a filter of convex weights cannot leave it).
fn in_range(t: Texel) -> bool {
    t.to_le_bytes().iter().all(|&c| (10..=200).contains(&c))
}

const MODES: [Mode; 4] = [
    Mode::Trilinear,
    Mode::BilinearNearestLevel,
    Mode::Nearest,
    Mode::NearestTexelLinearLevel,
];

fn sampler(r: &mut Runner) {
    let g = Geometry::new(8, 8, 4).expect("8×8, 4 levels");
    let mut buf = texels_for(&g);
    generate(&g, &mut buf).expect("exact buffer");
    for (name, x, xf) in FLOAT_CLASSES {
        for (which, edge) in [
            (0, "sampler: Sampler::sample_f64 u"),
            (1, "sampler: Sampler::sample_f64 v"),
            (2, "sampler: Sampler::sample_f64 lod"),
        ] {
            let buf = &buf;
            r.case(name, edge, move || {
                let mut seen = Vec::new();
                for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
                    let mut s =
                        Sampler::with_address(Pyramid::new(g, buf).map_err(|e| e.to_string())?, a);
                    for m in MODES {
                        let mut args = [0.3, 0.6, 1.2];
                        args[which] = x;
                        match s.sample_f64(args[0], args[1], args[2], m) {
                            Err(FilterError::NonFinite) if !x.is_finite() => {}
                            Ok(t) if x.is_finite() && in_range(t) => seen.push(t),
                            o => return bad(format!("{a:?} {m:?}: {o:?}")),
                        }
                    }
                }
                if x.is_finite() {
                    value(format!("{} texels in range", seen.len()))
                } else {
                    err("NonFinite")
                }
            });
            r.case(
                name,
                match which {
                    0 => "sampler: SamplerF32::sample u (float baseline)",
                    1 => "sampler: SamplerF32::sample v (float baseline)",
                    _ => "sampler: SamplerF32::sample lod (float baseline)",
                },
                move || {
                    for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
                        let s = SamplerF32::new(g, buf, a).ok_or("SamplerF32::new")?;
                        for m in MODES {
                            let mut args = [0.3f32, 0.6, 1.2];
                            args[which] = xf;
                            let t = s.sample(args[0], args[1], args[2], m);
                            // Documented: non-finite input, unspecified
                            // texel; finite input, a filtered one.
                            if xf.is_finite() && !in_range(t) {
                                return bad(format!("{a:?} {m:?}: {t:08x} out of range"));
                            }
                        }
                    }
                    if xf.is_finite() {
                        clamp("a texel in range")
                    } else {
                        value("a texel (documented: unspecified for non-finite input), no panic")
                    }
                },
            );
        }
    }
    let coords = [
        ("u,v MIN", TexCoord::MIN),
        ("u,v MAX", TexCoord::MAX),
        ("u,v -2^-32", -TexCoord::DELTA),
    ];
    for (cn, c) in coords {
        for (ln, l) in [("lod MIN", Lod::MIN), ("lod MAX", Lod::MAX)] {
            let buf = &buf;
            r.case(
                format!("{cn}, {ln}"),
                "sampler: Sampler::sample",
                move || {
                    for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
                        let mut s = Sampler::with_address(
                            Pyramid::new(g, buf).map_err(|e| e.to_string())?,
                            a,
                        );
                        for m in MODES {
                            let t = s.sample(c, c, l, m);
                            if !in_range(t) {
                                return bad(format!("{a:?} {m:?}: {t:08x}"));
                            }
                        }
                    }
                    clamp("clamped level and address, texels in range")
                },
            );
        }
    }
}

fn path(r: &mut Runner) {
    r.case(
        "Pl at the top of its range, 12 bounces",
        "ray stack: PathState::advance/bounce",
        || {
            let mut s = PathState::primary(&spread(), 0xA5);
            for _ in 0..12 {
                s = s.advance(PathLength::MAX).bounce(Spread::from_num(0.5));
            }
            let l = table_lod::<Accurate>(s.pl, Log2Pb::MIN).ok_or("untextured")?;
            let want = lod_ref(32.0 + 64.0);
            let ok = s.pl == PathLength::MAX
                && s.saturated
                && s.depth == 12
                && s.mask == 0xA5
                && s.cone.width == Width::MAX
                && (l.to_num::<f64>() - want).abs() <= 2.0 / 256.0;
            if ok {
                clamp(format!("Pl = MAX, w = MAX, saturated, lod {l}"))
            } else {
                bad(format!("{s:?}, lod {l}"))
            }
        },
    );
    r.case("spread ±MAX twice", "ray stack: PathState::bounce", || {
        let s = PathState::primary(&spread(), 1);
        let up = s.bounce(Spread::MAX).bounce(Spread::MAX);
        let down = s.bounce(Spread::MIN).bounce(Spread::MIN);
        if up.cone.spread == Spread::MAX
            && down.cone.spread == Spread::MIN
            && up.saturated
            && down.saturated
        {
            clamp("spread saturated at ±2, flagged")
        } else {
            bad(format!("{up:?} {down:?}"))
        }
    });
    r.case("depth 300 bounces", "ray stack: PathState::bounce", || {
        let s = (0..300).fold(PathState::default(), |p, _| p.bounce(Spread::ZERO));
        if s.depth == 255 {
            clamp("depth 255")
        } else {
            bad(format!("depth {}", s.depth))
        }
    });
    r.case(
        format!("push {} onto {DEFAULT_CAPACITY}", DEFAULT_CAPACITY + 1),
        "ray stack: RayStack::push",
        || {
            let mut st: RayStack = RayStack::new();
            let base = PathState::primary(&spread(), 0);
            for d in 0..DEFAULT_CAPACITY as u8 {
                st.push(PathState { depth: d, ..base })
                    .map_err(|e| e.to_string())?;
            }
            let extra = PathState { depth: 99, ..base };
            let res = st.push(extra);
            let order: Vec<u8> = std::iter::from_fn(|| st.pop()).map(|s| s.depth).collect();
            let want: Vec<u8> = (0..DEFAULT_CAPACITY as u8).rev().collect();
            match res {
                Err(e) if e.0 == extra && order == want => {
                    err("StackFull with the state handed back; 10 entries kept, LIFO")
                }
                o => bad(format!("{o:?}, popped {order:?}")),
            }
        },
    );
    r.case("pop an empty stack", "ray stack: RayStack::pop", || {
        let mut st: RayStack = RayStack::new();
        match st.pop() {
            None => err("None"),
            o => bad(format!("{o:?}")),
        }
    });
}

fn textures(r: &mut Runner) {
    let sizes = [
        (1u32, 1u32),
        (1, 4096),
        (4096, 1),
        (MAX_SIZE, 1),
        (1, MAX_SIZE),
        (4096, 4096),
    ];
    for (w, h) in sizes {
        r.case(
            format!("{w}×{h} texture, full chain"),
            "texture: generate + sample",
            move || {
                let levels = mip::full_levels(w, h);
                let g = Geometry::new(w, h, levels).map_err(|e| e.to_string())?;
                let want_len: u64 = (0..levels)
                    .map(|k| u64::from((w >> k).max(1)) * u64::from((h >> k).max(1)))
                    .sum();
                if g.len() as u64 != want_len || pyramid_len(w, h, levels) as u64 != want_len {
                    return bad(format!("len {} vs {want_len}", g.len()));
                }
                let mut buf = texels_for(&g);
                let level0 = g.level_size(0);
                let n0 = (level0.0 * level0.1) as usize;
                let before: Vec<Texel> = buf[..n0].to_vec();
                generate(&g, &mut buf).map_err(|e| e.to_string())?;
                if buf[..n0] != before[..] {
                    return bad("level 0 changed");
                }
                if !buf.iter().all(|&t| in_range(t)) {
                    return bad("a generated texel out of range");
                }
                let mut s = Sampler::wrap(Pyramid::new(g, &buf).map_err(|e| e.to_string())?);
                for l in [Lod::MIN, Lod::ZERO, Lod::from_num(levels), Lod::MAX] {
                    for m in MODES {
                        for c in [TexCoord::ZERO, TexCoord::from_num(0.999), TexCoord::MAX] {
                            if !in_range(s.sample(c, c, l, m)) {
                                return bad(format!("sample at lod {l} {m:?} out of range"));
                            }
                        }
                    }
                }
                value(format!("{levels} levels, {want_len} texels; level 0 kept"))
            },
        );
        r.case(
            format!("{w}×{h} pyramid, storage one texel short"),
            "texture: generate / Pyramid::new",
            move || {
                let g = Geometry::new(w, h, mip::full_levels(w, h)).map_err(|e| e.to_string())?;
                let mut buf = texels_for(&g);
                buf.pop();
                let before = buf.clone();
                let (n, got) = (g.len(), buf.len());
                let a = generate(&g, &mut buf);
                let b = Pyramid::new(g, &buf).map(|_| ());
                let want = Err(MipError::BufferTooShort { needed: n, got });
                if a == want && b == want && buf == before {
                    err(format!(
                        "BufferTooShort {{ needed: {n}, got: {got} }}, buffer untouched"
                    ))
                } else {
                    bad(format!("{a:?} / {b:?}"))
                }
            },
        );
    }
}

fn texture_limits(r: &mut Runner) {
    r.case(
        format!("{MAX_SIZE}×{MAX_SIZE} texture (geometry only)"),
        "texture: Geometry::new",
        || {
            let g = Geometry::new(MAX_SIZE, MAX_SIZE, 16).map_err(|e| e.to_string())?;
            let want: u64 = (0..16).map(|k| (u64::from(MAX_SIZE) >> k).pow(2)).sum();
            if g.len() as u64 == want {
                value(format!("{want} texels, 16 levels"))
            } else {
                bad(format!("{} vs {want}", g.len()))
            }
        },
    );
    for (name, w, h, l, want) in [
        ("side MAX_SIZE + 1", MAX_SIZE + 1, 1, 1, MipError::TooLarge),
        ("width 0", 0, 16, 1, MipError::ZeroSize),
        ("0 levels", 16, 16, 0, MipError::BadLevels),
        ("full_levels + 1", 16, 16, 6, MipError::BadLevels),
    ] {
        r.case(
            name,
            "texture: Geometry::new",
            move || match Geometry::new(w, h, l) {
                Err(e) if e == want => err(format!("{e:?}")),
                o => bad(format!("{o:?}")),
            },
        );
    }
    r.case("sides u32::MAX, 255 levels", "texture: pyramid_len", || {
        if pyramid_len(u32::MAX, u32::MAX, 255) == usize::MAX {
            clamp("usize::MAX (saturated)")
        } else {
            bad(format!("{}", pyramid_len(u32::MAX, u32::MAX, 255)))
        }
    });
}

/// `rm_table_build` of `len` entries at `entries` from no triangles, no
/// statistics.
///
/// # Safety
/// `entries` is null, misaligned (both refused before any access) or valid
/// for `len` writes.
#[allow(unsafe_code)]
unsafe fn build_empty(entries: *mut i32, len: usize, spread: i32) -> RmStatus {
    // SAFETY: `entries` as this function's contract; no triangles, no stats.
    unsafe {
        ffi::rm_table_build(
            entries,
            len,
            std::ptr::null(),
            0,
            spread,
            std::ptr::null_mut(),
        )
    }
}

#[allow(unsafe_code)]
fn c_abi(r: &mut Runner) {
    let sp = spread().angle().to_bits();
    r.case("null entries, len 4", "C ABI: rm_table_build", move || {
        // SAFETY: null is a documented input.
        let s = unsafe { build_empty(std::ptr::null_mut(), 4, sp) };
        refused(s, RmStatus::NullPointer, true, "NullPointer")
    });
    r.case("misaligned entries", "C ABI: rm_table_build", move || {
        let mut raw = [0i32; 4];
        let p = raw.as_mut_ptr().cast::<u8>().wrapping_add(1).cast::<i32>();
        // SAFETY: the misaligned pointer is refused before any access.
        let s = unsafe { build_empty(p, 2, sp) };
        refused(
            s,
            RmStatus::Misaligned,
            raw == [0; 4],
            "Misaligned, nothing written",
        )
    });
    for (name, bad) in [("spread 0", 0), ("spread i32::MIN", i32::MIN)] {
        r.case(name, "C ABI: rm_table_build", move || {
            let mut e = [0i32; 1];
            // SAFETY: valid pointer, one entry.
            let s = unsafe { build_empty(e.as_mut_ptr(), 1, bad) };
            refused(s, RmStatus::BadAngle, true, "BadAngle")
        });
    }
    r.case("untextured entry, null out", "C ABI: rm_table_lod", || {
        let mut out = 77i16;
        // SAFETY: valid or null pointers.
        let a = unsafe { ffi::rm_table_lod(1 << 32, RM_UNTEXTURED, &mut out) };
        let b = unsafe { ffi::rm_table_lod(1 << 32, 0, std::ptr::null_mut()) };
        if a == RmStatus::Untextured && out == 77 && b == RmStatus::NullPointer {
            err("Untextured (out untouched); NullPointer")
        } else {
            bad(format!("{a:?} {out} {b:?}"))
        }
    });
}

#[allow(unsafe_code)]
fn c_abi_lod(r: &mut Runner) {
    r.case(
        "grazing n·d = 0, extreme width and Δ",
        "C ABI: rm_cone_lod",
        || {
            for w in [0i64, 1, i64::MIN, i64::MAX] {
                for d in [i32::MIN, 0, i32::MAX] {
                    for c in [0u32, 1, 1 << 15, u32::MAX] {
                        let got = ffi::rm_cone_lod(w, d, c);
                        let rust = cone_lod::<Accurate>(
                            Width::from_bits(w),
                            Delta::from_bits(d),
                            Some(U1F31::from_bits(c)),
                        );
                        if got != rust.to_bits() {
                            return bad(format!(
                                "w {w} Δ {d} n·d {c}: C {got} vs Rust {}",
                                rust.to_bits()
                            ));
                        }
                    }
                }
            }
            clamp("C equals Rust on 48 extreme triples (n·d clamped to 2^-16)")
        },
    );
    r.case(
        "lod i16::MIN/MAX, 0 and 255 levels",
        "C ABI: rm_clamp_lod",
        || {
            let a = ffi::rm_clamp_lod(i16::MIN, 0);
            let b = ffi::rm_clamp_lod(i16::MAX, 255);
            let want_b = I8F8::from_num(127).to_bits();
            if a == 0 && b == want_b {
                clamp(format!("{a}, {b}"))
            } else {
                bad(format!("{a}, {b}"))
            }
        },
    );
    r.case(
        "sides u32::MAX, 255 levels",
        "C ABI: rm_pyramid_len",
        || {
            let n = ffi::rm_pyramid_len(u32::MAX, u32::MAX, 255);
            if n == usize::MAX {
                clamp("usize::MAX")
            } else {
                bad(format!("{n}"))
            }
        },
    );
    r.case("storage one texel short", "C ABI: rm_mip_generate", || {
        let g = Geometry::new(64, 32, 7).map_err(|e| e.to_string())?;
        let mut buf = texels_for(&g);
        buf.pop();
        let before = buf.clone();
        // SAFETY: `buf` holds `len` texels.
        let s = unsafe { ffi::rm_mip_generate(buf.as_mut_ptr(), buf.len(), 64, 32, 7) };
        refused(
            s,
            RmStatus::BufferTooShort,
            buf == before,
            "BufferTooShort, buffer untouched",
        )
    });
}

/// Sets up a C ABI sampler for `tex` with addressing `address` and, if that
/// succeeds, samples it once at `(u, u)`, lod `lod`, filter `mode`.
#[allow(unsafe_code)]
fn sample_once(
    tex: &RmTexture,
    u: i64,
    lod: i16,
    mode: u8,
    address: u8,
    out: &mut u32,
) -> RmStatus {
    let mut sm = RmSampler {
        opaque: [0; ffi::RM_SAMPLER_WORDS],
    };
    // SAFETY: `tex` describes a live buffer that outlives `sm`; `sm` and
    // `out` are writable locals.
    unsafe {
        match ffi::rm_sampler_init(&mut sm, tex, RmAddressBits(address)) {
            RmStatus::Ok => ffi::rm_sample(&mut sm, u, u, lod, RmModeBits(mode), out),
            s => s,
        }
    }
}

fn c_abi_sample(r: &mut Runner) {
    let g = Geometry::new(8, 8, 4).expect("8×8");
    let mut tex_buf = texels_for(&g);
    generate(&g, &mut tex_buf).expect("exact");
    let tex = RmTexture {
        texels: tex_buf.as_ptr(),
        len: tex_buf.len(),
        width: 8,
        height: 8,
        levels: 4,
    };
    for (name, u, lod, mode, address, want) in [
        (
            "mode 255",
            0i64,
            0i16,
            255u8,
            0u8,
            Some(RmStatus::OutOfRange),
        ),
        ("address 255", 0, 0, 0, 255, Some(RmStatus::OutOfRange)),
        ("u,v i64::MIN, lod i16::MIN", i64::MIN, i16::MIN, 0, 0, None),
        ("u,v i64::MAX, lod i16::MAX", i64::MAX, i16::MAX, 3, 1, None),
    ] {
        r.case(name, "C ABI: rm_sampler_init/rm_sample", move || {
            let mut out = 0u32;
            let s = sample_once(&tex, u, lod, mode, address, &mut out);
            match (s, want) {
                (s, Some(w)) if s == w && out == 0 => err(format!("{s:?}, nothing written")),
                (RmStatus::Ok, None) if in_range(out) => clamp("a texel in range"),
                o => bad(format!("{o:?} {out:08x}")),
            }
        });
    }
    r.case(
        "texture len one texel short",
        "C ABI: rm_sampler_init/rm_sample",
        move || {
            let short = RmTexture {
                len: tex.len - 1,
                ..tex
            };
            let mut out = 0u32;
            let s = sample_once(&short, 0, 0, 0, 0, &mut out);
            refused(s, RmStatus::BufferTooShort, out == 0, "BufferTooShort")
        },
    );
    r.case(
        "push capacity + 1, pop capacity + 1",
        "C ABI: rm_ray_stack_push/pop",
        || {
            let mut st = RmRayStack {
                entries: [RmPathState::default(); ffi::RM_RAY_STACK_CAPACITY],
                len: 0,
            };
            let mut pushed = Vec::new();
            for d in 0..=ffi::RM_RAY_STACK_CAPACITY as u8 {
                let e = RmPathState {
                    depth: d,
                    pl: u64::from(d) << 32,
                    ..RmPathState::default()
                };
                // SAFETY: valid pointers.
                pushed.push(unsafe { ffi::rm_ray_stack_push(&mut st, &e) });
            }
            let mut popped = Vec::new();
            let mut out = RmPathState::default();
            // SAFETY: valid pointers.
            while unsafe { ffi::rm_ray_stack_pop(&mut st, &mut out) } == RmStatus::Ok {
                popped.push(out.depth);
            }
            let want: Vec<u8> = (0..ffi::RM_RAY_STACK_CAPACITY as u8).rev().collect();
            if pushed.last() == Some(&RmStatus::StackFull) && popped == want {
                err("StackFull on the 11th push; 10 entries kept, LIFO")
            } else {
                bad(format!("{pushed:?} {popped:?}"))
            }
        },
    );
}

#[allow(unsafe_code)]
fn c_abi_stack(r: &mut Runner) {
    let sp = spread().angle().to_bits();
    r.case(
        "corrupt len u32::MAX",
        "C ABI: rm_ray_stack_push/pop",
        || {
            let mut st = RmRayStack {
                entries: [RmPathState::default(); ffi::RM_RAY_STACK_CAPACITY],
                len: u32::MAX,
            };
            let e = RmPathState::default();
            let mut out = RmPathState {
                depth: 7,
                ..RmPathState::default()
            };
            // SAFETY: valid pointers; the length is corrupt on purpose.
            let a = unsafe { ffi::rm_ray_stack_push(&mut st, &e) };
            let b = unsafe { ffi::rm_ray_stack_pop(&mut st, &mut out) };
            if a == RmStatus::StackFull
                && b == RmStatus::Ok
                && st.len as usize == ffi::RM_RAY_STACK_CAPACITY - 1
            {
                clamp("read as full: push StackFull, pop the top entry")
            } else {
                bad(format!("{a:?} {b:?} len {}", st.len))
            }
        },
    );
    r.case(
        "spread 0, t = u64::MAX × 12",
        "C ABI: rm_path_primary/advance",
        || {
            let mut s = RmPathState::default();
            // SAFETY: valid pointers.
            let a = unsafe { ffi::rm_path_primary(0, 1, &mut s) };
            let b = unsafe { ffi::rm_path_primary(sp, 1, &mut s) };
            for _ in 0..12 {
                // SAFETY: valid pointer.
                unsafe { ffi::rm_path_advance(&mut s, u64::MAX) };
            }
            if a == RmStatus::BadAngle && b == RmStatus::Ok && s.pl == u64::MAX && s.saturated != 0
            {
                clamp("BadAngle; Pl saturated at MAX, flagged")
            } else {
                bad(format!("{a:?} {b:?} {s:?}"))
            }
        },
    );
}

fn scene_file(r: &mut Runner) {
    let dir = std::env::temp_dir().join(format!("raymip-stress-{}", std::process::id()));
    for (name, text) in [
        (
            "NaN vertex",
            "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 8 8\nf 1 1 1 0 0 0 0 0\np 3\nnan 0 0\n1 0 0\n0 1 0\n",
        ),
        (
            "inf vertex",
            "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 8 8\nf 1 1 1 0 0 0 0 0\np 3\n0 0 0\n1e400 0 0\n0 1 0\n",
        ),
        (
            "NaN camera angle",
            "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle nan\nhither 0.01\nresolution 8 8\n",
        ),
    ] {
        let dir = dir.clone();
        r.case(name, "scene: load_aff", move || {
            std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
            let p = dir.join("s.aff");
            std::fs::write(&p, text).map_err(|e| e.to_string())?;
            let res = crate::scene::load_aff(&p, 0.0).map_err(|e| e.to_string());
            match res {
                Err(e) if e.contains("s.aff") => err(e.lines().next().unwrap_or("").to_string()),
                Err(e) => bad(format!("error without the file: {e}")),
                Ok(_) => bad("accepted"),
            }
        });
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The table as Markdown (one row per case) and the totals line.
#[must_use]
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::from("| # | class | edge | result | outcome |\n|---|---|---|---|---|\n");
    for (i, r) in rows.iter().enumerate() {
        let (res, out) = match (&r.result, r.panicked) {
            (Err(e), true) => (e.0.clone(), "PANICKED"),
            (Err(e), false) => (e.0.clone(), "MISBEHAVED"),
            (Ok((k, v)), _) => (
                v.clone(),
                match k {
                    Kind::Error => "error value",
                    Kind::Clamp => "clamp",
                    Kind::Value => "value",
                },
            ),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {out} |",
            i + 1,
            r.class,
            r.edge,
            res.replace('|', "\\|")
        );
    }
    s.push('\n');
    s.push_str(&totals_line(&Totals::of(rows)));
    s.push('\n');
    s
}

/// `N cases: … error values, … clamps, … values; … misbehaved, … panicked`.
#[must_use]
pub fn totals_line(t: &Totals) -> String {
    format!(
        "{} cases: {} error values, {} clamps, {} values; {} misbehaved, {} panicked",
        t.cases, t.errors, t.clamps, t.values, t.misbehaved, t.panicked
    )
}

/// Number of distinct API edges in the rows.
#[must_use]
pub fn edges(rows: &[Row]) -> usize {
    let mut e: Vec<&str> = rows.iter().map(|r| r.edge).collect();
    e.sort_unstable();
    e.dedup();
    e.len()
}

/// `raymip-host stress`: prints the table and the totals; with `readme`,
/// also writes the totals between `<!-- stress:begin -->` and
/// `<!-- stress:end -->` of that file. Err (non-zero exit) when anything
/// panicked or misbehaved.
///
/// # Errors
/// A panicked or misbehaving case (named), or the docs/reliability.md block not written.
pub fn cmd_stress(readme: Option<&Path>) -> Result<(), StressError> {
    let rows = run();
    print!("{}", markdown(&rows));
    if let Some(path) = readme {
        write_readme(&rows, path)?;
    }
    verdict(&rows)
}

/// `stress --write-readme PATH` without the table on stdout (the test that
/// the docs/reliability.md block is current).
///
/// # Errors
/// As [`cmd_stress`].
pub fn cmd_stress_quiet(readme: &Path) -> Result<(), StressError> {
    let rows = run();
    write_readme(&rows, readme)?;
    verdict(&rows)
}

fn write_readme(rows: &[Row], path: &Path) -> Result<(), OutputError> {
    let text = format!(
        "Measured by `raymip-host stress --write-readme docs/reliability.md` ({} {}): {} API edges, **{}**.\n",
        std::env::consts::ARCH,
        std::env::consts::OS,
        edges(rows),
        totals_line(&Totals::of(rows))
    );
    write_between_markers(path, "stress", &text)
}

fn verdict(rows: &[Row]) -> Result<(), StressError> {
    let t = Totals::of(rows);
    if t.clean() {
        Ok(())
    } else {
        let bad: Vec<String> = rows
            .iter()
            .filter(|r| r.result.is_err())
            .map(|r| {
                format!(
                    "{} / {}: {}",
                    r.edge,
                    r.class,
                    r.result.as_ref().err().map_or("", |e| e.0.as_str())
                )
            })
            .collect();
        Err(StressError::Misbehaved {
            misbehaved: t.misbehaved,
            panicked: t.panicked,
            cases: bad,
        })
    }
}

/// A 48×32 render (table and cone methods, fixed and float, 12 bounces)
/// of a scene with a zero-area and a collinear textured triangle, a
/// zero-UV-area one, a floor seen at grazing incidence from 10⁻³ above it
/// and two facing mirrors.
fn degenerate_scene() -> crate::scene::Scene {
    use crate::scene::builtin::{quads, tiles_texture};
    use crate::scene::{Camera, Light, Material, Scene, Triangle, V3};
    let mat = |specular: f64| Material {
        ambient: V3::splat(0.2),
        diffuse: V3::splat(0.7),
        specular: V3::splat(specular),
        shine: 50.0,
        transmission: V3::ZERO,
        ior: 1.0,
    };
    let tri = |p: [V3; 3], uv: [[f64; 2]; 3]| Triangle {
        p,
        n: None,
        uv: Some(uv),
        material: 0,
        texture: Some(0),
    };
    let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let mut t = vec![
        tri([V3::new(0.0, 1.0, -3.0); 3], uv),
        tri(
            [
                V3::new(-1.0, 0.5, -3.0),
                V3::new(0.0, 1.0, -3.0),
                V3::new(1.0, 1.5, -3.0),
            ],
            uv,
        ),
        tri(
            [
                V3::new(-1.0, 0.5, -2.5),
                V3::new(1.0, 0.5, -2.5),
                V3::new(0.0, 1.5, -2.5),
            ],
            [[0.5, 0.5]; 3],
        ),
    ];
    // A long floor and two panels at z = ∓6.
    #[rustfmt::skip]
    t.extend(quads(&[
        ([-50.0, 0.0, 5.0], [100.0, 0.0, 0.0], [0.0, 0.0, -200.0], [50.0, 100.0], 0, Some(0)),
        ([-3.0, 0.0, -6.0], [6.0, 0.0, 0.0],   [0.0, 3.0, 0.0],    [1.0, 1.0],    1, None),
        ([-3.0, 0.0, 6.0],  [6.0, 0.0, 0.0],   [0.0, 3.0, 0.0],    [1.0, 1.0],    1, None),
    ]));
    Scene {
        camera: Camera::looking_at(
            V3::new(0.0, 1.0e-3, 0.0),
            V3::new(0.0, 1.0e-3, -1.0),
            60.0,
            (48, 32),
        ),
        background: V3::splat(0.5),
        environment: None,
        ambient: V3::splat(0.2),
        lights: vec![Light {
            position: V3::new(0.0, 5.0, 0.0),
            color: V3::splat(0.8),
        }],
        materials: vec![mat(0.0), mat(0.95)],
        textures: vec![tiles_texture()],
        triangles: t,
    }
}

fn render_degenerate(r: &mut Runner) {
    use crate::render::{Method, Options, Precision, Prepared, render};
    let scene = degenerate_scene();
    for method in [Method::Table, Method::Cone] {
        for precision in [Precision::Fixed, Precision::Float] {
            let scene = scene.clone();
            r.case(
                format!(
                    "zero-area, collinear, zero-UV triangles; grazing floor; mirrors ({} {})",
                    method.name(),
                    precision.name()
                ),
                "renderer: render (12 bounces)",
                move || {
                    let prep = Prepared::new(scene, None).map_err(|e| e.to_string())?;
                    let img = render(
                        &prep,
                        &Options {
                            method,
                            precision,
                            size: None,
                            bounces: 12,
                            spp: 1,
                            record_blocks: false,
                            progress: false,
                            aniso: None,
                        },
                    );
                    let c = &img.counters;
                    if img.rgb.iter().flatten().all(|x| x.is_finite())
                        && c.stack_full == 0
                        && c.textured_hits > 0
                    {
                        value(format!(
                            "{} textured hits, deepest path {}, finite image, no branch dropped",
                            c.textured_hits,
                            c.max_depth()
                        ))
                    } else {
                        bad(format!("{c:?}"))
                    }
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdict_names_each_misbehaving_case() {
        let row = |class: &str, result| Row {
            class: class.into(),
            edge: "PbTable::update",
            result,
            panicked: false,
        };
        let rows = [
            row("NaN", Ok((Kind::Error, "NonFinite".into()))),
            row("huge", Err("entry 99 outside [-64, 64]".into())),
        ];
        let e = verdict(&rows).unwrap_err();
        assert!(
            matches!(
                &e,
                StressError::Misbehaved {
                    misbehaved: 1,
                    panicked: 0,
                    ..
                }
            ),
            "{e:?}"
        );
        let text = e.to_string();
        assert!(
            text.contains("PbTable::update / huge: entry 99 outside [-64, 64]"),
            "{text}"
        );
        assert!(verdict(&rows[..1]).is_ok());
    }
}
