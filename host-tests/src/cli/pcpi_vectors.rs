//! Reference vectors of the texture co-processor (`demo/softcore/pcpi_tex.v`), written by the firmware's software paths: `raymip-demo
//! pcpi-vectors FILE` writes them and the Verilator testbench
//! `demo/softcore/tb_pcpi_tex.cpp` checks every output bit of the RTL
//! against them (`scripts/softcore`).
//!
//! One vector a line, `OP RS1 RS2 RD` in hex (OP = the instruction's
//! funct3; RS1, RS2, RD 32-bit words):
//! * `0` `tex.log2pl`: `RS1`/`RS2` the low/high word of a U32F32 path length,
//!   `RD = log2_u32f32(Pl).to_bits() + 0x80` (the value the firmware's
//!   `table_lod` and `cone_lod` subtract from; see `raymip::coproc::pcpi`);
//! * `1` `tex.lod`: `RS1` the `tex.log2pl` value of `Pl` (as above), `RS2`
//!   the bits of a `Log2Pb` entry, `RD = table_lod::<Accurate>(Pl, Pb)` sign-extended,
//!   `0x8000_0000` for `None` (untextured);
//! * `2`…`5` the ACCURATE filter's `tex.bw` (`RS1 = fx`, `RS2 = fy`),
//!   `tex.bt` (`t00`, `t10`), `tex.bb` (`t01`, `t11`; `RD` = the footprint
//!   filtered and rounded, `round_wide(bilerp(..))`) and `tex.blend`
//!   (`RS1 = t`; `RD = blend_wide` of the last two footprints' `bilerp`):
//!   stateful, so the file is also the order they run in. Each level pair
//!   is `2 3 4 2 3 4` followed by blends at several fractions; `RD` of
//!   `tex.bw` and `tex.bt` is 0.
//!
//! Inputs: zero, every power of two and its neighbours, every one of the
//! 64 table intervals at its ends and middle in every octave, the U1F31
//! range the cone lod's normal term reads (`[2¹⁵, 2³¹]` as U32F32 bits),
//! and pseudo-random values with a uniformly drawn octave; entries: the
//! three markers, the finite extremes and random entries. Filter
//! footprints: all-0, all-255, each corner alone at 255 (and alone at 0),
//! the per-channel extremes and random texels, with weights at 0, 1, 2048,
//! 4095 and 4096 on each axis and random; fractions 0, 1, 128, 255, 256 and
//! random.
//!
//! Then, for the CFU unit only (`demo/softcore/cfu_tex.v`; the PCPI unit
//! does not implement them and its testbench stops at the first), the
//! addressing instructions with OP = the function id `{funct7, funct3}`:
//! * `8` `tex.lvl` (`RS1` = the level's byte address, `RS2` =
//!   [`raymip::texture::coproc::level_config`]; `RD = 0`),
//! * `9` `tex.addr` (`RS1`, `RS2` = [`raymip::texture::coproc::coord_i4f28`] of `u`,
//!   `v` in each axis's mode; `RD` = the address of `t00`) and `a` … `c`
//!   `tex.tap` (`t10`, `t01`, `t11`), the addresses from
//!   [`raymip::texture::address::AddressMode::linear`] (the software taps),
//! * then `tex.bt`, `tex.bb` of random texels with the weights `tex.addr`
//!   latched (`RD` of `tex.bb` with the software weights).
//!
//! Levels of every shape `2^kx × 2^ky` up to the largest side, every mode
//! pair but the border colour, coordinates at and around the texel centres
//! and edges, the seams, far outside `[0, 1)` and random.
//!
//! Then the texture unit (`funct7 = 2`), whose instructions read the RAM
//! behind the unit's read port: `400 OFFSET WORD 0` (not an instruction)
//! stores `WORD` at word `OFFSET` of that RAM ([`TB_RAM_BASE`], [`TB_RAM_BYTES`]:
//! the testbench's RAM, as in the LiteX SoC). Pyramids of several shapes
//! (full and trimmed) with random texels, each with samplers of several
//! address modes and lod windows: their texels and each sampler's
//! descriptor block ([`raymip::texture::Sampler::texture_unit_block`]) go
//! into the RAM, then
//! * `10` `tex.ram` (`RD` = the RAM's base `|` log2 of its bytes),
//! * `11` `tex.sel` (`RS1` = the block's address, `RS2` = a lod, I8F8 bits
//!   sign-extended; `RD = 1`; and blocks outside the RAM or without the
//!   valid bit [`raymip::coproc::BLOCK_VALID`]: `RD = 0`),
//! * `12` `tex.tri` / `13` `tex.bil` (`RS1`, `RS2` as for `tex.addr`;
//!   `RD` = the sampler's `sample_trilinear` / `sample_bilinear`, the
//!   software path) after each `tex.sel`,
//!
//! with lods below, inside and above each window, at and around level
//! boundaries, fractions 0 and random.

