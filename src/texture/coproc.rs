//! The texture half's side of the co-processors: instruction operands and
//! the texture unit's descriptor block, made from address modes and
//! power-of-two level views.
//!
//! The instructions, their encoding and the descriptor block's layout are
//! in [`crate::coproc`]; these functions are plain integer code, built on
//! every target (the harness writes the RTL's test vectors with them).

use crate::coproc::{BLOCK_VALID, BLOCK_WORDS, level_word};
use crate::texture::address::AddressMode;
use crate::texture::storage::level::Pow2Levels;
use crate::units::TexCoord;

/// Whether the addressing instructions implement `mode` (all but the
/// border colour, [`AddressMode::ClampToBorder`]).
#[inline(always)]
#[must_use]
pub const fn addressable(mode: AddressMode) -> bool {
    !matches!(mode, AddressMode::ClampToBorder)
}

/// The `tex.addr` operand of a coordinate on an axis addressed in `mode`.
/// Wrap: the 32 fractional bits of `c` (wrap keeps no integer part; the
/// unit uses the top 28). The other modes: I4F28, the 28 top fractional
/// bits of `c` and in bits 31..28 the integer part the mode's reduction
/// keeps (`⌊c⌋ mod 2` for mirror, `⌊c⌋` clamped to `[−4, 3]` for the
/// clamping modes, as the sampler's `AddressMode::taps` reduces it). The 4
/// fractional bits either drops change no tap or 12-bit weight of a side
/// up to 2¹⁵ texels: `frac·2^k` moves by less than `2^(k+4−32) ≤ 2⁻¹³`
/// texel, and the weight `⌊frac(x + 2⁻¹³)·2¹²⌋` depends on `x` only down
/// to that bit (tested for every mode, side and class of coordinate).
#[inline(always)]
#[must_use]
pub fn coord_i4f28(mode: AddressMode, c: TexCoord) -> u32 {
    let b = c.to_bits();
    let hi = (b >> 32) as i32;
    let int = match mode {
        // The fraction as it is: no shift on the wrap path.
        AddressMode::Wrap => return b as u32,
        AddressMode::Mirror => hi & 1,
        _ => hi.clamp(-4, 3),
    };
    // The fields share no bit: their sum is the packed word.
    ((b as u32) >> 4) + ((int as u32) << 28)
}

/// The `tex.lvl` operand of a level of `2^kx × 2^ky` texels (`kx, ky ≤
/// 15`; larger values are cut to 4 bits) addressed in `mu` on `u` and `mv`
/// on `v`: `kx | ky << 4 | mu << 8 | mv << 10` (the modes as
/// [`AddressMode`]'s numbers; border is not addressable, see
/// [`addressable`]).
#[inline(always)]
#[must_use]
pub const fn level_config(kx: u32, ky: u32, mu: AddressMode, mv: AddressMode) -> u32 {
    // The fields share no bit: their sum is the packed word.
    (kx & 15) + ((ky & 15) << 4) + ((mu as u32 & 3) << 8) + ((mv as u32 & 3) << 10)
}

/// Word 1 of a descriptor block: the lod window `[lo, hi]` (I8F8 bits,
/// `≤ 3840`; larger values are cut to 12 bits) and the address modes:
/// `lo | hi << 12 | mu << 24 | mv << 26`.
#[inline]
#[must_use]
pub const fn window_word(lo: u32, hi: u32, mu: AddressMode, mv: AddressMode) -> u32 {
    // The fields share no bit: their sum is the packed word.
    (lo & 0xFFF) + ((hi & 0xFFF) << 12) + ((mu as u32 & 3) << 24) + ((mv as u32 & 3) << 26)
}

