//! Lod edges: table and cone lods in fixed point and the f32 baselines.

use fixed::types::{I16F16, U1F31};
use raymip::baseline_f32::{cone_lod_f32, table_lod_f32};
use raymip::lod::{clamp_lod, cone_lod, table_lod};
use raymip::units::MIN_COS;
use raymip::units::{Accurate, Delta, Lod, Log2Pb, PathLength, Width};

use super::{FLOAT_CLASSES, Runner, bad, clamp, near, value};

pub(super) fn lod_ref(l: f64) -> f64 {
    l.clamp(Lod::MIN.to_num(), Lod::MAX.to_num())
}

pub(super) fn lods(r: &mut Runner) {
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

pub(super) fn cone_lods(r: &mut Runner) {
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

pub(super) fn lods_float(r: &mut Runner) {
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