use std::fmt::Write as _;

use fixed::types::U32F32;
use raymip::coproc::{BLOCK_VALID, BLOCK_WORDS};
use raymip::lod::table_lod;
use raymip::log2::log2_u32f32;
use raymip::rng::Rng;
use raymip::texture::address::AddressMode;
use raymip::texture::address::AnyAxis;
use raymip::texture::coproc::{coord_i4f28, level_config};
use raymip::texture::kernel::accurate::{WEIGHT_ONE, Wide, bilerp, blend_wide, round_wide};
use raymip::texture::sampler::state::SamplerDesc;
use raymip::texture::storage::pow2::Pow2Pyramid;
use raymip::units::{Accurate, Log2Pb, PathLength, TexCoord};
use raymip::{Cfg, Geometry, Lod, Pyramid, Sampler, SamplerState};

/// The software `tex.log2pl`: `log2 Pl` in I16F16 bits plus the I8F8
/// rounding offset `0x80`.
#[must_use]
pub fn log2pl(pl: u64) -> u32 {
    (log2_u32f32(U32F32::from_bits(pl)).to_bits() as u32).wrapping_add(0x80)
}

/// The software `tex.lod` of `(Pl, entry)`: `table_lod` sign-extended, or
/// `0x8000_0000` for `None`.
#[must_use]
pub fn lod(pl: u64, pb: Log2Pb) -> u32 {
    match table_lod::<Accurate>(PathLength::from_bits(pl), pb) {
        Some(l) => i32::from(l.to_bits()) as u32,
        None => 0x8000_0000,
    }
}

/// Path lengths of every input class (see the module docs).
#[must_use]
pub fn path_lengths() -> Vec<u64> {
    let mut v = vec![0u64, u64::MAX];
    for s in 0..64 {
        let p = 1u64 << s;
        v.extend([p, p - 1, p.wrapping_add(1), p | (p >> 1), !0u64 >> (63 - s)]);
    }
    // Every interval (index i, weight t) of the mantissa in every octave.
    for i in 0..64u64 {
        for t in [0u64, 1, 0x7FFF, 0x8000, 0xFFFF] {
            for low in [0u64, 0x1FF] {
                let m = (1u64 << 31) | (i << 25) | (t << 9) | low;
                for s in 0..=32 {
                    v.push(m << s);
                    v.push(m >> s.min(31));
                }
            }
        }
    }
    // U1F31 |n·d| values of the cone lod (clamped to [2¹⁵, 2³¹]).
    for c in [1u64 << 15, (1 << 15) + 1, 1 << 30, (1 << 31) - 1, 1 << 31] {
        v.push(c);
    }
    let mut r = Rng::new(0x7e8_c0de);
    for _ in 0..20_000 {
        let octave = r.next_u32() % 64;
        let m = (u64::from(r.next_u32()) << 32) | u64::from(r.next_u32());
        v.push((1u64 << octave) | (m & ((1u64 << octave) - 1)));
    }
    v
}

/// `Log2Pb` entries: the markers, the finite extremes, zero and neighbours,
/// and `n` random raw values (clamped as `Log2Pb::from_bits` clamps).
#[must_use]
pub fn entries(n: usize) -> Vec<Log2Pb> {
    let mut v = vec![
        Log2Pb::UNTEXTURED,
        Log2Pb::DEGENERATE_GEOMETRY,
        Log2Pb::DEGENERATE_UV,
        Log2Pb::MIN,
        Log2Pb::MAX,
        Log2Pb::from_bits(0),
        Log2Pb::from_bits(1),
        Log2Pb::from_bits(-1),
        Log2Pb::from_bits(0x7F),
        Log2Pb::from_bits(0x80),
    ];
    let mut r = Rng::new(0x1d5_b17e);
    for _ in 0..n {
        let b = r.next_u32() as i32;
        v.push(Log2Pb::from_bits(b >> (r.next_u32() % 9)));
    }
    v
}

