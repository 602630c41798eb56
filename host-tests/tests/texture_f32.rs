//! The bench's f32 filters compute the same thing as the firmware: within
//! 1 LSB per channel for bilinear/trilinear (both are within ~0.5 LSB of
//! exact), and the same texel for nearest modes except where f32 rounding
//! of `u·w` crosses a texel boundary (rare; counted).

use raymip::filter::{Address, Mode, Sampler, TexCoord};
use raymip::lod::Lod;
use raymip::mip::{Geometry, Pyramid, full_levels, generate};
use raymip_host::reference::texf32::SamplerF32;

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
    for a in [Address::Wrap, Address::Clamp] {
        let mut fixed = Sampler::new(Pyramid::new(g, &buf).unwrap(), a);
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
