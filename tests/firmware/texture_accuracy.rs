//! Filtering of linear RGBA8 data against an f64 reference written here
//! from the definitions (texel centres at (i + ½)/size; every address mode
//! as the Vulkan wrapping operation defines it, the border colour for
//! clamp-to-border; lod clamped to the stored levels, nearest level =
//! floor(lod + ½)), for both precision tiers.
//!
//! Bounds: nearest-texel modes exact (nearest texel, nearest level) or
//! within ½ LSB (nearest texel, linear level: one rounding of an exact
//! blend), both tiers; bilinear and trilinear ≤ `BILERP_MAX_ERROR_LSB` =
//! 0.5625 LSB per channel ACCURATE (goal < 0.75), ≤ `FAST_MAX_ERROR_LSB` =
//! 1.5 FAST. The run-time address form and the static keys give the
//! same bits.

use proptest::prelude::*;
use raymip::texture::address::{AnyAxis, ClampToBorder, ClampToEdge, Wrap};
use raymip::texture::kernel::Linear;
use raymip::texture::kernel::accurate::BILERP_MAX_ERROR_LSB;
use raymip::texture::kernel::fast::FAST_MAX_ERROR_LSB;
use raymip::texture::sampler::Key;
use raymip::texture::storage::mip::{Geometry, Pyramid, Texel, full_levels, generate};
use raymip::texture::{AddressMode, Cfg, FilterError, Mode, Sampler, SamplerDesc, SamplerState};
use raymip::units::{Fast, Lod, TexCoord};

use crate::common;
use common::{Rng, random_texture};

/// A generated pyramid with random level 0, owned.
struct Tex {
    g: Geometry,
    buf: Vec<Texel>,
}

impl Tex {
    fn random(w: u32, h: u32, levels: u8, seed: u64) -> Self {
        let (g, buf) = random_texture(w, h, levels, seed).unwrap();
        Tex { g, buf }
    }
    fn pyramid(&self) -> Pyramid<'_> {
        Pyramid::new(self.g, &self.buf).unwrap()
    }
    /// Channels of an addressed texel, or of the border colour.
    fn at(&self, k: u32, x: Option<i64>, y: Option<i64>) -> [f64; 4] {
        match (x, y) {
            (Some(x), Some(y)) => self.texel(k, x, y),
            _ => border(),
        }
    }
    /// Channels of texel (x, y) of level k, straight from the buffer.
    fn texel(&self, k: u32, x: i64, y: i64) -> [f64; 4] {
        let (w, _) = ref_size(&self.g, k);
        let off: usize = (0..k)
            .map(|j| {
                let (a, b) = ref_size(&self.g, j);
                (a * b) as usize
            })
            .sum();
        let t = self.buf[off + (y as usize) * w as usize + x as usize];
        [0, 1, 2, 3].map(|c| f64::from((t >> (8 * c)) & 0xFF))
    }
}

/// Level size from the definition.
fn ref_size(g: &Geometry, k: u32) -> (u32, u32) {
    ((g.width() >> k).max(1), (g.height() >> k).max(1))
}

/// Addressed integer index (`None`: the border colour), the Vulkan
/// wrapping operation written independently of the firmware.
fn addr(i: i64, n: u32, a: AddressMode) -> Option<i64> {
    let n = i64::from(n);
    match a {
        AddressMode::Wrap => Some(i.rem_euclid(n)),
        AddressMode::Mirror => {
            let m = i.rem_euclid(2 * n);
            Some(if m < n { m } else { 2 * n - 1 - m })
        }
        AddressMode::ClampToEdge => Some(i.clamp(0, n - 1)),
        AddressMode::MirrorOnce => Some((if i < 0 { -1 - i } else { i }).clamp(0, n - 1)),
        AddressMode::ClampToBorder => (0..n).contains(&i).then_some(i),
    }
}

/// The border colour of every sampler here (linear RGBA8).
const BORDER: Texel = 0x80FF_4010;

fn border() -> [f64; 4] {
    [0, 1, 2, 3].map(|c| f64::from((BORDER >> (8 * c)) & 0xFF))
}

fn ref_nearest(t: &Tex, k: u32, u: f64, v: f64, a: AddressMode) -> [f64; 4] {
    let (w, h) = ref_size(&t.g, k);
    let x = addr((u * f64::from(w)).floor() as i64, w, a);
    let y = addr((v * f64::from(h)).floor() as i64, h, a);
    t.at(k, x, y)
}