/// One footprint of the filter vectors: `[t00, t10, t01, t11]`, `fx`, `fy`.
pub type Footprint = ([u32; 4], u32, u32);

/// The filter footprints of every input class (see the module docs), in
/// pairs (level `a`, level `b`).
#[must_use]
pub fn footprints() -> Vec<(Footprint, Footprint)> {
    let weights = [0, 1, 2048, WEIGHT_ONE - 1, WEIGHT_ONE];
    let mut texels = vec![[0u32; 4], [u32::MAX; 4]];
    for c in 0..4 {
        let mut one = [0u32; 4];
        one[c] = u32::MAX;
        texels.push(one);
        let mut hole = [u32::MAX; 4];
        hole[c] = 0;
        texels.push(hole);
    }
    // Channel extremes apart: 0 and 255 in alternating channels.
    texels.push([0x00FF_00FF, 0xFF00_FF00, 0xFF00_FF00, 0x00FF_00FF]);
    let mut r = Rng::new(0xf117_e125);
    let random_texels = |r: &mut Rng| core::array::from_fn(|_| r.next_u32());
    for _ in 0..8 {
        texels.push(random_texels(&mut r));
    }
    let mut v = Vec::new();
    for (k, &t) in texels.iter().enumerate() {
        for &fx in &weights {
            for &fy in &weights {
                let other = texels[(k + 1 + (fx as usize) % 7) % texels.len()];
                v.push(((t, fx, fy), (other, fy, fx)));
            }
        }
    }
    // Rounding ties: a corner weight of 2176·3855 = 2²³ − 2⁷ on a channel
    // value 1 gives the corner sum X = 2²³ − 2⁷, whose 8.16 value
    // (X + 2⁷) >> 8 = 2¹⁵ rounds up to 1 only with both rounding constants
    // exact (each corner in turn, paired with zero and with all-255).
    for (c, (fx, fy)) in [(1920, 241), (2176, 241), (1920, 3855), (2176, 3855)]
        .into_iter()
        .enumerate()
    {
        let mut t = [0u32; 4];
        t[c] = 0x0101_0101;
        for other in [[0; 4], [u32::MAX; 4], t] {
            v.push(((t, fx, fy), (other, fx, fy)));
            v.push(((other, fy, fx), (t, fx, fy)));
        }
    }
    for _ in 0..4000 {
        let w = |r: &mut Rng| r.next_u32() % (WEIGHT_ONE + 1);
        let a = (random_texels(&mut r), w(&mut r), w(&mut r));
        let b = (random_texels(&mut r), w(&mut r), w(&mut r));
        v.push((a, b));
    }
    v
}

/// The software ACCURATE filter of one footprint in 8.16 (`bilerp`).
#[must_use]
pub fn level(f: Footprint) -> Wide {
    let ([t00, t10, t01, t11], fx, fy) = f;
    bilerp(t00, t10, t01, t11, fx, fy)
}

/// The filter vectors (ops 2…5, module docs), in the order they run.
fn filter_vectors(out: &mut String) {
    let mut r = Rng::new(0xb1e_0d5);
    for (a, b) in footprints() {
        for f in [a, b] {
            let (t, fx, fy) = f;
            let _ = writeln!(out, "2 {fx:08x} {fy:08x} 00000000");
            let _ = writeln!(out, "3 {:08x} {:08x} 00000000", t[0], t[1]);
            let rounded = round_wide(level(f));
            let _ = writeln!(out, "4 {:08x} {:08x} {rounded:08x}", t[2], t[3]);
        }
        let (wa, wb) = (level(a), level(b));
        for t in [0, 1, 128, 255, 256, r.next_u32() % 257] {
            let _ = writeln!(out, "5 {t:08x} 00000000 {:08x}", blend_wide(wa, wb, t));
        }
    }
}

