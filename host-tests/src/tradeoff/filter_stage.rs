//! Filter per sample: nearest, bilinear, trilinear and the stochastic
//! filters, fixed point (the firmware sampler) and f32 (`raymip::baseline_f32`),
//! timed per call; error in 8-bit LSB per channel against the exact f64
//! trilinear filter (`raymip_reference::sampler::Sampler`) at the same
//! inputs (the common target every filter approximates: the chart axis)
//! and against the exact f64 version of the row's own filter (the
//! implementation error).
//! Stochastic rows come twice: one frame (one sample) and the mean of
//! `Settings::accumulate` frames (the same per-frame cost).
//!
//! Bilinear and trilinear come in both precision tiers of the firmware
//! sampler ("fixed accurate", "fixed FAST").
//!
//! Anisotropic rows (caps 1×, 2×, 4×, 16×; fixed = the firmware
//! `Sampler::sample_aniso`, f32 = `SamplerF32::sample_aniso`) run
//! on their own inputs, long footprints ([`aniso_inputs`]: 16 to 32 times
//! longer than wide, so every cap is reached): their error is measured
//! against the exact f64 anisotropic 16× filter over the same footprint
//! (`Sampler::sample_aniso` of the reference, the best filter of that footprint: the
//! chart axis for these rows) and against the exact f64 filter of the
//! row's own cap.

use raymip::baseline_f32::SamplerF32;
use raymip::rng::Rng as FrameRng;
use raymip::texture::address::{AddressMode, Wrap};
use raymip::texture::kernel::Linear;
use raymip::texture::sampler::state::{SamplerDesc, SamplerState};
use raymip::texture::sampler::stochastic::StochasticMode;
use raymip::texture::storage::mip::{Geometry, Pyramid, Texel, full_levels, generate};
use raymip::texture::storage::pow2::Pow2Pyramid;
use raymip::texture::{Cfg, Mode, Sampler};
use raymip::units::{Fast, Footprint, Lod, TexCoord};

use super::timing::measure;
use super::{Row, Settings, Stage, error_stats};
use crate::accuracy;
use raymip::rng::XorShift64;
use raymip_reference::Draw;
use raymip_reference::sampler::{self as reference, State, Texture};

/// The f64 reference sampler over a test texture.
type RefSampler<'a> = reference::Sampler<'a, Texture>;

/// A random RGBA8 texture and its firmware pyramid.
pub struct TestTexture {
    /// Geometry (full chain).
    pub geometry: Geometry,
    /// Texels of every level.
    pub texels: Vec<Texel>,
}

impl TestTexture {
    /// A `size`×`size` level 0 of random texels (seeded), levels by
    /// `mip::generate`.
    #[must_use]
    pub fn random(size: u32, seed: u64) -> Self {
        let geometry = Geometry::new(size, size, full_levels(size, size))
            .unwrap_or_else(|e| panic!("texture {size}: {e}"));
        let mut texels = vec![0; geometry.len()];
        let mut r = XorShift64(seed | 1);
        for t in &mut texels[..(size * size) as usize] {
            *t = r.next_u64() as u32;
        }
        generate(&geometry, &mut texels).unwrap_or_else(|e| panic!("generate: {e}"));
        Self { geometry, texels }
    }

    /// The pyramid.
    #[must_use]
    pub fn pyramid(&self) -> Pyramid<'_> {
        Pyramid::new(self.geometry, &self.texels).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The pyramid with its direct level views (power-of-two sides).
    #[must_use]
    pub fn direct(&self) -> Pow2Pyramid<'_> {
        Pow2Pyramid::new(self.pyramid()).unwrap_or_else(|e| panic!("{e}"))
    }

    /// A firmware sampler over it (wrap addressing, ACCURATE).
    #[must_use]
    pub fn sampler(&self) -> Sampler<Pow2Pyramid<'_>> {
        Sampler::wrap(self.direct())
    }

    /// A firmware sampler over it (wrap addressing, FAST).
    #[must_use]
    pub fn sampler_fast(&self) -> Sampler<Pow2Pyramid<'_>, Cfg<Wrap, Wrap, Linear, Fast>> {
        Sampler::new(self.direct())
    }

    /// The exact f64 reference over the same texels (wrap, no bias).
    #[must_use]
    pub fn reference(&self) -> Texture {
        accuracy::texture_rgba8(&self.geometry, &self.texels)
    }
}

/// The reference sampler state: wrap, no bias or clamps, linear.
#[must_use]
pub fn ref_state() -> State {
    State::default()
}

