//! Set-up edges: the camera pixel spread and the Pb table (triangles,
//! degenerate geometry, limits).

use fixed::types::I2F30;
use raymip::setup::camera::{CameraError, PixelSpread};
use raymip::setup::table::{PbTable, TableError, TexTriangle};
use raymip::units::{Coord, Log2Pb, Spread, TexCoord};

use super::Misbehaviour;
use super::{FLOAT_CLASSES, Outcome, Runner, bad, clamp, err, near, value};

pub(super) fn spread() -> PixelSpread {
    PixelSpread::from_fov_y(60f64.to_radians(), 480).expect("60° over 480 rows")
}

pub(super) fn camera(r: &mut Runner) {
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

pub(super) const TRI_P: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
pub(super) const TRI_UV: [[f32; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

/// Builds a 3-entry table whose entries 0 and 2 hold a sentinel and entry
/// 1 the triangle; fails when a sentinel changed.
pub(super) fn entry_of(tri: TexTriangle) -> Result<(Log2Pb, u32), Misbehaviour> {
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

pub(super) fn check_entry(e: Log2Pb) -> Outcome {
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

pub(super) fn table(r: &mut Runner) {
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

pub(super) fn table_geometry(r: &mut Runner) {
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

pub(super) fn table_limits(r: &mut Runner) {
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
