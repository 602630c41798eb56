//! BC1–BC4: the firmware decoder (`raymip::texture::storage::bc`) against an independent
//! decoder from crates.io (`texture2ddecoder`, test-only dependency), bit
//! for bit, over random blocks and every mode edge; and the harness encoder
//! (`raymip_host::accuracy::texformat`) round trip.
//!
//! `texture2ddecoder` returns BGRA words and decodes the colour block of
//! BC2/BC3 with BC1's mode switch, where D3D specifies the four-colour
//! palette for every BC2/BC3 block; for those blocks with `c₀ ≤ c₁` the
//! reference decodes the equivalent BC1 block (endpoints swapped, indices
//! 0↔1 and 2↔3 exchanged, which is the same four-colour palette; equal
//! endpoints make every entry the endpoint).

use raymip::rng::XorShift64;
use raymip::texture::storage::bc::{decode_block, decode_texel};
use raymip::texture::storage::format::TexelFormat;
use raymip::texture::storage::mip::Texel;
use raymip_host::accuracy::texformat::encode_block;

/// BGRA word (texture2ddecoder) to our RGBA8 texel.
fn from_bgra(w: u32) -> Texel {
    let [b, g, r, a] = w.to_le_bytes();
    u32::from_le_bytes([r, g, b, a])
}

/// Reference decode of a BC1 colour block in the four-colour mode D3D
/// uses for BC2/BC3.
fn reference_four_colour(block: &[u8]) -> [Texel; 16] {
    let c0 = u16::from_le_bytes([block[0], block[1]]);
    let c1 = u16::from_le_bytes([block[2], block[3]]);
    let mut b = [0u8; 8];
    b.copy_from_slice(&block[..8]);
    if c0 < c1 {
        b[..2].copy_from_slice(&c1.to_le_bytes());
        b[2..4].copy_from_slice(&c0.to_le_bytes());
        let idx = u32::from_le_bytes([b[4], b[5], b[6], b[7]]);
        // Swap 0↔1 and 2↔3: flip the low bit of every 2-bit index.
        b[4..].copy_from_slice(&(idx ^ 0x5555_5555).to_le_bytes());
    } else if c0 == c1 {
        b[4..].copy_from_slice(&[0; 4]);
    }
    let mut out = [0u32; 16];
    texture2ddecoder::decode_bc1_block(&b, &mut out);
    out.map(from_bgra)
}

/// The independent decode of `block` in `format` as RGBA8 texels.
fn reference(format: TexelFormat, block: &[u8]) -> [Texel; 16] {
    let mut out = [0u32; 16];
    match format {
        TexelFormat::Bc1 => {
            texture2ddecoder::decode_bc1a_block(block, &mut out);
            out.map(from_bgra)
        }
        TexelFormat::Bc2 | TexelFormat::Bc3 => {
            if format == TexelFormat::Bc2 {
                texture2ddecoder::decode_bc2_block(block, &mut out);
            } else {
                texture2ddecoder::decode_bc3_block(block, &mut out);
            }
            let colour = reference_four_colour(&block[8..]);
            let mut res = [0u32; 16];
            for i in 0..16 {
                res[i] = (colour[i] & 0x00FF_FFFF) | (out[i] & 0xFF00_0000);
            }
            res
        }
        TexelFormat::Bc4 => {
            texture2ddecoder::decode_bc4_block(block, &mut out);
            // Red is the third byte of the BGRA word; the rest is ours
            // (D3D: green = blue = 0, alpha = 1).
            out.map(|w| ((w >> 16) & 0xFF) | 0xFF00_0000)
        }
        _ => unreachable!(),
    }
}

const BC: [TexelFormat; 4] = [
    TexelFormat::Bc1,
    TexelFormat::Bc2,
    TexelFormat::Bc3,
    TexelFormat::Bc4,
];

fn check(format: TexelFormat, block: &[u8]) {
    let mut ours = [0u32; 16];
    decode_block(format, block, &mut ours);
    let want = reference(format, block);
    assert_eq!(ours, want, "{format:?} block {block:02x?}");
    for (i, &t) in ours.iter().enumerate() {
        assert_eq!(decode_texel(format, block, i), t);
    }
}

#[test]
fn random_blocks_bit_exact() {
    let mut rng = XorShift64(0x9E37_79B9_7F4A_7C15);
    for format in BC {
        let n = format.unit_bytes() as usize;
        for _ in 0..50_000 {
            let bytes: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
            check(format, &bytes);
        }
    }
}