/// One sample position: exact in both I32F32 and f64; lod a multiple of
/// 1/256 in [−1, top + 1).
pub type Input = (TexCoord, TexCoord, Lod);

/// `n` random inputs for a texture of `levels` levels.
#[must_use]
pub fn inputs(n: usize, levels: u8, seed: u64) -> Vec<Input> {
    let mut r = XorShift64(seed | 1);
    (0..n)
        .map(|_| {
            let u = TexCoord::from_num(r.unit());
            let v = TexCoord::from_num(r.unit());
            let l = Lod::from_num(r.range(-1.0, f64::from(levels)));
            (u, v, l)
        })
        .collect()
}

/// The deterministic filter a stochastic mode converges to.
#[must_use]
pub fn expectation(m: StochasticMode) -> Mode {
    match m {
        StochasticMode::Bilinear => Mode::BilinearNearestLevel,
        StochasticMode::Trilinear | StochasticMode::TrilinearBilinear => Mode::Trilinear,
    }
}

/// Filter name of a mode in the tables and charts.
#[must_use]
pub fn mode_name(m: Mode) -> &'static str {
    match m {
        Mode::Trilinear => "trilinear",
        Mode::BilinearNearestLevel => "bilinear",
        Mode::Nearest => "nearest",
        Mode::NearestTexelLinearLevel => "nearest-texel linear-level",
    }
}

/// Filter name of a stochastic mode.
#[must_use]
pub fn stochastic_name(m: StochasticMode) -> &'static str {
    match m {
        StochasticMode::Trilinear => "stochastic trilinear",
        StochasticMode::Bilinear => "stochastic bilinear",
        StochasticMode::TrilinearBilinear => "stochastic trilinear+bilinear",
    }
}

/// The stochastic modes, in chart order.
pub const STOCHASTIC: [StochasticMode; 3] = [
    StochasticMode::Trilinear,
    StochasticMode::Bilinear,
    StochasticMode::TrilinearBilinear,
];

/// The random bits of sample `i` in frame `frame`.
#[must_use]
pub fn bits(i: usize, frame: u32) -> u32 {
    FrameRng::for_pixel(i as u32, 0, frame).next_u32()
}

/// Channels of a texel as f64.
#[must_use]
pub fn channels(t: Texel) -> [f64; 4] {
    t.to_le_bytes().map(f64::from)
}

/// Per-channel differences `got − exact` (LSB).
fn diffs<'a>(got: &'a [[f64; 4]], exact: &'a [[f64; 4]]) -> impl Iterator<Item = f64> + 'a {
    got.iter()
        .zip(exact)
        .flat_map(|(g, e)| (0..4).map(move |c| g[c] - e[c]))
}

/// Exact values at every input: the trilinear target and the row's own
/// filter.
struct Exact<'a> {
    target: &'a [[f64; 4]],
    own: Vec<[f64; 4]>,
}

fn row(filter: &str, precision: &str, ns: f64, got: &[[f64; 4]], ex: &Exact) -> Row {
    let (max, rms) = error_stats(diffs(got, ex.target));
    let (own_max, own_rms) = error_stats(diffs(got, &ex.own));
    Row {
        time_ns: Some(ns),
        filter: Some(filter.to_string()),
        own_error_max: Some(own_max),
        own_error_rms: Some(own_rms),
        ..Row::new(Stage::Filter, "sample", precision, max, rms, "LSB")
    }
}

/// The exact filter at every input.
fn exact(r: &RefSampler, inp: &[Input], mode: Mode) -> Vec<[f64; 4]> {
    inp.iter()
        .map(|&(u, v, l)| r.sample(u.to_num(), v.to_num(), l.to_num(), accuracy::mode(mode)))
        .collect()
}

/// The BUDGETS.md call that counts a mode's firmware path (ACCURATE, or
/// FAST).
pub(crate) fn budget_call(m: Mode, fast: bool) -> Option<&'static str> {
    match (m, fast) {
        (Mode::Trilinear, false) => Some("trilinear sample"),
        (Mode::BilinearNearestLevel, false) => Some("bilinear sample"),
        (Mode::Trilinear, true) => Some("trilinear sample FAST"),
        (Mode::BilinearNearestLevel, true) => Some("bilinear sample FAST"),
        _ => None,
    }
}

