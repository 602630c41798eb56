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

use raymip_host::output::image::write_png;
use raymip_host::output::metrics::psnr;
use raymip_host::output::report::{publish, write_option};
use raymip_host::render::{Arithmetic, Method, Options, Prepared, render, render_truth};
use raymip_host::scene::load_scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size = args
        .iter()
        .find_map(|a| raymip_host::cli::parse_size(a).ok())
        .unwrap_or((400, 240));
    let spp: u32 = args.iter().find_map(|a| a.parse().ok()).unwrap_or(256);
    let write = write_option(&args);
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
        "`builtin:hall`, {}×{}, ground truth {spp} jittered samples per pixel (bilinear in level 0); footprint and lod from ray differentials; fixed = firmware `TextureSampler`, float = the f64 unit of the harness; time = render only, 2 threads, one run on the project's machine (2 vCPU, shared) (`cargo run --release -p raymip-host --example aniso_hall -- {}x{} {spp} --write docs/texture-sampling.md`):\n",
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
        let mut psnrs = Vec::new();
        let mut fetched = 0.0;
        let mut time = 0.0;
        for arithmetic in [Arithmetic::Fixed, Arithmetic::Float] {
            let img = render(
                &prep,
                &Options {
                    arithmetic,
                    aniso,
                    ..base.clone()
                },
            );
            let rgb = img.to_rgb8();
            psnrs.push(psnr(&rgb, &truth));
            if arithmetic == Arithmetic::Fixed {
                fetched = img.counters.fetched as f64 / img.counters.textured_hits.max(1) as f64;
                time = img.render_s;
                let file = match aniso {
                    None => Some("hall_trilinear.png"),
                    Some(16) => Some("hall_aniso16.png"),
                    _ => None,
                };
                if let Some(f) = file {
                    std::fs::create_dir_all(docs)?;
                    write_png(&docs.join(f), img.width, img.height, &rgb)?;
                }
            }
        }
        writeln!(
            table,
            "| {name} | {:.2} dB | {:.2} dB | {fetched:.1} | {time:.2} s |",
            psnrs[0], psnrs[1]
        )?;
    }
    Ok(publish(&table, write, "aniso-hall")?)
}
