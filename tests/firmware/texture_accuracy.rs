//! Filtering of linear RGBA8 data against the f64 reference sampler
//! (`raymip_reference::sampler`: texel centres at (i + ½)/size; every
//! address mode as the Vulkan wrapping operation defines it, the border
//! colour for clamp-to-border; lod clamped to the stored levels, nearest
//! level = floor(lod + ½)), for both precision tiers.
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
use common::{XorShift64, random_texture, samples_for};
use raymip_reference::sampler::{self as reference, Texture};

/// A generated pyramid with random level 0, owned, and the reference's
/// copy of its texels.
struct Tex {
    g: Geometry,
    buf: Vec<Texel>,
    reference: Texture,
}

impl Tex {
    fn new(g: Geometry, buf: Vec<Texel>) -> Self {
        let reference = Texture::from_rgba8_levels(g.width(), g.height(), g.levels(), &buf);
        Tex { g, buf, reference }
    }
    fn random(w: u32, h: u32, levels: u8, seed: u64) -> Self {
        let (g, buf) = random_texture(w, h, levels, seed).unwrap();
        Self::new(g, buf)
    }
    fn pyramid(&self) -> Pyramid<'_> {
        Pyramid::new(self.g, &self.buf).unwrap()
    }
}

/// The border colour of every sampler here (linear RGBA8).
const BORDER: Texel = 0x80FF_4010;

/// Reference sample (channel values 0..=255); `u`, `v`, `lod` are the
/// exact values of the fixed inputs.
fn reference(t: &Tex, u: f64, v: f64, lod: f64, mode: Mode, a: AddressMode) -> [f64; 4] {
    let address = reference::Address::from_index(a as u8).unwrap();
    let sampler = reference::Sampler {
        tex: &t.reference,
        state: reference::State {
            address: [address; 2],
            border: BORDER.to_le_bytes().map(f64::from),
            ..reference::State::default()
        },
    };
    sampler.sample(u, v, lod, reference::Mode::from_index(mode as u8).unwrap())
}

/// The reference's address and filter modes are numbered as the
/// firmware's (`reference()` maps one to the other by number).
#[test]
fn reference_modes_are_numbered_as_the_firmware() {
    for a in AddressMode::ALL {
        let r = reference::Address::from_index(a as u8).unwrap();
        assert_eq!(format!("{r:?}"), format!("{a:?}"));
    }
    assert_eq!(
        reference::Address::from_index(AddressMode::ALL.len() as u8),
        None
    );
    for m in MODES {
        let r = reference::Mode::from_index(m as u8).unwrap();
        assert_eq!(format!("{r:?}"), format!("{m:?}"));
    }
    assert_eq!(reference::Mode::from_index(MODES.len() as u8), None);
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

fn run(w: u32, h: u32, n: usize) -> Worst {
    run_levels(w, h, full_levels(w, h), n)
}

fn run_levels(w: u32, h: u32, levels: u8, n: usize) -> Worst {
    let t = Tex::random(w, h, levels, u64::from(w) * 7919 + u64::from(h));
    let mut worst = Worst::default();
    check_samples(
        &t,
        &samples_for(&t.g, n, u64::from(w ^ (h << 3)), false),
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
    let t = Tex::new(g, buf);
    let mut rng = XorShift64(99);
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
        for t in [Tex::new(g, bw), Tex::random(w, h, levels, 17)] {
            let mut rng = XorShift64(u64::from(w) * 31 + 1);
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