/// Deterministic rows: each mode fixed and f32.
fn deterministic(
    tex: &TestTexture,
    r: &RefSampler,
    inp: &[Input],
    reps: usize,
    target: &[[f64; 4]],
) -> Vec<Row> {
    let mut out = Vec::new();
    let f32s = SamplerF32::new(tex.geometry, &tex.texels, AddressMode::Wrap)
        .unwrap_or_else(|| panic!("SamplerF32 over the test texture"));
    let fin: Vec<(f32, f32, f32)> = inp
        .iter()
        .map(|&(u, v, l)| (u.to_num(), v.to_num(), l.to_num()))
        .collect();
    for mode in [Mode::Nearest, Mode::BilinearNearestLevel, Mode::Trilinear] {
        let ex = Exact {
            target,
            own: exact(r, inp, mode),
        };
        let mut s = tex.sampler();
        let (ns, got) = measure(inp, reps, |(u, v, l)| s.sample(u, v, l, mode), channels);
        let call = budget_call(mode, false);
        let mut fw = row(mode_name(mode), "fixed accurate", ns, &got, &ex);
        fw.budget_call = call.map(|c| (c.to_string(), false));
        out.push(fw);
        if let Some(fast_call) = budget_call(mode, true) {
            let mut s = tex.sampler_fast();
            let (ns, got) = measure(inp, reps, |(u, v, l)| s.sample(u, v, l, mode), channels);
            let mut fw = row(mode_name(mode), "fixed FAST", ns, &got, &ex);
            fw.budget_call = Some((fast_call.to_string(), false));
            out.push(fw);
        }
        let (ns, got) = measure(&fin, reps, |(u, v, l)| f32s.sample(u, v, l, mode), channels);
        let mut fl = row(mode_name(mode), "f32 libm", ns, &got, &ex);
        fl.budget_call = call.map(|c| (c.to_string(), true));
        out.push(fl);
    }
    out
}

/// Stochastic rows: each mode, one frame and the mean of `frames` frames
/// (error against the exact filter of its expectation).
fn stochastic(
    tex: &TestTexture,
    r: &RefSampler,
    inp: &[Input],
    reps: usize,
    frames: u32,
    target: &[[f64; 4]],
) -> Vec<Row> {
    let mut out = Vec::new();
    let idx: Vec<(usize, Input)> = inp.iter().copied().enumerate().collect();
    for m in STOCHASTIC {
        let ex = Exact {
            target,
            own: exact(r, inp, expectation(m)),
        };
        let mut s = tex.sampler();
        let (ns, got) = measure(
            &idx,
            reps,
            |(i, (u, v, l))| s.sample_stochastic(u, v, l, m, bits(i, 0)),
            channels,
        );
        out.push(row(stochastic_name(m), "fixed accurate", ns, &got, &ex));
        let mean = mean_of_frames(tex, inp, m, frames);
        let mut acc = row(stochastic_name(m), "fixed accurate", ns, &mean, &ex);
        acc.frames = frames;
        out.push(acc);
    }
    out
}

/// Per input, the mean of the stochastic samples of frames `0..frames`.
#[must_use]
pub fn mean_of_frames(
    tex: &TestTexture,
    inp: &[Input],
    m: StochasticMode,
    frames: u32,
) -> Vec<[f64; 4]> {
    let mut s = tex.sampler();
    inp.iter()
        .enumerate()
        .map(|(i, &(u, v, l))| {
            let mut acc = [0.0; 4];
            for f in 0..frames {
                let c = channels(s.sample_stochastic(u, v, l, m, bits(i, f)));
                for k in 0..4 {
                    acc[k] += c[k];
                }
            }
            acc.map(|a| a / f64::from(frames.max(1)))
        })
        .collect()
}

/// One anisotropic input: position and footprint (exact in both I32F32
/// and f64).
pub type AnisoInput = (TexCoord, TexCoord, Footprint);

/// `n` random anisotropic inputs on a `size`×`size` texture: `u, v ∈
/// [0, 1)`, a minor axis of 0.5 to 4 texels in a random direction and a
/// major axis perpendicular to it, 16 to 32 times longer.
#[must_use]
pub fn aniso_inputs(n: usize, size: u32, seed: u64) -> Vec<AnisoInput> {
    let mut r = XorShift64(seed | 1);
    let c = |x: f64| TexCoord::from_num(x);
    (0..n)
        .map(|_| {
            let (u, v) = (c(r.unit()), c(r.unit()));
            let phi = r.range(0.0, std::f64::consts::TAU);
            let minor = r.range(0.5, 4.0) / f64::from(size);
            let major = minor * r.range(16.0, 32.0);
            let (dx, dy) = (phi.cos(), phi.sin());
            let fp = Footprint {
                x: [c(major * dx), c(major * dy)],
                y: [c(-minor * dy), c(minor * dx)],
            };
            (u, v, fp)
        })
        .collect()
}

