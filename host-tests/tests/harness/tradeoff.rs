//! `raymip-host tradeoff --quick` (CI): every file is written, every
//! configuration has a time and an error, and the errors are sane: the
//! f64 anchors have error 0, the firmware's accurate and fast lods stay
//! within their documented 2⁻⁸ levels, the fixed-point filters within their
//! rounding bounds, the accumulated stochastic filters closer to their
//! expectation than one frame.

use std::path::Path;
use std::process::Command;

use raymip::lod::LOD_MAX_ERROR;
use raymip::lod::raydiff::RAYDIFF_LOD_MAX_ERROR;
use raymip::texture::kernel::accurate::BILERP_MAX_ERROR_LSB;
use raymip_host::accuracy::ANISO_LOD_ERROR_LSB;
use serde_json::Value;

fn run(out: &Path) -> Vec<Value> {
    let st = Command::new(env!("CARGO_BIN_EXE_raymip-host"))
        .args(["tradeoff", "--quick", "--out"])
        .arg(out)
        .status()
        .expect("run raymip-host");
    assert!(st.success(), "tradeoff --quick failed: {st}");
    let text = std::fs::read_to_string(out.join("tradeoff.json")).expect("tradeoff.json");
    match serde_json::from_str(&text).expect("JSON") {
        Value::Array(rows) => rows,
        v => panic!("tradeoff.json is not an array: {v}"),
    }
}

fn f(r: &Value, k: &str) -> Option<f64> {
    r.get(k).and_then(Value::as_f64)
}

fn s<'a>(r: &'a Value, k: &str) -> &'a str {
    r.get(k).and_then(Value::as_str).unwrap_or("")
}

fn find<'a>(
    rows: &'a [Value],
    stage: &str,
    method: &str,
    precision: &str,
    filter: Option<&str>,
) -> &'a Value {
    rows.iter()
        .find(|r| {
            s(r, "stage") == stage
                && s(r, "method") == method
                && s(r, "precision") == precision
                && filter.is_none_or(|x| s(r, "filter") == x)
                && f(r, "frames") == Some(1.0)
        })
        .unwrap_or_else(|| panic!("no row {stage} {method} {precision} {filter:?}"))
}