fn ref_bilinear(t: &Tex, k: u32, u: f64, v: f64, a: AddressMode) -> [f64; 4] {
    let (w, h) = ref_size(&t.g, k);
    let x = u * f64::from(w) - 0.5;
    let y = v * f64::from(h) - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (xa, xb) = (addr(x0 as i64, w, a), addr(x0 as i64 + 1, w, a));
    let (ya, yb) = (addr(y0 as i64, h, a), addr(y0 as i64 + 1, h, a));
    let (p, q, r, s) = (
        t.at(k, xa, ya),
        t.at(k, xb, ya),
        t.at(k, xa, yb),
        t.at(k, xb, yb),
    );
    [0, 1, 2, 3].map(|c| {
        (1.0 - fy) * ((1.0 - fx) * p[c] + fx * q[c]) + fy * ((1.0 - fx) * r[c] + fx * s[c])
    })
}

/// Reference sample; `u`, `v`, `lod` are the exact values of the fixed inputs.
fn reference(t: &Tex, u: f64, v: f64, lod: f64, mode: Mode, a: AddressMode) -> [f64; 4] {
    let top = f64::from(t.g.levels() - 1);
    let lod = lod.clamp(0.0, top);
    let lower = lod.floor();
    let frac = lod - lower;
    let nearest_level = (lod + 0.5).floor().min(top) as u32;
    let blend = |p: [f64; 4], q: [f64; 4]| [0, 1, 2, 3].map(|c| (1.0 - frac) * p[c] + frac * q[c]);
    let l0 = lower as u32;
    let l1 = (l0 + 1).min(top as u32);
    match mode {
        Mode::Trilinear => blend(ref_bilinear(t, l0, u, v, a), ref_bilinear(t, l1, u, v, a)),
        Mode::BilinearNearestLevel => ref_bilinear(t, nearest_level, u, v, a),
        Mode::Nearest => ref_nearest(t, nearest_level, u, v, a),
        Mode::NearestTexelLinearLevel => {
            blend(ref_nearest(t, l0, u, v, a), ref_nearest(t, l1, u, v, a))
        }
    }
}

/// Largest per-channel |fixed − reference| over the samples, per mode
/// (in `MODES` order), ACCURATE then FAST.
#[derive(Default, Debug)]
struct Worst([f64; 8]);

const MODES: [Mode; 4] = [
    Mode::Trilinear,
    Mode::BilinearNearestLevel,
    Mode::Nearest,
    Mode::NearestTexelLinearLevel,
];

fn bound(mode: Mode, fast: bool) -> f64 {
    match mode {
        Mode::Nearest => 0.0,
        Mode::NearestTexelLinearLevel => 0.5,
        _ if fast => FAST_MAX_ERROR_LSB,
        _ => BILERP_MAX_ERROR_LSB,
    }
}

/// The state of every sampler here: address mode `a` on both axes,
/// [`BORDER`].
fn state(a: AddressMode) -> SamplerState {
    SamplerState::new(SamplerDesc {
        address_u: a,
        address_v: a,
        border: BORDER,
        ..SamplerDesc::default()
    })
    .unwrap()
}

type AccurateAny = Cfg<AnyAxis>;

/// One sample through a fresh sampler of key `K`.
fn one<K: Key>(
    p: Pyramid<'_>,
    st: SamplerState,
    (u, v, lod): (TexCoord, TexCoord, Lod),
    mode: Mode,
) -> Texel {
    Sampler::<_, K>::with_state(p, st)
        .unwrap()
        .sample(u, v, lod, mode)
}
type FastAny = Cfg<AnyAxis, AnyAxis, Linear, Fast>;