/// The address modes the CFU's addressing instructions implement.
pub const ADDRESS_MODES: [AddressMode; 4] = [
    AddressMode::Wrap,
    AddressMode::Mirror,
    AddressMode::ClampToEdge,
    AddressMode::MirrorOnce,
];

/// Coordinates (I32F32 bits) for a level side of `2^k` texels: the
/// texel centres and edges near 0, ½ and 1 with their neighbours, far
/// outside `[0, 1)` and `n` random ones.
#[must_use]
pub fn coords(k: u32, r: &mut Rng, n: usize) -> Vec<i64> {
    let one = 1i64 << 32;
    let texel = one >> k;
    let mut v = vec![
        i64::MIN,
        i64::MAX,
        -one * 5,
        one * 4 + 7,
        -one,
        2 * one,
        -1,
        0,
        1,
    ];
    for base in [0, one / 2, one, -one / 2, 3 * one / 2] {
        for d in [-texel, -texel / 2, 0, texel / 2, texel] {
            for e in [-1, 0, 1, 1 << 3, 1 << 4] {
                v.push(base + d + e);
            }
        }
    }
    for _ in 0..n {
        let hi = i64::from(r.next_u32() as i32 >> (r.next_u32() % 32));
        v.push((hi << 32) | i64::from(r.next_u32()));
    }
    v
}

/// The addressing vectors (OP 8…12, then 3 and 4; module docs).
fn address_vectors(out: &mut String) {
    let mut r = Rng::new(0x0add_2e55);
    let tap = |mode: AddressMode, c: i64, k: u32| {
        let ([i0, i1], f) = mode.linear(TexCoord::from_bits(c), 1 << k);
        (i0.unwrap_or(0), i1.unwrap_or(0), f)
    };
    for kx in 0..=15u32 {
        for ky in 0..=15u32 {
            let (mu, mv) = (
                ADDRESS_MODES[(kx % 4) as usize],
                ADDRESS_MODES[((kx + ky) % 4) as usize],
            );
            let modes = [(mu, mv)].into_iter().chain(if kx == ky {
                ADDRESS_MODES
                    .iter()
                    .flat_map(|&a| ADDRESS_MODES.iter().map(move |&b| (a, b)))
                    .collect()
            } else {
                Vec::new()
            });
            for (mu, mv) in modes {
                let base = r.next_u32() & !3;
                let _ = writeln!(
                    out,
                    "8 {base:08x} {:08x} 00000000",
                    level_config(kx, ky, mu, mv)
                );
                let (us, vs) = (coords(kx, &mut r, 24), coords(ky, &mut r, 24));
                for (j, &u) in us.iter().enumerate() {
                    let v = vs[(j * 7 + 3) % vs.len()];
                    let (x0, x1, fx) = tap(mu, u, kx);
                    let (y0, y1, fy) = tap(mv, v, ky);
                    let addr = |x: u32, y: u32| base.wrapping_add(((y << kx) | x) << 2);
                    let _ = writeln!(
                        out,
                        "9 {:08x} {:08x} {:08x}",
                        coord_i4f28(mu, TexCoord::from_bits(u)),
                        coord_i4f28(mv, TexCoord::from_bits(v)),
                        addr(x0, y0)
                    );
                    let _ = writeln!(out, "a 00000000 00000000 {:08x}", addr(x1, y0));
                    let _ = writeln!(out, "b 00000000 00000000 {:08x}", addr(x0, y1));
                    let _ = writeln!(out, "c 00000000 00000000 {:08x}", addr(x1, y1));
                    if j % 4 == 0 {
                        let t: [u32; 4] = core::array::from_fn(|_| r.next_u32());
                        let rounded = round_wide(level((t, fx, fy)));
                        let _ = writeln!(out, "3 {:08x} {:08x} 00000000", t[0], t[1]);
                        let _ = writeln!(out, "4 {:08x} {:08x} {rounded:08x}", t[2], t[3]);
                    }
                }
            }
        }
    }
}

/// Base address of the RAM the texture unit reads in the testbench (the
/// LiteX SoC's main RAM).
pub const TB_RAM_BASE: u32 = 0x4000_0000;
/// Bytes of that RAM (`2¹⁸`, cfu_tex.v's default `RAM_AW = 15`).
pub const TB_RAM_BYTES: u32 = 1 << 18;

