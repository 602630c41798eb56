//! Writes the docs/skipping.md table of what each scene doesn't need: per
//! scene, the pyramid bytes the set-up analysis lets a table-method render
//! leave out, the per-hit skips, and the render time with full and with
//! trimmed pyramids (best of `REPEATS` each), checked bit-identical.
//!
//! ```sh
//! cargo run --release -p raymip-host --example skip_table -- [WxH] [--write docs/skipping.md]
//! ```
//!
//! Scenes: every built-in scene and BART kitchen and robots (left out, with a
//! line saying so, when `../shared/scenes/bart` is absent). Prints the
//! Markdown; with `--write FILE` it replaces the text between
//! `<!-- skipping:begin -->` and `<!-- skipping:end -->` in FILE.

use std::fmt::Write as _;

use raymip_host::cli::MeasureArgs;
use raymip_host::output::machine::cpu_model;
use raymip_host::output::report::publish;
use raymip_host::render::skip::{bit_identical, plan, render_trimmed};
use raymip_host::render::{Arithmetic, Method, Options, Prepared, render};
use raymip_host::scene::{SceneError, builtin, default_bart_dir, load_scene_dir};

const REPEATS: usize = 3;

/// A scene loader.
type Load = Box<dyn Fn() -> Result<raymip_host::scene::Scene, SceneError>>;

fn cpu() -> String {
    let model = cpu_model();
    let load = std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "?".into());
    format!(
        "{model}, {} rayon threads, load average {load} at the start: the machine is shared, times are indicative",
        rayon::current_num_threads()
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cmd = MeasureArgs::from_env();
    let size = cmd.size.unwrap_or((640, 384));
    let write = cmd.write.as_deref();
    let mut scenes: Vec<(String, Load)> = builtin::NAMES
        .iter()
        .map(|&n| {
            let f: Load = Box::new(move || builtin::by_name(n));
            (format!("builtin:{n}"), f)
        })
        .collect();
    let mut note = String::new();
    for name in ["kitchen", "robots"] {
        let dir = default_bart_dir().join(name);
        if dir.is_dir() {
            scenes.push((
                format!("BART {name}"),
                Box::new(move || load_scene_dir(&dir, 0.0)),
            ));
        } else {
            writeln!(
                note,
                "BART {name}: not found (../shared/scenes/bart), left out."
            )?;
        }
    }
    let opts = Options {
        method: Method::Table,
        arithmetic: Arithmetic::Fixed,
        size: Some(size),
        bounces: 10,
        spp: 1,
        record_blocks: false,
        progress: false,
        aniso: None,
    };
    let mut t = String::new();
    writeln!(
        t,
        "Table method, firmware fixed point, {}×{}, 10 bounces; render times best of {REPEATS} \
         (`cargo run --release -p raymip-host --example skip_table -- {}x{} --write docs/skipping.md`; \
         machine: {}).\n",
        size.0,
        size.1,
        size.0,
        size.1,
        cpu()
    )?;
    writeln!(
        t,
        "| scene | pyramids full (KiB) | stored (KiB) | saved | textures skipped | untextured hits skipped | second trilinear levels skipped | render, full pyramids (s) | render, trimmed (s) | bit-identical |"
    )?;
    writeln!(t, "|---|---|---|---|---|---|---|---|---|---|")?;
    for (label, load) in &scenes {
        eprintln!("skip_table: {label}");
        let mut prep = Prepared::new(load()?, Some(size))?;
        let p = plan(&prep, &opts);
        let (mut full_s, mut trim_s) = (f64::INFINITY, f64::INFINITY);
        let mut identical = true;
        let mut counters = None;
        for _ in 0..REPEATS {
            let full = render(&prep, &opts);
            let trimmed = render_trimmed(&mut prep, &opts, &p);
            identical &= bit_identical(&full, &trimmed);
            full_s = full_s.min(full.render_s);
            trim_s = trim_s.min(trimmed.render_s);
            counters = Some(full.counters);
        }
        let c = counters.ok_or("no render")?;
        writeln!(
            t,
            "| {label} | {:.0} | {:.0} | {:.1} % | {} | {} | {} | {:.3} | {:.3} | {} |",
            p.full_bytes as f64 / 1024.0,
            p.stored_bytes as f64 / 1024.0,
            p.saved_percent(),
            p.textures_skipped,
            c.untextured_skipped,
            c.fetch_skipped / 4,
            full_s,
            trim_s,
            if identical { "yes" } else { "NO" }
        )?;
        if !identical {
            return Err(format!("{label}: trimmed render differs").into());
        }
    }
    if !note.is_empty() {
        writeln!(t, "\n{note}")?;
    }
    Ok(publish(&t, write, "skipping")?)
}