/// Every mode edge: colour endpoints equal, one apart either way, at the
/// extremes; BC4/BC3-alpha values equal, one apart, 0 and 255; each with
/// every index in every position.
#[test]
fn mode_edges_bit_exact() {
    let mut rng = XorShift64(12345);
    let colour_pairs: [(u16, u16); 8] = [
        (0, 0),
        (0xFFFF, 0xFFFF),
        (0x1234, 0x1234),
        (0x1235, 0x1234),
        (0x1234, 0x1235),
        (0xFFFF, 0),
        (0, 0xFFFF),
        (1, 0),
    ];
    let value_pairs: [(u8, u8); 8] = [
        (0, 0),
        (255, 255),
        (100, 100),
        (101, 100),
        (100, 101),
        (255, 0),
        (0, 255),
        (1, 0),
    ];
    for &(c0, c1) in &colour_pairs {
        for &(a0, a1) in &value_pairs {
            for rep in 0..64 {
                // Index patterns: all k (rep < 8 walks each index value), then random.
                let cidx = if rep < 4 {
                    0x5555_5555u32 * rep as u32
                } else {
                    rng.next_u64() as u32
                };
                let vidx = if rep < 8 {
                    (0..16).fold(0u64, |b, i| b | ((rep as u64) << (3 * i)))
                } else {
                    rng.next_u64() & 0xFFFF_FFFF_FFFF
                };
                let mut colour = [0u8; 8];
                colour[..2].copy_from_slice(&c0.to_le_bytes());
                colour[2..4].copy_from_slice(&c1.to_le_bytes());
                colour[4..].copy_from_slice(&cidx.to_le_bytes());
                let mut value = [0u8; 8];
                value[0] = a0;
                value[1] = a1;
                value[2..].copy_from_slice(&vidx.to_le_bytes()[..6]);
                check(TexelFormat::Bc1, &colour);
                check(TexelFormat::Bc4, &value);
                let mut bc3 = value.to_vec();
                bc3.extend_from_slice(&colour);
                check(TexelFormat::Bc3, &bc3);
                let mut bc2 = (rng.next_u64()).to_le_bytes().to_vec();
                bc2.extend_from_slice(&colour);
                check(TexelFormat::Bc2, &bc2);
            }
        }
    }
}

/// The harness encoder produces blocks the decoder reads back close to the
/// source: within the RGB565 box-diagonal palette's reach for smooth
/// blocks, exact for two-colour blocks whose colours are 565 values.
#[test]
fn encoder_round_trip() {
    let mut rng = XorShift64(777);
    for format in BC {
        for _ in 0..2000 {
            // Two 565-exact colours (and alphas 0/255), randomly placed.
            let a = TexelFormat::Rgb565.decode(rng.next_u64() as u32 & 0xFFFF);
            let b = TexelFormat::Rgb565.decode(rng.next_u64() as u32 & 0xFFFF);
            let texels: [Texel; 16] = std::array::from_fn(|_| {
                let t = if rng.next_u64() & 1 == 0 { a } else { b };
                if format == TexelFormat::Bc1 {
                    t
                } else {
                    (t & 0xFFFFFF) | ((rng.next_u64() as u32 & 1) * 0xFF00_0000)
                }
            });
            let block = encode_block(format, &texels);
            assert_eq!(block.len(), format.unit_bytes() as usize);
            let mut out = [0u32; 16];
            decode_block(format, &block, &mut out);
            for i in 0..16 {
                let (s, d) = (texels[i].to_le_bytes(), out[i].to_le_bytes());
                let channels = if format == TexelFormat::Bc4 {
                    0..1
                } else {
                    0..4
                };
                for c in channels {
                    assert_eq!(
                        s[c], d[c],
                        "{format:?} texel {i} channel {c}: {texels:08x?}"
                    );
                }
            }
        }
    }
    // BC1 transparency: alpha < 128 → transparent black.
    let mut texels = [0xFF80_4020u32; 16];
    texels[5] = 0x0000_0000;
    let block = encode_block(TexelFormat::Bc1, &texels);
    let mut out = [0u32; 16];
    decode_block(TexelFormat::Bc1, &block, &mut out);
    assert_eq!(out[5], 0);
    assert_eq!(out[0] >> 24, 255);
}
