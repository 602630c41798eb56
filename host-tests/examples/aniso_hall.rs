//! Anisotropic filtering on the built-in hall (the floor recedes to the
//! horizon): PSNR against ground truth of isotropic trilinear filtering and
//! of anisotropic filtering with 2–16 probes, both at the footprint of ray
//! differentials (pbrt-style axes), fixed point (firmware) and f64.
//!
//! ```sh
//! cargo run --release -p raymip-host --example aniso_hall -- [WxH] [SPP] [--write docs/texture-sampling.md]
//! ```
//!
//! Writes `docs/hall_trilinear.png` and `docs/hall_aniso16.png` (fixed
//! point) and, with `--write FILE`, the Markdown table between
//! `<!-- aniso-hall:begin -->` and `<!-- aniso-hall:end -->` in FILE.

use std::fmt::Write as _;
use std::path::Path;

use raymip_host::cli::MeasureArgs;
use raymip_host::output::image::write_png;
use raymip_host::output::metrics::psnr;
use raymip_host::output::report::publish;
use raymip_host::render::{Method, Options, Prepared, render_fixed_and_float, render_truth};
use raymip_host::scene::load_scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cmd = MeasureArgs::from_env();
    let size = cmd.size.unwrap_or((400, 240));
    let spp = cmd.number.unwrap_or(256);
    let write = cmd.write.as_deref();
    let prep = Prepared::new(load_scene("builtin:hall", 0.0)?, Some(size))?;
    let base = Options {
        method: Method::Raydiff,
        size: Some(size),
        spp,
        progress: true,
        ..Options::default()
    };
    let truth = render_truth(&prep, &base).to_rgb8();
    let mut table = String::new();
    writeln!(
        table,
        "`builtin:hall`, {}×{}, ground truth {spp} jittered samples per pixel (bilinear in level 0); footprint and lod from ray differentials; fixed = the firmware `Sampler`, float = the f64 reference sampler of the harness; time = render only, 2 threads, one run on the project's machine (2 vCPU, shared) (`cargo run --release -p raymip-host --example aniso_hall -- {}x{} {spp} --write docs/texture-sampling.md`):\n",
        size.0, size.1, size.0, size.1
    )?;
    writeln!(
        table,
        "| filter | PSNR vs truth, fixed | float | texels fetched per textured hit (fixed) | render time (fixed) |"
    )?;
    writeln!(table, "|---|---|---|---|---|")?;
    let docs = Path::new("docs");
    for aniso in [None, Some(2u8), Some(4), Some(8), Some(16)] {
        let name = aniso.map_or(
            "trilinear (isotropic, lod of the major axis)".to_string(),
            |n| format!("anisotropic, max {n}×"),
        );
        let [fixed, float] = render_fixed_and_float(
            &prep,
            &Options {
                aniso,
                ..base.clone()
            },
        );
        let rgb = fixed.to_rgb8();
        let psnrs = [psnr(&rgb, &truth), psnr(&float.to_rgb8(), &truth)];
        let fetched = fixed.counters.fetched as f64 / fixed.counters.textured_hits.max(1) as f64;
        let time = fixed.render_s;
        let file = match aniso {
            None => Some("hall_trilinear.png"),
            Some(16) => Some("hall_aniso16.png"),
            _ => None,
        };
        if let Some(f) = file {
            std::fs::create_dir_all(docs)?;
            write_png(&docs.join(f), fixed.width, fixed.height, &rgb)?;
        }
        writeln!(
            table,
            "| {name} | {:.2} dB | {:.2} dB | {fetched:.1} | {time:.2} s |",
            psnrs[0], psnrs[1]
        )?;
    }
    Ok(publish(&table, write, "aniso-hall")?)
}
