//! The CLI's render / compare / table1 commands end to end (small sizes).

use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("raymip-cli-{}-{name}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    d
}

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_raymip-host"))
        .args(args)
        .output()
        .expect("run raymip-host")
}

/// `run(args)`, which must succeed.
fn run_ok(args: &[&str]) -> std::process::Output {
    let o = run(args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// `render --scene builtin:hall ARGS --out OUT`: must succeed; its
/// `report.json`.
fn render_hall(out: &Path, args: &[&str]) -> serde_json::Value {
    run_ok(
        &[
            &["render", "--scene", "builtin:hall"],
            args,
            &["--out", out.to_str().unwrap()],
        ]
        .concat(),
    );
    serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap()
}

#[test]
fn render_writes_image_levels_and_reports() {
    let out = tmp("render");
    let r = render_hall(&out, &["--size", "80x48"]);
    for f in ["image.png", "levels.png", "report.json", "report.md"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    assert_eq!(r["width"], 80);
    assert_eq!(r["method"], "table");
    assert_eq!(r["precision"], "fixed");
    assert_eq!(r["counters"]["paths"], 80 * 48);
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn render_with_anisotropic_filtering() {
    let out = tmp("aniso");
    let aniso = ["--filter", "aniso", "--max-aniso"];
    let r = render_hall(
        &out,
        &[
            &["--size", "40x24", "--method", "raydiff"],
            &aniso[..],
            &["8"],
        ]
        .concat(),
    );
    assert_eq!(r["max_aniso"], 8);
    let o = run(&[
        &["render", "--scene", "builtin:hall"],
        &aniso[..],
        &["17", "--out", out.to_str().unwrap()],
    ]
    .concat());
    assert!(!o.status.success());
    // The table and cone methods have no footprint: refused, never a
    // silent switch to ray differentials.
    for m in ["table", "cone"] {
        let o = run(&[
            &[
                "render",
                "--scene",
                "builtin:hall",
                "--size",
                "8x8",
                "--method",
                m,
            ],
            &aniso[..],
            &["4", "--out", out.to_str().unwrap()],
        ]
        .concat());
        assert!(!o.status.success(), "{m}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains("--method raydiff"), "{m}: {e}");
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn compare_and_table1_run_on_builtin_scenes() {
    let out = tmp("compare");
    run_ok(&[
        "compare",
        "--scene",
        "builtin:glass",
        "--size",
        "40x24",
        "--spp",
        "4",
        "--methods",
        "table,mip0",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(out.join("diff_table_fixed_vs_float.png").is_file());
    assert!(out.join("compare.json").is_file());
    let o = run_ok(&[
        "table1",
        "--scenes",
        "/nonexistent-raymip",
        "--builtin",
        "--size",
        "40x24",
        "--out",
        out.to_str().unwrap(),
    ]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("SKIP") && s.contains("builtin:mirrors"), "{s}");
    assert!(out.join("table1.md").is_file());
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn bad_inputs_are_clear_errors() {
    let never = ["--out", "/tmp/raymip-never"];
    for (args, says) in [
        (
            &["render", "--scene", "builtin:nope"][..],
            "unknown built-in scene",
        ),
        (&["render", "--scene", "/no/such.aff"][..], "/no/such.aff"),
        (
            &["render", "--scene", "builtin:hall", "--size", "0x3"][..],
            "--size `0x3`: `0` is not a number in 1..=16384",
        ),
        (
            &["render", "--scene", "builtin:hall", "--size", "800"][..],
            "--size `800`: expected WxH",
        ),
    ] {
        let o = run(&[args, &never[..]].concat());
        assert!(!o.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
    }
    // A malformed scene line: the message names the file and the line.
    let dir = std::env::temp_dir().join(format!("raymip-badline-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let aff = dir.join("bad.aff");
    std::fs::write(
        &aff,
        "v\nfrom 0 0 5\nat zero 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 8 8\n",
    )
    .unwrap();
    let o = run(&[
        &["render", "--scene", aff.to_str().unwrap()][..],
        &never[..],
    ]
    .concat());
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(&format!("{}:3:", aff.display())), "{err}");
    std::fs::remove_dir_all(&dir).ok();
    let o = run(&["table1", "--scenes", "/nonexistent-raymip"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("not found"));
}

/// `table1` with a requested scene that cannot be loaded is an error naming
/// the scene and the reason, unless the user asked to skip.
#[test]
fn table1_fails_on_a_scene_that_does_not_load() {
    let dir = tmp("table1-broken");
    std::fs::create_dir_all(dir.join("broken")).unwrap();
    std::fs::write(
        dir.join("broken").join("broken.aff"),
        "this is not AFF {{{\n",
    )
    .unwrap();
    let table1 = |extra: &[&str]| {
        let args = [
            "table1",
            "--scenes",
            dir.to_str().unwrap(),
            "--size",
            "8x8",
            "--builtin",
        ];
        let o = run(&[&args[..], extra].concat());
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    // With the built-in scenes measurable beside it (the old code measured
    // those, printed the broken one and exited 0).
    let (ok, err) = table1(&[]);
    assert!(!ok, "exit 0 with an unloadable scene; stderr: {err}");
    assert!(
        err.contains("broken") && err.contains("cannot be loaded"),
        "{err}"
    );
    // Skipped on request: the built-in scenes are still measured.
    let (ok, err) = table1(&["--skip-unloadable"]);
    assert!(ok, "{err}");
    assert!(err.contains("skipped") && err.contains("broken"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