/// The sample of `mode` through the ACCURATE and FAST run-time-address
/// samplers and, for wrap and clamp to edge, the static keys (which must
/// give the same bits).
fn both_tiers(
    acc: &mut Sampler<Pyramid<'_>, AccurateAny>,
    fast: &mut Sampler<Pyramid<'_>, FastAny>,
    p: Pyramid<'_>,
    (u, v, lod): (TexCoord, TexCoord, Lod),
    mode: Mode,
) -> [Texel; 2] {
    let got = [acc.sample(u, v, lod, mode), fast.sample(u, v, lod, mode)];
    let st = *acc.state();
    let x = (u, v, lod);
    let statics = match st.address()[0] {
        AddressMode::Wrap => Some([
            one::<Cfg<Wrap>>(p, st, x, mode),
            one::<Cfg<Wrap, Wrap, Linear, Fast>>(p, st, x, mode),
        ]),
        AddressMode::ClampToEdge => Some([
            one::<Cfg<ClampToEdge>>(p, st, x, mode),
            one::<Cfg<ClampToEdge, ClampToEdge, Linear, Fast>>(p, st, x, mode),
        ]),
        AddressMode::ClampToBorder => Some([
            one::<Cfg<ClampToBorder>>(p, st, x, mode),
            one::<Cfg<ClampToBorder, ClampToBorder, Linear, Fast>>(p, st, x, mode),
        ]),
        _ => None,
    };
    if let Some(st) = statics {
        assert_eq!(st, got, "static keys against the run-time address form");
    }
    got
}

/// Samples (u, v, lod) in all modes, every addressing and both tiers,
/// checks bounds.
fn check_samples(t: &Tex, samples: &[(TexCoord, TexCoord, Lod)], worst: &mut Worst) {
    for a in AddressMode::ALL {
        let p = t.pyramid();
        let mut acc = Sampler::<_, AccurateAny>::with_state(p, state(a)).unwrap();
        let mut fast = Sampler::<_, FastAny>::with_state(p, state(a)).unwrap();
        for (n, &(u, v, lod)) in samples.iter().enumerate() {
            let (uf, vf, lf) = (u.to_num::<f64>(), v.to_num::<f64>(), lod.to_num::<f64>());
            for (m, &mode) in MODES.iter().enumerate() {
                // The static keys on every 16th sample (they are slower to build).
                let got = if n % 16 == 0 {
                    both_tiers(&mut acc, &mut fast, p, (u, v, lod), mode)
                } else {
                    [acc.sample(u, v, lod, mode), fast.sample(u, v, lod, mode)]
                };
                let want = reference(t, uf, vf, lf, mode, a);
                for (tier, g) in got.into_iter().enumerate() {
                    for (c, &wc) in want.iter().enumerate() {
                        let e = (f64::from((g >> (8 * c)) & 0xFF) - wc).abs();
                        let w = &mut worst.0[m + 4 * tier];
                        *w = w.max(e);
                        assert!(
                            e <= bound(mode, tier == 1) + 1e-9,
                            "{}x{} {a:?} {mode:?} tier {tier} u={uf} v={vf} lod={lf} ch{c}: got {} want {wc}",
                            t.g.width(),
                            t.g.height(),
                            (g >> (8 * c)) & 0xFF
                        );
                    }
                }
            }
        }
        assert_eq!(
            acc.stats(),
            fast.stats(),
            "{a:?}: both tiers read the same texels"
        );
    }
}

/// Random samples plus edge samples (texel centres, corners, wrap seams,
/// integer/fractional/out-of-range lod, large coordinates).
fn samples_for(g: &Geometry, n: usize, seed: u64) -> Vec<(TexCoord, TexCoord, Lod)> {
    let mut rng = Rng(seed | 1);
    let top = f64::from(g.levels() - 1);
    let mut out = Vec::new();
    let lods = [
        -3.0,
        0.0,
        0.25,
        0.5,
        1.0,
        1.5,
        top - 0.5,
        top,
        top + 2.0,
        1.0 / 256.0,
        255.0 / 256.0,
    ];
    let q = |x: f64| TexCoord::from_num(x);
    // Random, lod random in [−1, top + 1].
    for _ in 0..n {
        let u = rng.unit() * 5.0 - 2.0;
        let v = rng.unit() * 5.0 - 2.0;
        let lod = rng.unit() * (top + 2.0) - 1.0;
        out.push((q(u), q(v), Lod::from_num(lod)));
    }
    // Texel centres and corners of each level, wrap seams.
    for k in 0..g.levels() {
        let (w, h) = g.level_size(k);
        for _ in 0..n / 8 + 4 {
            let i = (rng.next_u64() % u64::from(w)) as f64;
            let j = (rng.next_u64() % u64::from(h)) as f64;
            let lod = Lod::from_num(lods[(rng.next_u64() % lods.len() as u64) as usize]);
            let kl = Lod::from_num(f64::from(k));
            out.push((q((i + 0.5) / f64::from(w)), q((j + 0.5) / f64::from(h)), kl));
            out.push((q(i / f64::from(w)), q(j / f64::from(h)), kl));
            out.push((q((i + 0.5) / f64::from(w)), q(j / f64::from(h)), lod));
        }
    }
    let eps = TexCoord::from_bits(1);
    for &lod in &lods {
        let l = Lod::from_num(lod);
        for (u, v) in [
            (TexCoord::ZERO, TexCoord::ZERO),
            (TexCoord::ONE, TexCoord::ONE),
            (-eps, eps),
            (TexCoord::ONE - eps, TexCoord::ONE + eps),
            (q(1e6 + 0.3), q(-1e6 - 0.7)),
            (q(-1e6), q(1e6)),
            (q(0.5), q(-3.999)),
        ] {
            out.push((u, v, l));
        }
    }
    out
}