/// The descriptor block (valid: word 1 is the [`window_word`] with
/// [`BLOCK_VALID`]) of a sampler over the power-of-two levels
/// `levels` (every level index `0 ..= 16`) with lod window `bias` and
/// `[lo, hi]` (the sampler's I8F8 bits: `lod + bias` clamped to
/// `0 ≤ lo ≤ hi ≤ 3840`) and address modes `mu`, `mv`, for a texture unit
/// reading the `ram_bytes` bytes at address `ram_base`. `None` when a mode
/// is not addressable ([`addressable`]), the window is out of its range,
/// or a level's texels are not all in that RAM (the sampler then samples
/// in software).
#[must_use]
pub fn descriptor_block(
    levels: &Pow2Levels<'_>,
    bias: i32,
    (lo, hi): (i32, i32),
    (mu, mv): (AddressMode, AddressMode),
    (ram_base, ram_bytes): (usize, usize),
) -> Option<[u32; BLOCK_WORDS]> {
    let max = 15 << 8;
    if !(addressable(mu) && addressable(mv) && 0 <= lo && lo <= hi && hi <= max) {
        return None;
    }
    // The unit adds the bias to an I8F8 lod in 18 bits.
    i16::try_from(bias).ok()?;
    let mut block = [0; BLOCK_WORDS];
    block[0] = bias as u32;
    // `window_word` fills bits 0–27 and the valid bit is bit 28.
    block[1] = window_word(lo as u32, hi as u32, mu, mv) + BLOCK_VALID;
    for (l, word) in block[2..].iter_mut().enumerate() {
        let view = levels.level(l);
        let (w, h) = (view.width(), view.height());
        // Exposed: the texture unit reads these texels (`cfu`'s safety).
        let start = view
            .base()
            .as_ptr()
            .expose_provenance()
            .checked_sub(ram_base)?;
        let end = start.checked_add(4 * w as usize * h as usize)?;
        if start % 4 != 0 || end > ram_bytes || start / 4 >= 1 << 24 {
            return None;
        }
        *word = level_word((start / 4) as u32, w.trailing_zeros(), h.trailing_zeros());
    }
    Some(block)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::texture::storage::level::LevelView;
    use std::vec;

    /// The I4F28 operand, read back as a coordinate, selects the same taps
    /// and weight as the coordinate itself, for every addressable mode,
    /// every power-of-two side up to 2¹⁵ and coordinates at and around
    /// texel edges and centres, the seams, far outside `[0, 1)` and random.
    #[test]
    fn i4f28_keeps_every_tap_and_weight() {
        let mut r = crate::rng::Rng::new(0x14f2_8c00);
        for mode in [
            AddressMode::Wrap,
            AddressMode::Mirror,
            AddressMode::ClampToEdge,
            AddressMode::MirrorOnce,
        ] {
            for k in 0..=15u32 {
                let one = 1i64 << 32;
                let texel = one >> k;
                let mut cs = vec![i64::MIN, i64::MAX, -5 * one, 4 * one + 7, -1, 0, 1];
                for base in [0, one / 2, one, -one / 2, 3 * one / 2, 2 * one] {
                    for d in [-texel, -texel / 2, 0, texel / 2, texel] {
                        for e in [-17, -16, -1, 0, 1, 15, 16] {
                            cs.push(base + d + e);
                        }
                    }
                }
                for _ in 0..2000 {
                    let hi = i64::from(r.next_u32() as i32 >> (r.next_u32() % 32));
                    cs.push((hi << 32) | i64::from(r.next_u32()));
                }
                for c in cs {
                    let q = coord_i4f28(mode, TexCoord::from_bits(c));
                    // What the unit reads: the top 28 fractional bits, and
                    // for the other modes than wrap the integer part.
                    let back = if mode == AddressMode::Wrap {
                        i64::from(q & !15)
                    } else {
                        (i64::from(q as i32 >> 28) << 32) | i64::from((q & 0x0FFF_FFFF) << 4)
                    };
                    let size = 1 << k;
                    assert_eq!(
                        mode.linear(TexCoord::from_bits(back), size),
                        mode.linear(TexCoord::from_bits(c), size),
                        "{mode:?} k {k} c {c:#x}"
                    );
                }
            }
        }
    }

    #[test]
    fn level_config_packs_fields() {
        let c = level_config(15, 3, AddressMode::MirrorOnce, AddressMode::Mirror);
        assert_eq!(c, 15 | 3 << 4 | 3 << 8 | 1 << 10);
        assert!(!addressable(AddressMode::ClampToBorder));
        assert!(addressable(AddressMode::MirrorOnce));
    }

    /// `tex.lvl`'s operand as documented: `kx | ky << 4 | mu << 8 | mv <<
    /// 10`, sides cut to 4 bits (the expected words written out by hand
    /// from that layout).
    #[test]
    fn level_config_words_follow_the_layout() {
        use AddressMode::{ClampToEdge, Mirror, MirrorOnce, Wrap};
        // kx 5, ky 9, u clamped to the edge (2), v wrapped (0).
        assert_eq!(level_config(5, 9, ClampToEdge, Wrap), 0x0000_0295);
        // kx 0x1A and ky 0x27 cut to 0xA and 0x7; u wrapped, v mirrored.
        assert_eq!(level_config(0x1A, 0x27, Wrap, Mirror), 0x0000_047A);
        assert_eq!(level_config(0, 0, Wrap, Wrap), 0);
        assert_eq!(level_config(15, 15, MirrorOnce, MirrorOnce), 0x0000_0FFF);
    }

    /// Word 1 as documented: `lo | hi << 12 | mu << 24 | mv << 26`, the
    /// window's bounds cut to 12 bits (the expected words written out by
    /// hand from that layout).
    #[test]
    fn window_words_follow_the_layout() {
        use AddressMode::{ClampToEdge, Mirror, MirrorOnce, Wrap};
        assert_eq!(window_word(0x123, 0xABC, Mirror, MirrorOnce), 0x0DAB_C123);
        // Bounds above 12 bits keep their low 12.
        assert_eq!(
            window_word(0x1_F123, 0x7_0ABC, Mirror, MirrorOnce),
            0x0DAB_C123
        );
        assert_eq!(window_word(0, 3840, Wrap, Wrap), 0x00F0_0000);
        assert_eq!(window_word(3840, 3840, ClampToEdge, Wrap), 0x02F0_0F00);
        assert_eq!(window_word(1, 0, Wrap, ClampToEdge), 0x0800_0001);
        assert_eq!(window_word(0, 0, Wrap, Wrap), 0);
    }

    /// The wrap operand is the coordinate's fraction, all 32 bits, however
    /// far outside `[0, 1)` the coordinate is; the clamping modes keep
    /// `⌊c⌋` clamped to `[−4, 3]` above the top 28 fractional bits.
    #[test]
    fn i4f28_integer_part_per_mode() {
        let one = 1i64 << 32;
        for (c, frac) in [
            (2 * one + one / 2 + 5, 0x8000_0005),
            (-3 * one + one / 4, 0x4000_0000),
            (7 * one + 15, 15),
        ] {
            let q = coord_i4f28(AddressMode::Wrap, TexCoord::from_bits(c));
            assert_eq!(q, frac, "{c:#x}");
        }
        // 2.5 clamped to the edge: integer part 2, fraction 0.5.
        let q = coord_i4f28(
            AddressMode::ClampToEdge,
            TexCoord::from_bits(2 * one + one / 2),
        );
        assert_eq!(q, 0x2800_0000);
        // ⌊−5.25⌋ = −6 clamped to −4 (0xC in bits 31..28), fraction 0.75;
        // mirror keeps −6 mod 2 = 0.
        let c = TexCoord::from_bits(-5 * one - one / 4);
        assert_eq!(coord_i4f28(AddressMode::MirrorOnce, c), 0xCC00_0000);
        assert_eq!(coord_i4f28(AddressMode::Mirror, c), 0x0C00_0000);
    }

    /// One `w × h` level (every level index reads it) over `texels`.
    fn one_level(texels: &[u32], w: u32, h: u32) -> Pow2Levels<'_> {
        Pow2Levels::from_fn(|_| LevelView::new(texels, w, h)).unwrap()
    }

    /// `None` when either address mode is the border colour or the window
    /// is out of `0 ≤ lo ≤ hi ≤ 3840`, each alone with the rest valid;
    /// a block at the window's limits.
    #[test]
    fn descriptor_block_rejects_each_invalid_field() {
        use AddressMode::{ClampToBorder, Wrap};
        let texels = vec![7u32; 32];
        let levels = one_level(&texels, 8, 4);
        let ram = (texels.as_ptr().expose_provenance(), 4 * texels.len());
        let block = |window, modes| descriptor_block(&levels, 0, window, modes, ram);
        assert!(block((0, 3840), (Wrap, Wrap)).is_some());
        assert!(block((3840, 3840), (Wrap, Wrap)).is_some());
        assert_eq!(block((0, 3840), (Wrap, ClampToBorder)), None);
        assert_eq!(block((0, 3840), (ClampToBorder, Wrap)), None);
        assert_eq!(block((-1, 3840), (Wrap, Wrap)), None);
        assert_eq!(block((257, 256), (Wrap, Wrap)), None);
        assert_eq!(block((0, 3841), (Wrap, Wrap)), None);
    }

    /// A level's texels must end inside the RAM: an 8×4 level (128 bytes)
    /// fits 128 bytes and not 124.
    #[test]
    fn descriptor_block_needs_the_whole_level_in_the_ram() {
        use AddressMode::Wrap;
        let texels = vec![7u32; 32];
        let levels = one_level(&texels, 8, 4);
        let base = texels.as_ptr().expose_provenance();
        let block = |bytes| descriptor_block(&levels, 0, (0, 0), (Wrap, Wrap), (base, bytes));
        // Bias 0; window [0, 0] both wrapped, valid: bit 28; every level
        // at word 0 with kx 3, ky 2: `0 | 3 << 24 | 2 << 28`.
        let mut want = [0x2300_0000; BLOCK_WORDS];
        want[0] = 0;
        want[1] = 0x1000_0000;
        assert_eq!(block(128), Some(want));
        assert_eq!(block(124), None);
    }

    /// A level's word offset must be below 2²⁴ (the 24 bits of its field):
    /// a 1×1 level at byte `2²⁶ − 4` of the RAM is word `0xFF_FFFF`, at
    /// byte `2²⁶` it has no descriptor.
    #[test]
    fn descriptor_block_offsets_fit_24_bits() {
        use AddressMode::Wrap;
        let texels = vec![7u32; 1];
        let levels = one_level(&texels, 1, 1);
        let at = texels.as_ptr().expose_provenance();
        assert!(at >= 1 << 26);
        let block = |start: usize| {
            descriptor_block(&levels, 0, (0, 0), (Wrap, Wrap), (at - start, 1 << 27))
        };
        let b = block((1 << 26) - 4).unwrap();
        assert!(b[2..].iter().all(|&w| w == 0x00FF_FFFF));
        assert_eq!(block(1 << 26), None);
    }

    /// A sampler's block ([`Sampler::texture_unit_block`](crate::texture::Sampler::texture_unit_block))
    /// is its power-of-two source's descriptor block for the ACCURATE
    /// linear kernel; none for a kernel that keeps no weights in the
    /// co-processor, or texels outside the unit's RAM.
    #[test]
    fn sampler_block_is_its_sources_descriptor_block() {
        use crate::texture::address::Wrap;
        use crate::texture::kernel::{Fast, Linear};
        use crate::texture::storage::mip::{Geometry, Pyramid, pyramid_len};
        use crate::texture::storage::pow2::Pow2Pyramid;
        use crate::texture::{Cfg, Sampler};
        let texels: vec::Vec<u32> = (0..pyramid_len(8, 4, 4) as u32).collect();
        let p = Pyramid::new(Geometry::new(8, 4, 4).unwrap(), &texels).unwrap();
        let p = Pow2Pyramid::new(p).unwrap();
        let ram = (texels.as_ptr().expose_provenance(), 4 * texels.len());
        let block = Sampler::wrap(p).texture_unit_block(ram).unwrap();
        // Level 0 (8×4) at word 0 of the RAM, level 1 (4×2) after its 32
        // texels; both axes wrap.
        assert_eq!(block[2], level_word(0, 3, 2));
        assert_eq!(block[3], level_word(32, 2, 1));
        // Valid (bit 28), both axes wrapped (mode 0 in bits 24..27).
        assert_eq!(block[1] >> 24, 0x10);
        let fast = Sampler::<_, Cfg<Wrap, Wrap, Linear, Fast>>::new(p);
        assert_eq!(fast.texture_unit_block(ram), None);
        assert_eq!(Sampler::wrap(p).texture_unit_block((ram.0, 64)), None);
    }
}
