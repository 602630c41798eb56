//! The bench's f32 filters compute the same thing as the firmware: within
//! 1 LSB per channel for bilinear/trilinear (both are within ~0.5 LSB of
//! exact), and the same texel for nearest modes except where f32 rounding
//! of `u·w` crosses a texel boundary (rare; counted).

use raymip::baseline_f32::SamplerF32;
use raymip::texture::storage::mip::{Geometry, Pyramid, full_levels, generate};
use raymip::texture::{AddressMode, Mode, Sampler};
use raymip::units::{Lod, TexCoord};

#[test]
fn f32_matches_fixed() {
    let (w, h) = (300u32, 64u32);
    let g = Geometry::new(w, h, full_levels(w, h)).unwrap();
    let mut buf = vec![0u32; g.len()];
    let mut s = 12345u64;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    for t in &mut buf[..(w * h) as usize] {
        *t = next() as u32;
    }
    generate(&g, &mut buf).unwrap();
    let mut mismatched_nearest = 0;
    let n = 20_000;
    for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
        let mut fixed = Sampler::with_address(Pyramid::new(g, &buf).unwrap(), a);
        let float = SamplerF32::new(g, &buf, a).unwrap();
        for _ in 0..n {
            // Inputs exactly representable in f32 and in the fixed formats.
            let u = ((next() >> 40) as f32 / (1u32 << 22) as f32) - 1.0;
            let v = ((next() >> 40) as f32 / (1u32 << 22) as f32) - 1.0;
            let lod = ((next() % 2600) as f32 - 200.0) / 256.0;
            let (uf, vf, lf) = (
                TexCoord::from_num(u),
                TexCoord::from_num(v),
                Lod::from_num(lod),
            );
            for mode in [
                Mode::Trilinear,
                Mode::BilinearNearestLevel,
                Mode::Nearest,
                Mode::NearestTexelLinearLevel,
            ] {
                let x = fixed.sample(uf, vf, lf, mode).to_le_bytes();
                let y = float.sample(u, v, lod, mode).to_le_bytes();
                let d = x.iter().zip(y).map(|(&p, q)| p.abs_diff(q)).max().unwrap();
                match mode {
                    Mode::Nearest | Mode::NearestTexelLinearLevel => {
                        mismatched_nearest += usize::from(d > 1)
                    }
                    _ => assert!(d <= 1, "{a:?} {mode:?} {u} {v} {lod}: {x:?} vs {y:?}"),
                }
            }
        }
    }
    assert!(mismatched_nearest * 1000 < 4 * n, "{mismatched_nearest}");
}

/// `SamplerF32::sample_aniso` against the exact f64 anisotropic filter
/// (`raymip_reference::sampler::Sampler::sample_aniso`: the same probe
/// rule in f64): within ½ LSB
/// of final rounding plus 1/64 LSB for f32 arithmetic (positions, weights,
/// `log2f`), over random footprints of every eccentricity and every cap;
/// footprints whose probe count or major axis is a rounding tie are left
/// out (counted: few).
#[test]
fn f32_aniso_matches_f64_reference() {
    use raymip::rng::XorShift64;
    use raymip_host::tradeoff::filter_stage::{TestTexture, ref_state};
    use raymip_reference::Draw;
    use raymip_reference::sampler::{Mode as RefMode, Sampler as RefSampler};

    let tex = TestTexture::random(32, 0xA2150);
    let rt = tex.reference();
    let float = SamplerF32::new(tex.geometry, &tex.texels, AddressMode::Wrap).unwrap();
    let mut r = XorShift64(77);
    let (mut ties, n) = (0, 5_000);
    for i in 0..n {
        let max = (i % 16) as u8 + 1;
        let mut state = ref_state();
        state.max_aniso = u32::from(max);
        let exact = RefSampler { tex: &rt, state };
        let f = |x: f64| x as f32;
        let (u, v) = (f(r.range(-2.0, 2.0)), f(r.range(-2.0, 2.0)));
        let s = r.unit() * r.unit();
        let axes32 = [
            [f(r.range(-0.5, 0.5)), f(r.range(-0.5, 0.5))],
            [f(r.range(-0.5, 0.5) * s), f(r.range(-0.5, 0.5) * s)],
        ];
        let axes = axes32.map(|a| a.map(f64::from));
        let len = |a: [f64; 2]| (a[0] * 32.0).hypot(a[1] * 32.0);
        let (la, lb) = (len(axes[0]), len(axes[1]));
        let ratio = la.max(lb) / la.min(lb).max(1e-300);
        if (1..=16).any(|k| (ratio / f64::from(k) - 1.0).abs() < 1e-4)
            || (la - lb).abs() < 1e-4 * la.max(lb)
            || la.min(lb) < 1e-4
        {
            ties += 1;
            continue;
        }
        let got = float.sample_aniso(u, v, axes32, max, Mode::Trilinear);
        let want = exact.sample_aniso(f64::from(u), f64::from(v), axes, RefMode::Trilinear);
        for (g, w) in got.to_le_bytes().iter().zip(want) {
            let e = (f64::from(*g) - w).abs();
            assert!(
                e <= 0.5 + 1.0 / 64.0,
                "max {max} {u} {v} {axes:?}: {got:08x} vs {want:?}"
            );
        }
    }
    assert!(ties * 50 < n, "{ties} ties");
}