/// The footprint's axes in f64 (exact: I32F32 values).
#[must_use]
pub fn axes_f64(fp: &Footprint) -> [[f64; 2]; 2] {
    [fp.x.map(|c| c.to_num()), fp.y.map(|c| c.to_num())]
}

/// The anisotropic caps of the rows.
pub const ANISO_CAPS: [u8; 4] = [1, 2, 4, 16];

/// Filter name of an anisotropic cap.
#[must_use]
pub fn aniso_name(cap: u8) -> String {
    format!("anisotropic {cap}×")
}

/// The exact f64 anisotropic filter with at most `cap` probes at every
/// input.
fn exact_aniso(tex: &Texture, inp: &[AnisoInput], cap: u8) -> Vec<[f64; 4]> {
    let mut state = ref_state();
    state.max_aniso = u32::from(cap);
    let r = reference::Sampler { tex, state };
    inp.iter()
        .map(|(u, v, fp)| {
            r.sample_aniso(
                u.to_num(),
                v.to_num(),
                axes_f64(fp),
                reference::Mode::Trilinear,
            )
        })
        .collect()
}

/// Anisotropic rows: each cap fixed and f32 (error against the exact
/// 16× filter and against the exact filter of the row's cap).
fn anisotropic(tex: &TestTexture, rt: &Texture, inp: &[AnisoInput], reps: usize) -> Vec<Row> {
    let target = exact_aniso(rt, inp, 16);
    let p = Pyramid::new(tex.geometry, &tex.texels).unwrap_or_else(|e| panic!("{e}"));
    let f32s = SamplerF32::new(tex.geometry, &tex.texels, AddressMode::Wrap)
        .unwrap_or_else(|| panic!("SamplerF32 over the test texture"));
    let fin: Vec<(f32, f32, [[f32; 2]; 2])> = inp
        .iter()
        .map(|(u, v, fp)| {
            let a = axes_f64(fp).map(|x| x.map(|c| c as f32));
            (u.to_num(), v.to_num(), a)
        })
        .collect();
    let mut out = Vec::new();
    for cap in ANISO_CAPS {
        let ex = Exact {
            target: &target,
            own: exact_aniso(rt, inp, cap),
        };
        let state = SamplerState::new(SamplerDesc {
            max_anisotropy: cap,
            ..SamplerDesc::default()
        })
        .unwrap_or_else(|e| panic!("aniso state {cap}: {e}"));
        let mut s = Sampler::wrap(p);
        s = Sampler::with_state(s.into_source(), state)
            .unwrap_or_else(|e| panic!("aniso sampler {cap}: {e}"));
        let (ns, got) = measure(inp, reps, |(u, v, fp)| s.sample_aniso(u, v, &fp), channels);
        let name = aniso_name(cap);
        let mut fw = row(&name, "fixed accurate", ns, &got, &ex);
        // BUDGETS.md counts the capped rows ("anisotropic N× sample").
        fw.budget_call = (cap > 1).then(|| (format!("{name} sample"), false));
        out.push(fw);
        let (ns, got) = measure(
            &fin,
            reps,
            |(u, v, a)| f32s.sample_aniso(u, v, a, cap, Mode::Trilinear),
            channels,
        );
        out.push(row(&name, "f32 libm", ns, &got, &ex));
    }
    out
}

/// Every filter row. `tick` is called after each group.
pub fn rows(s: &Settings, tick: &dyn Fn()) -> Vec<Row> {
    let tex = TestTexture::random(s.texture_size, 0x5EED_7E57);
    let rt = tex.reference();
    let r = reference::Sampler {
        tex: &rt,
        state: ref_state(),
    };
    let inp = inputs(s.filter_inputs, tex.geometry.levels(), 0xF11E);
    let target = exact(&r, &inp, Mode::Trilinear);
    let mut out = deterministic(&tex, &r, &inp, s.repeats, &target);
    tick();
    out.extend(stochastic(&tex, &r, &inp, s.repeats, s.accumulate, &target));
    tick();
    let ainp = aniso_inputs(s.filter_inputs, s.texture_size, 0xA2150);
    out.extend(anisotropic(&tex, &rt, &ainp, s.repeats));
    tick();
    out
}