/// Pyramid shapes `(width, height, levels)` of the texture-unit vectors:
/// full pyramids, trimmed ones, a single texel.
const TU_SHAPES: [(u32, u32, u8); 6] = [
    (64, 64, 7),
    (128, 8, 8),
    (16, 256, 5),
    (1, 1, 1),
    (32, 32, 3),
    (4, 64, 7),
];
/// Lod windows `(bias, lo, hi)` (I8F8 bits) per pyramid, `top` its top
/// level: none, a bias, a bias with both clamps, a single level.
fn tu_windows(top: i32) -> [(i32, i32, i32); 4] {
    [
        (0, 0, 16 * 256),
        (300, 0, 16 * 256),
        (-700, 256 + 64, top * 256 - 32),
        (0, top * 256, top * 256),
    ]
}

/// The texture-unit vectors (OP 400 and 10…13; module docs); returns how
/// many samplers they cover (every pyramid with every window, unless one
/// cannot be made or has no descriptor block).
fn texture_unit_vectors(out: &mut String) -> usize {
    let shapes = TU_SHAPES;
    let mut made = 0;
    let mut r = Rng::new(0x7e_c5e1);
    let lens: Vec<usize> = shapes
        .iter()
        .map(|&(w, h, l)| Geometry::new(w, h, l).map_or(0, |g| g.len()))
        .collect();
    // One arena: every pyramid, then room for a descriptor block; the
    // arena's first word is word 0 of the RAM.
    let total: usize = lens.iter().sum();
    let arena: Vec<u32> = (0..total + BLOCK_WORDS).map(|_| r.next_u32()).collect();
    let ram = (arena.as_ptr() as usize, TB_RAM_BYTES as usize);
    let _ = writeln!(
        out,
        "10 00000000 00000000 {:08x}",
        TB_RAM_BASE | TB_RAM_BYTES.trailing_zeros()
    );
    for (k, &w) in arena[..total].iter().enumerate() {
        let _ = writeln!(out, "400 {k:08x} {w:08x} 00000000");
    }
    let block_at = total as u32;
    let block_addr = TB_RAM_BASE + 4 * block_at;
    let lod = |bits: i32| Lod::from_bits(bits as i16);
    let mut start = 0;
    for (&(w, h, l), &len) in shapes.iter().zip(&lens) {
        let texels = &arena[start..start + len];
        start += len;
        let Ok(p) = Geometry::new(w, h, l).and_then(|g| Pyramid::new(g, texels)) else {
            continue;
        };
        let Ok(p) = Pow2Pyramid::new(p) else { continue };
        let top = i32::from(l) - 1;
        for (j, &(bias, lo, hi)) in tu_windows(top).iter().enumerate() {
            let (mu, mv) = (
                ADDRESS_MODES[(j + usize::from(l)) % 4],
                ADDRESS_MODES[(j + usize::from(l) * 3 + 1) % 4],
            );
            let desc = SamplerDesc {
                address_u: mu,
                address_v: mv,
                lod_bias: lod(bias),
                min_lod: lod(lo.max(0)),
                max_lod: lod(hi.max(lo.max(0))),
                ..SamplerDesc::default()
            };
            let Ok(state) = SamplerState::new(desc) else {
                continue;
            };
            let Ok(mut s) = Sampler::<_, Cfg<AnyAxis>>::with_state(p, state) else {
                continue;
            };
            let Some(block) = s.texture_unit_block(ram) else {
                continue;
            };
            made += 1;
            for (k, b) in block.iter().enumerate() {
                let _ = writeln!(out, "400 {:08x} {b:08x} 00000000", block_at as usize + k);
            }
            let mut lods = vec![i32::from(i16::MIN), i32::from(i16::MAX), -4096, -1];
            for level in 0..=(top + 1) {
                lods.extend([
                    level * 256 - 1,
                    level * 256,
                    level * 256 + 1,
                    level * 256 + 128,
                ]);
            }
            lods.extend((0..12).map(|_| (r.next_u32() % 5000) as i32 - 800));
            let (us, vs) = (
                coords(w.trailing_zeros(), &mut r, 6),
                coords(h.trailing_zeros(), &mut r, 6),
            );
            for (i, &lbits) in lods.iter().enumerate() {
                let lbits = lbits.clamp(i32::from(i16::MIN), i32::from(i16::MAX));
                let _ = writeln!(out, "11 {block_addr:08x} {:08x} 00000001", lbits as u32);
                for (j, &u) in us.iter().enumerate().skip(i % 3).step_by(3) {
                    let v = vs[(j * 7 + i) % vs.len()];
                    let (tu, tv) = (TexCoord::from_bits(u), TexCoord::from_bits(v));
                    let (cu, cv) = (coord_i4f28(mu, tu), coord_i4f28(mv, tv));
                    let tri = s.sample_trilinear(tu, tv, lod(lbits));
                    let bil = s.sample_bilinear(tu, tv, lod(lbits));
                    let _ = writeln!(out, "12 {cu:08x} {cv:08x} {tri:08x}");
                    let _ = writeln!(out, "13 {cu:08x} {cv:08x} {bil:08x}");
                }
            }
        }
    }
    // Blocks the unit cannot read: outside the RAM, misaligned, crossing
    // its end.
    for a in [
        0,
        TB_RAM_BASE - 4,
        TB_RAM_BASE + 2,
        TB_RAM_BASE + TB_RAM_BYTES - 72,
    ] {
        let _ = writeln!(out, "11 {a:08x} 00000000 00000000");
    }
    invalid_block_vectors(out, block_at);
    made
}