fn run(w: u32, h: u32, n: usize) -> Worst {
    run_levels(w, h, full_levels(w, h), n)
}

fn run_levels(w: u32, h: u32, levels: u8, n: usize) -> Worst {
    let t = Tex::random(w, h, levels, u64::from(w) * 7919 + u64::from(h));
    let mut worst = Worst::default();
    check_samples(
        &t,
        &samples_for(&t.g, n, u64::from(w ^ (h << 3))),
        &mut worst,
    );
    println!(
        "{w}x{h} ({levels} levels): max error (LSB) trilinear {:.4}, bilinear {:.4}, nearest {:.4}, nearest-texel linear-level {:.4}; FAST {:.4}, {:.4}, {:.4}, {:.4}",
        worst.0[0],
        worst.0[1],
        worst.0[2],
        worst.0[3],
        worst.0[4],
        worst.0[5],
        worst.0[6],
        worst.0[7]
    );
    worst
}

#[test]
fn tiny_and_one_wide_sizes() {
    for (w, h) in [
        (1, 1),
        (1, 2),
        (2, 1),
        (1, 37),
        (64, 1),
        (1, 256),
        (3, 5),
        (2, 2),
    ] {
        run(w, h, 300);
    }
}

/// Pyramids storing fewer levels than the full chain: lod clamps to the
/// top stored level.
#[test]
fn partial_chains_clamp_to_stored_levels() {
    for (w, h, levels) in [(64, 64, 3), (1044, 1044, 4), (128, 512, 1), (1, 37, 2)] {
        run_levels(w, h, levels, 500);
    }
}

#[test]
fn npot_sizes() {
    for (w, h) in [(1044, 1044), (128, 512), (100, 37), (7, 9)] {
        run(w, h, 2000);
    }
}

#[test]
fn pot_sizes_and_goal() {
    let mut all = [0.0f64; 8];
    for (w, h) in [(256, 256), (64, 16), (4096, 4096)] {
        let wst = run(w, h, 3000);
        for (a, b) in all.iter_mut().zip(wst.0) {
            *a = a.max(b);
        }
    }
    // Goal of the issue: < 0.75 LSB for bilinear and trilinear.
    assert!(all[0] < 0.75 && all[1] < 0.75, "{all:?}");
    assert_eq!((all[2], all[6]), (0.0, 0.0));
}

/// Worst-case kernel inputs: a black/white edge makes the weight error
/// visible, and positions one step off a tie probe the rounding.
#[test]
fn high_contrast_edges() {
    let g = Geometry::new(256, 4, 3).unwrap();
    let mut buf = vec![0u32; g.len()];
    for y in 0..4 {
        for x in 0..256 {
            buf[y * 256 + x] = if (x / 3 + y) % 2 == 0 {
                0xFFFF_FFFF
            } else {
                0xFF00_0000
            };
        }
    }
    generate(&g, &mut buf).unwrap();
    let t = Tex { g, buf };
    let mut rng = Rng(99);
    let mut samples = Vec::new();
    for _ in 0..20_000 {
        let u = TexCoord::from_bits((rng.next_u64() >> 31) as i64);
        let v = TexCoord::from_bits((rng.next_u64() >> 31) as i64);
        let lod = Lod::from_bits((rng.next_u64() % 700) as i16 - 100);
        samples.push((u, v, lod));
    }
    let mut worst = Worst::default();
    check_samples(&t, &samples, &mut worst);
    println!("edges: {worst:?}");
}