#[test]
fn quick_run_writes_everything_and_errors_are_sane() {
    let out = std::env::temp_dir().join(format!("raymip-tradeoff-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let rows = run(&out);
    for stem in raymip_host::tradeoff::report::CHARTS {
        for ext in ["png", "svg"] {
            let p = out.join(format!("{stem}.{ext}"));
            let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
            assert!(len > 1000, "{} missing or empty", p.display());
        }
    }
    let md = std::fs::read_to_string(out.join("tradeoff.md")).expect("tradeoff.md");
    assert!(
        md.contains("Pareto-optimal") && md.contains("Machine:"),
        "{md}"
    );

    // Every stage present; every configuration timed and measured.
    for stage in ["lod", "filter", "frame"] {
        assert!(
            rows.iter().any(|r| s(r, "stage") == stage),
            "no {stage} rows"
        );
    }
    for r in &rows {
        for k in [
            "stage",
            "method",
            "precision",
            "filter",
            "time_ns",
            "time_ms",
            "instructions_m4",
            "instructions_rv32",
            "error_max",
            "error_rms",
            "psnr_truth_db",
        ] {
            assert!(r.get(k).is_some(), "key {k} missing in {r}");
        }
        let t = f(r, "time_ns").or(f(r, "time_ms"));
        assert!(t.is_some_and(|t| t.is_finite() && t > 0.0), "no time: {r}");
        let (max, rms) = (f(r, "error_max").unwrap(), f(r, "error_rms").unwrap());
        assert!(
            max.is_finite() && rms.is_finite() && (0.0..=max + 1e-12).contains(&rms),
            "errors: {r}"
        );
        if s(r, "stage") == "frame" {
            assert!(f(r, "psnr_truth_db").is_some_and(|p| p > 5.0), "psnr: {r}");
        }
    }
    assert!(
        rows.iter()
            .any(|r| r.get("pareto") == Some(&Value::Bool(true)))
    );

    // Frame cost on the controller: counted calls × BUDGETS.md. Costed:
    // the bilinear and trilinear rows (BUDGETS.md counts those samples);
    // f64 rows at their f32 twins' counts, which are larger than fixed
    // point's for every call; a trilinear frame costs more than a bilinear
    // one (same hits, 240 against 116 instructions per sample); PicoRV32
    // cycles exceed M4 instructions (CPI above 4 on the soft core).
    let cost = |m: &str, p: &str, fl: &str| f(find(&rows, "frame", m, p, Some(fl)), "frame_m4");
    for m in ["table", "cone", "mip0"] {
        for fl in ["bilinear", "trilinear"] {
            if m == "mip0" && fl == "trilinear" {
                continue;
            }
            let fx = cost(m, "fixed accurate", fl).unwrap_or_else(|| panic!("{m} {fl}: no cost"));
            let fl64 = cost(m, "f64", fl).unwrap_or_else(|| panic!("{m} {fl} f64: no cost"));
            assert!(fx > 0.0 && fl64 > fx, "{m} {fl}: fixed {fx}, f64 {fl64}");
            let r = find(&rows, "frame", m, "fixed accurate", Some(fl));
            let cycles = f(r, "frame_picorv32").unwrap_or_else(|| panic!("{m} {fl}: no cycles"));
            assert!(cycles > fx, "{m} {fl}: {cycles} cycles, {fx} instructions");
        }
        assert!(
            cost(m, "fixed accurate", "nearest").is_none(),
            "{m} nearest: BUDGETS.md counts no nearest sample"
        );
    }
    assert!(
        cost("table", "fixed accurate", "trilinear") > cost("table", "fixed accurate", "bilinear")
    );
    // Ray differentials cost more than a cone per frame; a G-buffer's first
    // hits (set-up instead of transfer) make its frame cheaper than the
    // ray-traced one's (the talk: about 2× and 3× a cone's cost).
    let tri = |m| cost(m, "fixed accurate", "trilinear").unwrap_or_else(|| panic!("{m}: no cost"));
    let (cone, rt, gb) = (tri("cone"), tri("raydiff"), tri("gbuffer"));
    assert!(
        cone < gb && gb < rt,
        "cone {cone}, gbuffer {gb}, raydiff {rt}"
    );
    assert!(
        rows.iter()
            .any(|r| r.get("pareto_cost") == Some(&Value::Bool(true)))
    );

    // LOD: f64 anchors exact; the firmware within 2⁻⁸; f32 libm far closer
    // than the firmware; the cheapest variant (no table) visibly worse.
    for m in ["table", "cone", "cone+normal", "raydiff"] {
        assert_eq!(
            f(find(&rows, "lod", m, "f64", None), "error_max"),
            Some(0.0),
            "{m} f64"
        );
    }
    for m in ["table", "cone", "cone+normal"] {
        let fx = f(find(&rows, "lod", m, "fixed accurate", None), "error_max").unwrap();
        assert!(fx <= LOD_MAX_ERROR && fx > 0.0, "{m} fixed: {fx}");
        // The FAST path: the same documented bound.
        let fast = f(find(&rows, "lod", m, "fixed fast", None), "error_max").unwrap();
        assert!(
            fast <= LOD_MAX_ERROR && fast > 0.0,
            "{m} fixed fast: {fast}"
        );
        let libm = f(find(&rows, "lod", m, "f32 libm", None), "error_max").unwrap();
        assert!(libm < 1e-4, "{m} f32: {libm}");
        let mitchell = f(find(&rows, "lod", m, "fixed mitchell", None), "error_max").unwrap();
        assert!(
            mitchell > 0.05 && mitchell < 0.1,
            "{m} mitchell: {mitchell}"
        );
    }
    // Ray differentials: the firmware lod of the same footprints within
    // its documented bound, with its BUDGETS.md count.
    let rd = find(&rows, "lod", "raydiff", "fixed accurate", None);
    let rd_err = f(rd, "error_max").unwrap();
    assert!(
        rd_err <= RAYDIFF_LOD_MAX_ERROR && rd_err > 0.0,
        "raydiff fixed: {rd_err}"
    );
    assert!(
        f(rd, "instructions_m4").is_some(),
        "BUDGETS.md counts not read: {rd}"
    );
    for p in ["fixed accurate", "fixed fast"] {
        let table = find(&rows, "lod", "table", p, None);
        assert!(
            f(table, "instructions_m4").is_some(),
            "BUDGETS.md counts not read: {table}"
        );
    }

    // Filters: each fixed filter within the rounding bound of its own
    // exact filter; stochastic means converge toward their expectation.
    for filt in ["nearest", "bilinear", "trilinear"] {
        let r = find(&rows, "filter", "sample", "fixed accurate", Some(filt));
        let own = f(r, "own_error_max").unwrap();
        assert!(own <= BILERP_MAX_ERROR_LSB, "{filt}: {own}");
    }
    for filt in [
        "stochastic trilinear",
        "stochastic bilinear",
        "stochastic trilinear+bilinear",
    ] {
        let one = find(&rows, "filter", "sample", "fixed accurate", Some(filt));
        let acc = rows
            .iter()
            .find(|r| s(r, "filter") == filt && f(r, "frames").unwrap_or(1.0) > 1.0)
            .unwrap_or_else(|| panic!("no accumulated {filt}"));
        let (a, b) = (
            f(one, "own_error_rms").unwrap(),
            f(acc, "own_error_rms").unwrap(),
        );
        assert!(
            b < a / 2.0,
            "{filt}: RMS {a} after one frame, {b} accumulated"
        );
    }

    // Anisotropic: the fixed rows within the sampler's bound plus the probe
    // lod's error of their own exact filter, f32 within ½ LSB + f32
    // rounding; more probes come closer to the 16× target; the capped
    // fixed rows carry their BUDGETS.md counts.
    let aniso_bound = BILERP_MAX_ERROR_LSB + ANISO_LOD_ERROR_LSB;
    for cap in [1, 2, 4, 16] {
        let filt = format!("anisotropic {cap}×");
        let fx = find(&rows, "filter", "sample", "fixed accurate", Some(&filt));
        let own = f(fx, "own_error_max").unwrap();
        assert!(own <= aniso_bound, "{filt} fixed: {own}");
        let fl = find(&rows, "filter", "sample", "f32 libm", Some(&filt));
        let own = f(fl, "own_error_max").unwrap();
        assert!(own <= 0.5 + 1.0 / 64.0, "{filt} f32: {own}");
        if cap > 1 {
            assert!(
                f(fx, "instructions_m4").is_some(),
                "BUDGETS.md counts not read: {fx}"
            );
        }
    }
    let rms = |cap: u32| {
        let filt = format!("anisotropic {cap}×");
        f(
            find(&rows, "filter", "sample", "fixed accurate", Some(&filt)),
            "error_rms",
        )
        .unwrap()
    };
    assert!(
        rms(16) < rms(4) && rms(4) < rms(2) && rms(2) < rms(1),
        "{} {} {} {}",
        rms(1),
        rms(2),
        rms(4),
        rms(16)
    );
    std::fs::remove_dir_all(&out).ok();
}
