//! Stochastic filtering over frames: the error of the mean of the first
//! `N` frames (N = 1, 2, …) against the deterministic filter it converges
//! to, per sample (firmware deterministic filter at the same inputs) and
//! per frame (the deterministic fixed-point render of the same method).

use serde::Serialize;

use crate::render::texunit::Filter;
use crate::render::{Arithmetic, FrameFilter, Method, Options, render_filtered};

use super::filter_stage::{
    self, Input, STOCHASTIC, TestTexture, channels, expectation, stochastic_name,
};
use super::frame_stage::prepare;
use super::{Settings, TradeoffError, error_stats};

/// One convergence curve.
#[derive(Clone, Debug, Serialize)]
pub struct Curve {
    /// Stochastic mode.
    pub mode: String,
    /// `sample` (filter stage) or `frame` (a render).
    pub kind: &'static str,
    /// RMS error in LSB of the mean of frames `0..N`, `N = 1..`.
    pub rms_lsb: Vec<f64>,
    /// Largest error in LSB of the same means.
    pub max_lsb: Vec<f64>,
}

/// Errors of running means: `sums` are per-value sums after `n` frames.
fn point(sums: &[f64], target: &[f64], n: u32) -> (f64, f64) {
    let k = f64::from(n);
    error_stats(sums.iter().zip(target).map(|(s, t)| s / k - t))
}

/// Per-sample curves over `frames` frames (every mode).
fn sample_curves(s: &Settings) -> Vec<Curve> {
    let tex = TestTexture::random(s.texture_size, 0x5EED_7E57);
    let inp: Vec<Input> = filter_stage::inputs(s.filter_inputs, tex.geometry.levels(), 0xC0FE);
    let mut smp = tex.sampler();
    STOCHASTIC
        .iter()
        .map(|&m| {
            let target: Vec<f64> = inp
                .iter()
                .flat_map(|&(u, v, l)| channels(smp.sample(u, v, l, expectation(m))))
                .collect();
            let mut sums = vec![0.0; target.len()];
            let (mut rms, mut max) = (Vec::new(), Vec::new());
            for f in 0..s.convergence_frames {
                for (i, &(u, v, l)) in inp.iter().enumerate() {
                    let c = channels(smp.sample_stochastic(u, v, l, m, filter_stage::bits(i, f)));
                    for k in 0..4 {
                        sums[4 * i + k] += c[k];
                    }
                }
                let (mx, r) = point(&sums, &target, f + 1);
                rms.push(r);
                max.push(mx);
            }
            Curve {
                mode: stochastic_name(m).into(),
                kind: "sample",
                rms_lsb: rms,
                max_lsb: max,
            }
        })
        .collect()
}

/// Per-frame curves on the first scene (table method, fixed point): the
/// running mean of stochastic frames against the deterministic frame.
fn frame_curves(s: &Settings, tick: &dyn Fn()) -> Result<Vec<Curve>, TradeoffError> {
    let Some(spec) = s.scenes.first() else {
        return Ok(Vec::new());
    };
    let prep = prepare(spec, s.size)?;
    let o = Options {
        method: Method::Table,
        arithmetic: Arithmetic::Fixed,
        size: Some(s.size),
        bounces: s.bounces,
        ..Options::default()
    };
    let rgb = |filter, frame| -> Vec<f64> {
        let img = render_filtered(&prep, &o, Some(FrameFilter { filter, frame }));
        tick();
        img.rgb
            .iter()
            .flat_map(|c| c.map(|x| f64::from(x) * 255.0))
            .collect()
    };
    let mut out = Vec::new();
    for m in STOCHASTIC {
        let det = match filter_stage::expectation(m) {
            raymip::texture::Mode::BilinearNearestLevel => Filter::Bilinear,
            _ => Filter::Trilinear,
        };
        let target = rgb(det, 0);
        let mut sums = vec![0.0; target.len()];
        let (mut rms, mut max) = (Vec::new(), Vec::new());
        for f in 0..s.convergence_frames {
            sums.iter_mut()
                .zip(rgb(Filter::Stochastic(m), f))
                .for_each(|(a, b)| *a += b);
            let (mx, r) = point(&sums, &target, f + 1);
            rms.push(r);
            max.push(mx);
        }
        out.push(Curve {
            mode: stochastic_name(m).into(),
            kind: "frame",
            rms_lsb: rms,
            max_lsb: max,
        });
    }
    Ok(out)
}

/// Renders [`curves`] makes (for the progress bar).
#[must_use]
pub fn renders(s: &Settings) -> u64 {
    if s.scenes.is_empty() {
        0
    } else {
        3 * (1 + u64::from(s.convergence_frames))
    }
}

/// Every convergence curve: per sample, then per frame.
pub fn curves(s: &Settings, tick: &dyn Fn()) -> Result<Vec<Curve>, TradeoffError> {
    let mut c = sample_curves(s);
    c.extend(frame_curves(s, tick)?);
    Ok(c)
}
