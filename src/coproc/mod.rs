//! Co-processors: wrappers of the custom instructions of texture units
//! built beside a soft core.
//!
//! Each is compiled only for the core and feature it belongs to; without
//! one every path is the software one, with the same bits.
//!
//! * `pcpi` (feature `pcpi`, `riscv32` only): the PicoRV32 texture
//!   co-processor on the PCPI port (`demo/softcore/pcpi_tex.v`): the lod
//!   and filter instructions.
//! * `cfu` (feature `cfu`, `riscv32` only): the texture co-processor on
//!   VexRiscv's CFU port (`demo/softcore/cfu_tex.v`): the same lod and
//!   filter instructions (the wrappers of `pcpi`: feature `cfu` turns
//!   `pcpi` on) and the addressing instructions.
//!
//! # The encoding (both ports)
//!
//! R-type instructions of the `custom-0` opcode ([`CUSTOM0`]), the
//! instruction named by `funct7` and `funct3` (the CFU port hands the unit
//! `{funct7, funct3}` as its function id; the PCPI unit decodes the same
//! fields):
//!
//! | instruction | funct7 | funct3 | rs1 | rs2 | rd |
//! |---|---|---|---|---|---|
//! | `tex.log2pl` | 0 | [`LOG2PL`] | low word of a U32F32 path length | high word | `log2 Pl` in I16F16 bits `+ 0x80` |
//! | `tex.lod` | 0 | [`LOD`] | a `tex.log2pl` result | `log2 Pb` (I16F16 bits) | the I8F8 table lod sign-extended, or `0x8000_0000` |
//! | `tex.bw` | 0 | [`BW`] | `fx ∈ [0, 4096]` | `fy ∈ [0, 4096]` | (latches the weights) |
//! | `tex.bt` | 0 | [`BT`] | `t00` | `t10` | (latches the top row) |
//! | `tex.bb` | 0 | [`BB`] | `t01` | `t11` | the footprint filtered and rounded |
//! | `tex.blend` | 0 | [`BLEND`] | `t ∈ [0, 256]` | — | the blend of the last two `tex.bb` values |
//! | `tex.lvl` | [`ADDRESSING`] | [`LVL`] | byte address of the level's texel (0, 0) | [`level_config`] | (latches the level) |
//! | `tex.addr` | [`ADDRESSING`] | [`ADDR`] | [`coord_i4f28`] of `u` | of `v` | address of `t00`; latches the weights and the other taps |
//! | `tex.tap` | [`ADDRESSING`] | [`TAP10`], [`TAP01`], [`TAP11`] | — | — | address of `t10`, `t01`, `t11` |
//! | `tex.ram` | [`TEXTURE_UNIT`] | [`RAM`] | — | — | the RAM the texture unit reads: its base address `\|` log2 of its bytes |
//! | `tex.sel` | [`TEXTURE_UNIT`] | [`SEL`] | address of a [`descriptor_block`] | a lod (I8F8 bits) | 1 when the block is in that RAM, else 0; reads the block's window and levels |
//! | `tex.tri` | [`TEXTURE_UNIT`] | [`TRI`] | [`coord_i4f28`] of `u` | of `v` | the trilinear sample at the selected lod |
//! | `tex.bil` | [`TEXTURE_UNIT`] | [`BIL`] | [`coord_i4f28`] of `u` | of `v` | the bilinear sample of the nearest level |
//!
//! The RTL headers specify each instruction; the Verilator testbenches
//! check every output bit of both units against vectors the software paths
//! write (`scripts/softcore`). The PCPI unit implements `funct7 = 0`
//! (the UP5K it was sized for has no room for the addressing); on it the
//! addressing and texture-unit instructions trap as illegal.
//!
//! # The texture unit's descriptor block
//!
//! The CFU unit reads the texels of a power-of-two pyramid itself (a read
//! port of its own on the SoC's RAM) and filters them: a sampler keeps a
//! block of [`BLOCK_WORDS`] words ([`descriptor_block`]) in that RAM, and
//! a sample is `tex.sel` (the block and the lod) then `tex.tri` or
//! `tex.bil` (the coordinates). Word 0 is the lod bias, word 1 the lod
//! window and the address modes ([`window_word`]), words `2 + l` the
//! levels `l = 0 … 16` ([`level_word`]).

use crate::texture::address::AddressMode;
use crate::texture::storage::level::Pow2Levels;
use crate::units::TexCoord;

#[cfg(all(feature = "cfu", target_arch = "riscv32"))]
pub mod cfu;
#[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
pub mod pcpi;

