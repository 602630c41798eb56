//! Environment-map LOD (Ray Tracing Gems ch. 21) on `builtin:envmap`: a
//! mirror sphere, a glass sphere and a polished floor under a lat-long map of
//! fine detail. PSNR against a supersampled ground truth of the lookups of
//! rays that leave the scene at level 0 (mip0), at the cone lod and at the
//! ray-differential lod (both with the pole term), fixed point (the
//! firmware's `raymip::lod::envmap` lod and CORDIC `(u, v)`, the firmware
//! sampler) and f64.
//!
//! ```sh
//! cargo run --release -p raymip-host --example envmap_scene -- [WxH] [SPP] [--write docs/environment-map.md]
//! ```
//!
//! Writes `docs/envmap_truth.png` and `docs/envmap_{mip0,cone,raydiff}.png`
//! (fixed point) and, with `--write FILE`, the Markdown table between
//! `<!-- envmap-psnr:begin -->` and `<!-- envmap-psnr:end -->` in FILE.

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
    let size = cmd.size.unwrap_or((320, 192));
    let spp = cmd.number.unwrap_or(64);
    let write = cmd.write.as_deref();
    let prep = Prepared::new(load_scene("builtin:envmap", 0.0)?, Some(size))?;
    let base = Options {
        size: Some(size),
        spp,
        progress: true,
        ..Options::default()
    };
    let docs = Path::new("docs");
    std::fs::create_dir_all(docs)?;
    let truth = render_truth(&prep, &base);
    let truth_rgb = truth.to_rgb8();
    write_png(
        &docs.join("envmap_truth.png"),
        truth.width,
        truth.height,
        &truth_rgb,
    )?;
    let mut table = String::new();
    writeln!(
        table,
        "`builtin:envmap`, {}×{}, 2048×1024 environment map, ground truth {spp} jittered samples per pixel (bilinear in level 0); misses (and the floor's texture) sampled trilinearly at the method's lod (mip0: bilinear in level 0); fixed = firmware lod, `(u, v)` and sampler, float = the f64 reference and unit; {} bounces (`cargo run --release -p raymip-host --example envmap_scene -- {}x{} {spp} --write docs/environment-map.md`):\n",
        size.0, size.1, base.bounces, size.0, size.1
    )?;
    writeln!(
        table,
        "| method (lod of a miss) | PSNR vs truth, fixed | float |"
    )?;
    writeln!(table, "|---|---|---|")?;
    for (method, label, file) in [
        (Method::Mip0, "mip 0 (no lod)", "envmap_mip0.png"),
        (
            Method::Table,
            "camera pixel spread γ (table method: flat surfaces)",
            "",
        ),
        (Method::Cone, "ray cone spread angle", "envmap_cone.png"),
        (
            Method::Raydiff,
            "ray differentials (larger of ∂D/∂x, ∂D/∂y)",
            "envmap_raydiff.png",
        ),
    ] {
        let [fixed, float] = render_fixed_and_float(
            &prep,
            &Options {
                method,
                ..base.clone()
            },
        );
        let rgb = fixed.to_rgb8();
        let psnrs = [psnr(&rgb, &truth_rgb), psnr(&float.to_rgb8(), &truth_rgb)];
        if !file.is_empty() {
            write_png(&docs.join(file), fixed.width, fixed.height, &rgb)?;
        }
        writeln!(
            table,
            "| {label} | {:.2} dB | {:.2} dB |",
            psnrs[0], psnrs[1]
        )?;
    }
    Ok(publish(&table, write, "envmap-psnr")?)
}