/// `x` reduced as address mode `a` reduces coordinates (changing no
/// texel it selects), in f64: exact for these operations.
fn reduce(x: f64, a: AddressMode) -> f64 {
    match a {
        AddressMode::Wrap => x - x.floor(),
        AddressMode::Mirror => x - 2.0 * (x / 2.0).floor(),
        AddressMode::ClampToEdge | AddressMode::ClampToBorder => x.clamp(-1.0, 2.0),
        AddressMode::MirrorOnce => x.clamp(-2.0, 2.0),
    }
}

#[test]
fn non_finite_and_huge_f64_inputs() {
    let t = Tex::random(16, 8, 5, 5);
    for a in AddressMode::ALL {
        let mut s = Sampler::<_, AccurateAny>::with_state(t.pyramid(), state(a)).unwrap();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for mode in MODES {
                assert_eq!(
                    s.sample_f64(bad, 0.5, 0.0, mode),
                    Err(FilterError::NonFinite)
                );
                assert_eq!(
                    s.sample_f64(0.5, bad, 0.0, mode),
                    Err(FilterError::NonFinite)
                );
                assert_eq!(
                    s.sample_f64(0.5, 0.5, bad, mode),
                    Err(FilterError::NonFinite)
                );
            }
        }
        // ±1e6 through the float edge equals the fixed path and the reference.
        for (u, v) in [
            (1e6 + 0.1, -1e6 - 0.3),
            (-1e6 + 0.77, 1e6 + 0.5),
            (1e300, -1e300),
            (f64::MAX, f64::MIN),
        ] {
            for mode in MODES {
                let got = s.sample_f64(u, v, 1.25, mode).unwrap();
                let (ru, rv) = (reduce(u, a), reduce(v, a));
                let want = reference(
                    &t,
                    TexCoord::from_num(ru).to_num(),
                    TexCoord::from_num(rv).to_num(),
                    1.25,
                    mode,
                    a,
                );
                for (c, &wc) in want.iter().enumerate() {
                    assert!(
                        (f64::from((got >> (8 * c)) & 0xFF) - wc).abs()
                            <= bound(mode, false) + 1e-9
                    );
                }
            }
        }
        // Huge lod clamps to the top level.
        assert_eq!(
            s.sample_f64(0.3, 0.3, 1e9, Mode::Nearest).unwrap(),
            s.sample(
                TexCoord::from_num(0.3),
                TexCoord::from_num(0.3),
                Lod::from_num(4),
                Mode::Nearest
            )
        );
    }
}

#[test]
fn skip_rules_and_counts() {
    let t = Tex::random(32, 32, 6, 1);
    let mut s = Sampler::wrap(t.pyramid());
    let u = TexCoord::from_num(0.4);
    for lod in [-2.0, 0.0, 1.0, 5.0, 9.0] {
        s.sample(u, u, Lod::from_num(lod), Mode::Trilinear);
    }
    assert_eq!(s.stats().fetched, 5 * 4);
    assert_eq!(s.stats().skipped, 5 * 4);
    s.sample(u, u, Lod::from_num(1.5), Mode::Trilinear);
    s.sample(u, u, Lod::from_num(1.5), Mode::NearestTexelLinearLevel);
    s.sample(u, u, Lod::from_num(2.0), Mode::NearestTexelLinearLevel);
    s.sample(u, u, Lod::from_num(2.0), Mode::Nearest);
    s.sample(u, u, Lod::from_num(2.0), Mode::BilinearNearestLevel);
    assert_eq!(s.stats().fetched, 20 + 8 + 2 + 1 + 1 + 4);
    assert_eq!(s.stats().skipped, 20 + 1);
    s.reset_stats();
    assert_eq!(s.stats().fetched, 0);
}

