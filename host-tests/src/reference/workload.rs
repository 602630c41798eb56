//! The fixed-vs-f32 texture workload shared by `benches/texture.rs` and
//! `examples/texture_icount.rs`: a random pyramid and random sample
//! positions, so both measure the same thing.

use raymip::filter::TexCoord;
use raymip::lod::Lod;
use raymip::mip::{Geometry, MipError, Texel, full_levels, generate};

use super::Rng;

/// A `size × size` full-chain pyramid with random level-0 texels.
///
/// # Errors
/// When `size` is 0 or above [`raymip::mip::MAX_SIZE`].
pub fn random_pyramid(size: u32) -> Result<(Geometry, Vec<Texel>), MipError> {
    let g = Geometry::new(size, size, full_levels(size, size))?;
    let mut buf = vec![0; g.len()];
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for t in buf
        .iter_mut()
        .take(g.width() as usize * g.height() as usize)
    {
        *t = rng.next_u64() as u32;
    }
    generate(&g, &mut buf)?;
    Ok((g, buf))
}

/// `n` random `(u, v, lod)` with u, v in [−2, 2) and lod in [0, 6) with a
/// fraction in [0.125, 0.875), so trilinear always reads two levels.
pub fn random_inputs(n: usize) -> Vec<(f32, f32, f32)> {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let mut unit = move || (rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
    (0..n)
        .map(|_| {
            let lod = (unit() * 6.0).floor() + 0.125 + 0.75 * unit();
            (unit() * 4.0 - 2.0, unit() * 4.0 - 2.0, lod)
        })
        .collect()
}

/// The same inputs in the firmware's formats.
pub fn to_fixed(inputs: &[(f32, f32, f32)]) -> Vec<(TexCoord, TexCoord, Lod)> {
    inputs
        .iter()
        .map(|&(u, v, l)| {
            (
                TexCoord::from_num(u),
                TexCoord::from_num(v),
                Lod::from_num(l),
            )
        })
        .collect()
}