/// The `custom-0` major opcode (`0001011`) of every instruction.
pub const CUSTOM0: u32 = 0x0b;
/// `funct3` of `tex.log2pl` (`funct7 = 0`).
pub const LOG2PL: u32 = 0;
/// `funct3` of `tex.lod` (`funct7 = 0`).
pub const LOD: u32 = 1;
/// `funct3` of `tex.bw` (`funct7 = 0`).
pub const BW: u32 = 2;
/// `funct3` of `tex.bt` (`funct7 = 0`).
pub const BT: u32 = 3;
/// `funct3` of `tex.bb` (`funct7 = 0`).
pub const BB: u32 = 4;
/// `funct3` of `tex.blend` (`funct7 = 0`).
pub const BLEND: u32 = 5;
/// `funct7` of the addressing instructions.
pub const ADDRESSING: u32 = 1;
/// `funct3` of `tex.lvl` (`funct7 = ADDRESSING`).
pub const LVL: u32 = 0;
/// `funct3` of `tex.addr` (`funct7 = ADDRESSING`).
pub const ADDR: u32 = 1;
/// `funct3` of `tex.tap` for `t10` (`funct7 = ADDRESSING`).
pub const TAP10: u32 = 2;
/// `funct3` of `tex.tap` for `t01` (`funct7 = ADDRESSING`).
pub const TAP01: u32 = 3;
/// `funct3` of `tex.tap` for `t11` (`funct7 = ADDRESSING`).
pub const TAP11: u32 = 4;

/// `funct7` of the texture unit's instructions.
pub const TEXTURE_UNIT: u32 = 2;
/// `funct3` of `tex.ram` (`funct7 = TEXTURE_UNIT`).
pub const RAM: u32 = 0;
/// `funct3` of `tex.sel` (`funct7 = TEXTURE_UNIT`).
pub const SEL: u32 = 1;
/// `funct3` of `tex.tri` (`funct7 = TEXTURE_UNIT`).
pub const TRI: u32 = 2;
/// `funct3` of `tex.bil` (`funct7 = TEXTURE_UNIT`).
pub const BIL: u32 = 3;
/// Words of a texture-unit descriptor block.
pub const BLOCK_WORDS: usize = 19;

/// Whether the addressing instructions implement `mode` (all but the
/// border colour, [`AddressMode::ClampToBorder`]).
#[inline(always)]
#[must_use]
pub const fn addressable(mode: AddressMode) -> bool {
    !matches!(mode, AddressMode::ClampToBorder)
}

/// The `tex.addr` operand of a coordinate on an axis addressed in `mode`:
/// I4F28, the 28 top fractional bits of `c` and in bits 31..28 the integer
/// part the mode's reduction keeps (none for wrap, `⌊c⌋ mod 2` for
/// mirror, `⌊c⌋` clamped to `[−4, 3]` for the clamping modes, as the
/// sampler's `AddressMode::taps` reduces it). The 4 fractional bits
/// dropped change no tap or 12-bit weight of a side up to 2¹⁵ texels:
/// `frac·2^k` moves by less than `2^(k+4−32) ≤ 2⁻¹³` texel, and the weight
/// `⌊frac(x + 2⁻¹³)·2¹²⌋` depends on `x` only down to that bit (tested for
/// every mode, side and class of coordinate).
#[inline(always)]
#[must_use]
pub fn coord_i4f28(mode: AddressMode, c: TexCoord) -> u32 {
    let b = c.to_bits();
    let hi = (b >> 32) as i32;
    let int = match mode {
        AddressMode::Wrap => 0,
        AddressMode::Mirror => hi & 1,
        _ => hi.clamp(-4, 3),
    };
    ((b as u32) >> 4) | ((int as u32) << 28)
}

/// The `tex.lvl` operand of a level of `2^kx × 2^ky` texels (`kx, ky ≤
/// 15`; larger values are cut to 4 bits) addressed in `mu` on `u` and `mv`
/// on `v`: `kx | ky << 4 | mu << 8 | mv << 10` (the modes as
/// [`AddressMode`]'s numbers; border is not addressable, see
/// [`addressable`]).
#[inline(always)]
#[must_use]
pub const fn level_config(kx: u32, ky: u32, mu: AddressMode, mv: AddressMode) -> u32 {
    (kx & 15) | (ky & 15) << 4 | (mu as u32 & 3) << 8 | (mv as u32 & 3) << 10
}

/// Word 1 of a descriptor block: the lod window `[lo, hi]` (I8F8 bits,
/// `≤ 3840`; larger values are cut to 12 bits) and the address modes:
/// `lo | hi << 12 | mu << 24 | mv << 26`.
#[inline]
#[must_use]
pub const fn window_word(lo: u32, hi: u32, mu: AddressMode, mv: AddressMode) -> u32 {
    (lo & 0xFFF) | (hi & 0xFFF) << 12 | (mu as u32 & 3) << 24 | (mv as u32 & 3) << 26
}

/// Word `2 + l` of a descriptor block: a level of `2^kx × 2^ky` texels
/// (`kx, ky ≤ 15`) whose texel (0, 0) is word `offset < 2²⁴` of the
/// unit's RAM: `offset | kx << 24 | ky << 28`.
#[inline]
#[must_use]
pub const fn level_word(offset: u32, kx: u32, ky: u32) -> u32 {
    (offset & 0xFF_FFFF) | (kx & 15) << 24 | (ky & 15) << 28
}

/// The descriptor block of a sampler over the power-of-two levels
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
    block[1] = window_word(lo as u32, hi as u32, mu, mv);
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
                    let back =
                        (i64::from(q as i32 >> 28) << 32) | i64::from((q & 0x0FFF_FFFF) << 4);
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
}
