//! `raymip-host stress`: the command exits 0, its totals add up
//! with nothing panicked or misbehaved, every class of the issue is
//! present, and the docs/reliability.md block is what `--write-readme` writes now.

use std::path::Path;
use std::process::Command;

use raymip_host::cli::stress::cmd_stress_quiet;
use raymip_host::stress::{self, FLOAT_CLASSES, Totals};

#[test]
fn stress_command_exits_zero_with_clean_totals() {
    let out = Command::new(env!("CARGO_BIN_EXE_raymip-host"))
        .arg("stress")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}\n{}",
        stdout,
        String::from_utf8_lossy(&out.stderr)
    );
    let rows = stress::run();
    let t = Totals::of(&rows);
    assert_eq!(
        stdout.lines().last(),
        Some(stress::totals_line(&t).as_str())
    );
    assert_eq!(t.cases, t.errors + t.clamps + t.values);
    assert_eq!((t.misbehaved, t.panicked), (0, 0));
    assert!(t.cases >= 270 && t.errors > 0 && t.clamps > 0 && t.values > 0);
    // Every float class reaches every float edge.
    for edge in [
        "camera: PixelSpread::from_fov_y(fov, 480)",
        "table: TexTriangle::from_f32 position",
        "table: TexTriangle::from_f32 uv",
        "sampler: Sampler::sample_f64 u",
        "sampler: Sampler::sample_f64 v",
        "sampler: Sampler::sample_f64 lod",
        "lod: table_lod_f32(pl, 0) (float baseline)",
    ] {
        for (class, _, _) in FLOAT_CLASSES {
            assert!(
                rows.iter().any(|r| r.edge == edge && r.class == class),
                "{edge} / {class}"
            );
        }
    }
    for class in [
        "zero-area triangle",
        "collinear triangle",
        "Pl at the top of its range",
        "grazing",
        "push 11 onto 10",
        "1×1 texture",
        "1×4096 texture",
        "4096×1 texture",
        "32768×1 texture",
        "storage one texel short",
        "corrupt len",
    ] {
        assert!(
            rows.iter().any(|r| r.class.contains(class)),
            "no case of class {class}"
        );
    }
}

#[test]
fn totals_count_misbehaviour_and_panics() {
    let row = |result, panicked| stress::Row {
        class: "c".into(),
        edge: "e",
        result,
        panicked,
    };
    let rows = [
        row(Ok((stress::Kind::Error, String::new())), false),
        row(Ok((stress::Kind::Clamp, String::new())), false),
        row(Err("wrong".into()), false),
        row(Err("panicked: x".into()), true),
    ];
    let t = Totals::of(&rows);
    assert_eq!((t.cases, t.errors, t.clamps, t.values), (4, 1, 1, 0));
    assert_eq!((t.misbehaved, t.panicked), (1, 1));
    assert!(!t.clean());
    assert!(stress::markdown(&rows).contains("PANICKED"));
}

/// The docs/reliability.md block equals what `stress --write-readme` writes now.
#[test]
fn readme_block_is_current() {
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/reliability.md");
    let now = std::fs::read_to_string(&readme).unwrap();
    let dir = std::env::temp_dir().join(format!("raymip-stress-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let copy = dir.join("reliability.md");
    std::fs::write(&copy, &now).unwrap();
    cmd_stress_quiet(&copy).unwrap();
    let fresh = std::fs::read_to_string(&copy).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        fresh == now,
        "docs/reliability.md stress block is stale: run `cargo run --release -p raymip-host -- stress --write-readme docs/reliability.md`"
    );
}
