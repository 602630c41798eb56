//! Method comparisons: fixed vs float of the same method and every method
//! vs ground truth (PSNR, max difference, heat-maps).

use std::path::Path;

use serde::Serialize;
use serde_json::json;

use super::error::CommandError;
use crate::error::FileError;
use crate::output::image::write_png;
use crate::output::metrics::{heat_map, max_diff, psnr};
use crate::output::report::{write_json, write_text};
use crate::render::{Arithmetic, Image, Method, Options, Prepared, render, render_truth};
use crate::scene::{builtin, load_scene};

/// One comparison row.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Method.
    pub method: Method,
    /// Arithmetic of the image compared with truth.
    pub arithmetic: Arithmetic,
    /// PSNR vs ground truth (dB).
    pub psnr_vs_truth: f64,
    /// Max channel difference vs ground truth.
    pub max_diff_vs_truth: u8,
    /// PSNR fixed vs float of the same method (dB; fixed rows only).
    pub psnr_fixed_vs_float: Option<f64>,
    /// Max channel difference fixed vs float.
    pub max_diff_fixed_vs_float: Option<u8>,
    /// Render time (s).
    pub render_s: f64,
}

/// Result of [`compare`].
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// Rows (method × precision).
    pub rows: Vec<Row>,
    /// Truth samples per pixel.
    pub spp: u32,
    /// Truth render time (s).
    pub truth_s: f64,
}

fn opts(base: &Options, method: Method, arithmetic: Arithmetic) -> Options {
    Options {
        method,
        arithmetic,
        ..base.clone()
    }
}

/// Renders truth and, for each method, fixed and float; writes images and
/// heat-maps into `out` when given.
pub fn compare(
    prep: &Prepared,
    base: &Options,
    methods: &[Method],
    out: Option<&Path>,
) -> Result<Comparison, CommandError> {
    let save = |name: &str, img: &[[u8; 3]]| -> Result<(), CommandError> {
        if let Some(dir) = out {
            write_png(&dir.join(name), prep.width, prep.height, img)?;
        }
        Ok(())
    };
    let truth = render_truth(prep, base);
    let t8 = truth.to_rgb8();
    save("truth.png", &t8)?;
    let mut rows = Vec::new();
    for &m in methods.iter().filter(|&&m| m != Method::Truth) {
        let fixed: Image = render(prep, &opts(base, m, Arithmetic::Fixed));
        let float: Image = render(prep, &opts(base, m, Arithmetic::Float));
        let (a, b) = (fixed.to_rgb8(), float.to_rgb8());
        save(&format!("{}_fixed.png", m.name()), &a)?;
        save(&format!("{}_float.png", m.name()), &b)?;
        save(
            &format!("diff_{}_fixed_vs_float.png", m.name()),
            &heat_map(&a, &b, 16),
        )?;
        save(
            &format!("diff_{}_fixed_vs_truth.png", m.name()),
            &heat_map(&a, &t8, 64),
        )?;
        rows.push(Row {
            method: m,
            arithmetic: Arithmetic::Fixed,
            psnr_vs_truth: psnr(&a, &t8),
            max_diff_vs_truth: max_diff(&a, &t8),
            psnr_fixed_vs_float: Some(psnr(&a, &b)),
            max_diff_fixed_vs_float: Some(max_diff(&a, &b)),
            render_s: fixed.render_s,
        });
        rows.push(Row {
            method: m,
            arithmetic: Arithmetic::Float,
            psnr_vs_truth: psnr(&b, &t8),
            max_diff_vs_truth: max_diff(&b, &t8),
            psnr_fixed_vs_float: None,
            max_diff_fixed_vs_float: None,
            render_s: float.render_s,
        });
    }
    Ok(Comparison {
        rows,
        spp: base.spp,
        truth_s: truth.render_s,
    })
}

/// Markdown table of a comparison.
#[must_use]
pub fn markdown(c: &Comparison) -> String {
    let mut s = String::from(
        "| method | precision | PSNR vs truth (dB) | max diff vs truth | PSNR fixed vs float (dB) | max diff fixed vs float | render (s) |\n|---|---|---|---|---|---|---|\n",
    );
    let f = |x: f64| {
        if x.is_infinite() {
            "inf".to_string()
        } else {
            format!("{x:.2}")
        }
    };
    for r in &c.rows {
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {:.2} |\n",
            r.method.name(),
            r.arithmetic.name(),
            f(r.psnr_vs_truth),
            r.max_diff_vs_truth,
            r.psnr_fixed_vs_float.map_or("".into(), f),
            r.max_diff_fixed_vs_float
                .map_or("".into(), |d| d.to_string()),
            r.render_s
        );
    }
    s += &format!(
        "\nGround truth: {} jittered samples per pixel, mip 0 bilinear, {:.2} s.\n",
        c.spp, c.truth_s
    );
    s
}

/// `compare`: truth and every method in both precisions; writes images,
/// heat-maps and `compare.json` / `compare.md` into `out`.
pub fn cmd_compare(
    spec: &str,
    time: f64,
    opts: &Options,
    methods: &[Method],
    out: &Path,
) -> Result<(), CommandError> {
    std::fs::create_dir_all(out).map_err(|e| FileError::write(out, e))?;
    let scene = load_scene(spec, time)?;
    let size = opts.size.or_else(|| {
        spec.starts_with("builtin:")
            .then_some(builtin::DEFAULT_SIZE)
    });
    let prep = Prepared::new(scene, size)?;
    let c = compare(&prep, opts, methods, Some(out))?;
    let md = format!(
        "# raymip compare: {spec} ({}×{}, {} bounces)\n\n{}",
        prep.width,
        prep.height,
        opts.bounces,
        markdown(&c)
    );
    write_text(&out.join("compare.md"), &md)?;
    write_json(
        &out.join("compare.json"),
        &json!({"scene": spec, "width": prep.width, "height": prep.height, "bounces": opts.bounces, "comparison": c}),
    )?;
    println!("{md}");
    Ok(())
}
