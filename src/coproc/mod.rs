//! Co-processors: wrappers of the custom instructions of texture units
//! built beside a soft core.
//!
//! The wrappers take and return raw words; the operands made from the
//! texture half's types (address modes, level views, the texture unit's
//! descriptor block) are in [`crate::texture::coproc`], above.
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
//! | `tex.lvl` | [`ADDRESSING`] | [`LVL`] | byte address of the level's texel (0, 0) | [`level_config`](crate::texture::coproc::level_config) | (latches the level) |
//! | `tex.addr` | [`ADDRESSING`] | [`ADDR`] | [`coord_i4f28`](crate::texture::coproc::coord_i4f28) of `u` | of `v` | address of `t00`; latches the weights and the other taps |
//! | `tex.tap` | [`ADDRESSING`] | [`TAP10`], [`TAP01`], [`TAP11`] | — | — | address of `t10`, `t01`, `t11` |
//! | `tex.ram` | [`TEXTURE_UNIT`] | [`RAM`] | — | — | the RAM the texture unit reads: its base address `\|` log2 of its bytes |
//! | `tex.sel` | [`TEXTURE_UNIT`] | [`SEL`] | address of a [`descriptor_block`](crate::texture::coproc::descriptor_block) | a lod (I8F8 bits) | 1 when the block is in that RAM and valid ([`BLOCK_VALID`]), else 0; reads the block's window and levels |
//! | `tex.tri` | [`TEXTURE_UNIT`] | [`TRI`] | [`coord_i4f28`](crate::texture::coproc::coord_i4f28) of `u` | of `v` | the trilinear sample at the selected lod |
//! | `tex.bil` | [`TEXTURE_UNIT`] | [`BIL`] | [`coord_i4f28`](crate::texture::coproc::coord_i4f28) of `u` | of `v` | the bilinear sample of the nearest level |
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
//! block of [`BLOCK_WORDS`] words ([`descriptor_block`](crate::texture::coproc::descriptor_block)) in that RAM, and
//! a sample is `tex.sel` (the block and the lod) then `tex.tri` or
//! `tex.bil` (the coordinates). Word 0 is the lod bias, word 1 the lod
//! window and the address modes ([`window_word`](crate::texture::coproc::window_word)) and the valid bit
//! [`BLOCK_VALID`], words `2 + l` the levels `l = 0 … 16` ([`level_word`]).
//! A block without the valid bit (all zeros: a sampler without one) is
//! refused by `tex.sel` like a block outside the RAM, so the firmware
//! needs no flag of its own beside the block.

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
/// Bit 28 of word 1 of a descriptor block: set in every block
/// [`descriptor_block`](crate::texture::coproc::descriptor_block) makes;
/// `tex.sel` answers 0 (and selects nothing) for a block without it.
pub const BLOCK_VALID: u32 = 1 << 28;

/// Word `2 + l` of a descriptor block: a level of `2^kx × 2^ky` texels
/// (`kx, ky ≤ 15`) whose texel (0, 0) is word `offset < 2²⁴` of the
/// unit's RAM: `offset | kx << 24 | ky << 28`.
#[inline]
#[must_use]
pub const fn level_word(offset: u32, kx: u32, ky: u32) -> u32 {
    (offset & 0xFF_FFFF) | (kx & 15) << 24 | (ky & 15) << 28
}