/// FAST trilinear at every lod step of the first two level pairs
/// (`t = frac(lod)` over all of `0..=255`, plus the integral lods where
/// `t = 0` and the top level), on black/white texels (all 0 or 255 per
/// channel, the largest position error) and random texels, at texel
/// centres and corners of both levels (weights 0 and 1) and random
/// positions; power-of-two and not, wrap and clamp (`check_samples`).
#[test]
fn fast_trilinear_every_lod_step() {
    for (w, h) in [(16u32, 8u32), (13, 7)] {
        let levels = full_levels(w, h);
        let g = Geometry::new(w, h, levels).unwrap();
        let mut bw = vec![0u32; g.len()];
        for (i, t) in bw.iter_mut().take((w * h) as usize).enumerate() {
            *t = if (i * 7 / 3) % 2 == 0 {
                0xFF00_FF00
            } else {
                0x00FF_00FF
            };
        }
        generate(&g, &mut bw).unwrap();
        for t in [Tex { g, buf: bw }, Tex::random(w, h, levels, 17)] {
            let mut rng = Rng(u64::from(w) * 31 + 1);
            let mut samples = Vec::new();
            for lb in 0..=(i16::from(levels) * 256) {
                let lod = Lod::from_bits(lb);
                for d in [0.0, 0.5] {
                    let i = (rng.next_u64() % u64::from(w)) as f64;
                    let j = (rng.next_u64() % u64::from(h)) as f64;
                    let q = |x: f64| TexCoord::from_num(x);
                    samples.push((q((i + d) / f64::from(w)), q((j + d) / f64::from(h)), lod));
                }
                let u = TexCoord::from_bits((rng.next_u64() >> 30) as i64);
                let v = TexCoord::from_bits((rng.next_u64() >> 30) as i64);
                samples.push((u, v, lod));
            }
            let mut worst = Worst::default();
            check_samples(&t, &samples, &mut worst);
            println!("{w}x{h} every lod step: {worst:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]
    /// Full input range: any I32F32 coordinates, any lod, never a panic,
    /// always within the bound.
    #[test]
    fn full_range_within_bound(ub in any::<i64>(), vb in any::<i64>(), lb in any::<i16>(), small in any::<bool>(), wsel in 0usize..4) {
        let sizes = [(1u32, 1u32), (5, 3), (16, 64), (33, 8)];
        let (w, h) = sizes[wsel];
        let t = Tex::random(w, h, full_levels(w, h), 3);
        // Half the cases near [0, 1) to hit interesting texels, half over the full range.
        let (ub, vb) = if small { (ub % (3 << 32), vb % (3 << 32)) } else { (ub, vb) };
        let (u, v, lod) = (TexCoord::from_bits(ub), TexCoord::from_bits(vb), Lod::from_bits(lb));
        // Coordinates beyond 2^21 are not exact in f64: reduce first
        // (exactly, on the bits) as the mode does.
        let exact = |x: TexCoord, a: AddressMode| {
            let b = x.to_bits();
            TexCoord::from_bits(match a {
                AddressMode::Wrap => b & 0xFFFF_FFFF,
                AddressMode::Mirror => b & 0x1_FFFF_FFFF,
                AddressMode::ClampToEdge | AddressMode::ClampToBorder => b.clamp(-(1 << 32), 2 << 32),
                AddressMode::MirrorOnce => b.clamp(-(2 << 32), 2 << 32),
            })
        };
        for a in AddressMode::ALL {
            let p = t.pyramid();
            let mut acc = Sampler::<_, AccurateAny>::with_state(p, state(a)).unwrap();
            let mut fast = Sampler::<_, FastAny>::with_state(p, state(a)).unwrap();
            for mode in MODES {
                let got = both_tiers(&mut acc, &mut fast, p, (u, v, lod), mode);
                let want = reference(&t, exact(u, a).to_num(), exact(v, a).to_num(), lod.to_num(), mode, a);
                for (tier, g) in got.into_iter().enumerate() {
                    for (c, &wc) in want.iter().enumerate() {
                        let e = (f64::from((g >> (8 * c)) & 0xFF) - wc).abs();
                        prop_assert!(e <= bound(mode, tier == 1) + 1e-9, "{:?} {:?} tier {} {} {} {} ch{}: {}", a, mode, tier, u, v, lod, c, e);
                    }
                }
                // Only the reduced coordinate's bits matter.
                prop_assert_eq!(got, [acc.sample(exact(u, a), exact(v, a), lod, mode), fast.sample(exact(u, a), exact(v, a), lod, mode)]);
            }
        }
    }
}