/// Blocks in the RAM at word `block_at` without the valid bit, which
/// `tex.sel` refuses: a sampler's empty block (zeros) and one whose word 1
/// has every other bit set.
fn invalid_block_vectors(out: &mut String, block_at: u32) {
    for word1 in [0, !BLOCK_VALID] {
        for k in 0..BLOCK_WORDS {
            let b = if k == 1 { word1 } else { 0 };
            let _ = writeln!(out, "400 {:08x} {b:08x} 00000000", block_at as usize + k);
        }
        let addr = TB_RAM_BASE + 4 * block_at;
        let _ = writeln!(out, "11 {addr:08x} 00000100 00000000");
    }
}

/// The whole vector file.
#[must_use]
pub fn vectors() -> String {
    let pls = path_lengths();
    let pbs = entries(64);
    let mut out = String::new();
    for &p in &pls {
        let _ = writeln!(
            out,
            "0 {:08x} {:08x} {:08x}",
            p as u32,
            (p >> 32) as u32,
            log2pl(p)
        );
    }
    // tex.lod: every entry with a spread of path lengths, then random pairs.
    let mut lod_line = |p: u64, pb: Log2Pb| {
        let _ = writeln!(
            out,
            "1 {:08x} {:08x} {:08x}",
            log2pl(p),
            pb.to_bits() as u32,
            lod(p, pb)
        );
    };
    for (k, &p) in pls.iter().enumerate() {
        lod_line(p, pbs[k % pbs.len()]);
        if k % 97 == 0 {
            for &pb in &pbs[..10] {
                lod_line(p, pb);
            }
        }
    }
    filter_vectors(&mut out);
    address_vectors(&mut out);
    let _ = texture_unit_vectors(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vectors against an independent f64 reference: log2 within
    /// `LOG2_MAX_ERROR`, the lod within `LOD_MAX_ERROR` (entries inside the
    /// finite range) and the untextured marker mapped to `0x8000_0000`.
    #[test]
    fn vectors_match_f64() {
        for p in path_lengths() {
            let got = f64::from(log2pl(p).wrapping_sub(0x80) as i32) / 65536.0;
            let want = (p.max(1) as f64).log2() - 32.0;
            assert!(
                (got - want).abs() <= raymip::log2::LOG2_MAX_ERROR,
                "{p:#x}: {got} vs {want}"
            );
            for pb in [Log2Pb::MIN, Log2Pb::MAX, Log2Pb::from_bits(0x12345)] {
                let l = f64::from(lod(p, pb) as i32) / 256.0;
                let want = want - f64::from(pb.to_bits()) / 65536.0;
                assert!(
                    (l - want).abs() <= raymip::lod::LOD_MAX_ERROR,
                    "{p:#x}: {l} vs {want}"
                );
            }
            assert_eq!(lod(p, Log2Pb::UNTEXTURED), 0x8000_0000);
        }
    }

    /// The filter vectors against the exact real-valued filter in f64:
    /// each footprint's rounded value and each blend within
    /// `BILERP_MAX_ERROR_LSB` per channel (the weights are exact here).
    #[test]
    fn filter_vectors_match_f64() {
        use raymip::texture::kernel::accurate::BILERP_MAX_ERROR_LSB;
        let exact = |f: Footprint, c: u32| {
            let ([t00, t10, t01, t11], fx, fy) = f;
            let ch = |t: u32| f64::from((t >> (8 * c)) & 0xFF);
            let (x, y) = (f64::from(fx) / 4096.0, f64::from(fy) / 4096.0);
            (ch(t00) * (1.0 - x) + ch(t10) * x) * (1.0 - y)
                + (ch(t01) * (1.0 - x) + ch(t11) * x) * y
        };
        for (a, b) in footprints() {
            let (ra, wa, wb) = (round_wide(level(a)), level(a), level(b));
            for c in 0..4 {
                let got = f64::from((ra >> (8 * c)) & 0xFF);
                assert!(
                    (got - exact(a, c)).abs() <= BILERP_MAX_ERROR_LSB,
                    "{a:x?} {c}"
                );
                for t in [0u32, 1, 77, 128, 255, 256] {
                    let got = f64::from((blend_wide(wa, wb, t) >> (8 * c)) & 0xFF);
                    let s = f64::from(t) / 256.0;
                    let want = exact(a, c) * (1.0 - s) + exact(b, c) * s;
                    assert!(
                        (got - want).abs() <= BILERP_MAX_ERROR_LSB,
                        "{a:x?} {b:x?} {t} {c}"
                    );
                }
            }
        }
    }

    /// Every pyramid with every window has a descriptor block (none is
    /// left out of the texture-unit vectors), and the file has every
    /// texture-unit instruction.
    #[test]
    fn texture_unit_vectors_cover_every_sampler() {
        let mut out = String::new();
        assert_eq!(
            texture_unit_vectors(&mut out),
            TU_SHAPES.len() * tu_windows(0).len()
        );
        let count = |op: &str| out.lines().filter(|l| l.starts_with(op)).count();
        assert_eq!(count("10 "), 1);
        assert!(count("11 ") > 500 && count("12 ") > 20_000);
        assert_eq!(count("12 "), count("13 "));
        assert_eq!(
            out.lines()
                .filter(|l| l.starts_with("11 ") && l.ends_with(" 00000000"))
                .count(),
            6,
            "the blocks outside the RAM or without the valid bit"
        );
    }

    #[test]
    fn vector_file_has_both_ops_and_every_class() {
        let v = vectors();
        let n0 = v.lines().filter(|l| l.starts_with("0 ")).count();
        let n1 = v.lines().filter(|l| l.starts_with("1 ")).count();
        assert!(n0 > 20_000 && n1 > n0, "{n0} {n1}");
        let count = |op: &str| v.lines().filter(|l| l.starts_with(op)).count();
        let pairs = footprints().len();
        let addr = count("9 ");
        assert_eq!([count("2 "), count("5 ")], [2 * pairs, 6 * pairs]);
        assert!(count("3 ") > 2 * pairs && count("4 ") == count("3 "));
        assert!(count("8 ") >= 256 && addr > 20_000, "{addr}");
        assert_eq!([count("a "), count("b "), count("c ")], [addr; 3]);
        // All-255 footprints round to all-255 (no carry into a neighbour).
        assert!(v.contains("4 ffffffff ffffffff ffffffff"));
        assert!(
            v.contains("2 00001000 00001000 00000000"),
            "weights at 4096"
        );
        // A rounding tie (footprints()): X = 2²³ − 2⁷ rounds up to 1.
        assert!(v.contains("4 00000000 01010101 01010101"));
        assert!(
            v.contains("0 00000000 00000000 ffe00080"),
            "zero reads as 2^-32"
        );
        assert!(
            v.lines()
                .any(|l| l.starts_with("1 ") && l.ends_with(" 80000000"))
        );
    }
}
