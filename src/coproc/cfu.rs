//! The texture co-processor on VexRiscv's CFU port (feature `cfu`,
//! `riscv32` only): `demo/softcore/cfu_tex.v`, whose header specifies the
//! instructions.
//!
//! The CFU runs the same instruction words as the PicoRV32 unit (the
//! encoding in [`super`]): with feature `cfu` (which turns on `pcpi`) the
//! table and cone lod and the ACCURATE linear filter use the wrappers of
//! [`super::pcpi`] exactly as on PicoRV32. This module adds what only the
//! CFU unit has:
//!
//! * [`enable`]: VexRiscv's CFU plugin treats custom instructions as
//!   illegal until bit 31 of CSR `0xBC0` is set; call it once before the
//!   first raymip call (the demo firmware does in riscv-rt's pre-init).
//! * the addressing instructions `tex.lvl`, `tex.addr`, `tex.tap`
//!   (`funct7 = 1`): the taps and weights of a power-of-two level in
//!   memory from `(u, v)`, the level's size and the address modes (wrap,
//!   mirror, clamp to edge, mirror once), as texel addresses. The sampler's
//!   in-memory path of the ACCURATE linear kernel takes its footprint from
//!   `texture::storage::level::cfu_footprint` (where the texel reads and
//!   their safety argument are): the firmware only loads the four texels, and the
//!   weights stay in the co-processor for `tex.bt`/`tex.bb`.
//! * the texture unit `tex.ram`, `tex.sel`, `tex.tri`, `tex.bil`
//!   (`funct7 = 2`): the co-processor reads the texels itself through a
//!   read port of its own on the SoC's RAM and filters them. A sampler
//!   whose pyramid and lod window the unit can take keeps its
//!   [`TextureUnit`] (the descriptor block the unit reads,
//!   [`descriptor_block`](crate::texture::coproc::descriptor_block)); a sample is then [`TextureUnit::select`]
//!   and [`trilinear`] or [`bilinear`], and the in-memory path above is
//!   what samplers whose texels lie outside that RAM take.
//!
//! # Safety
//!
//! The instruction wrappers are as in [`super::pcpi`]: one `asm!` block,
//! one `.insn`, registers only (`nomem, nostack`); the addressing
//! instructions keep state in the co-processor (the level, the taps, the
//! weights), so none is `pure`: the compiler keeps each, in program order.
//! [`enable`] writes one CSR of the CFU plugin and nothing else.
//!
//! The texture unit's instructions read memory, but not through the CPU:
//! the co-processor's read port returns words of the RAM to the unit, and
//! the instructions return plain words (any `u32` is a valid [`Texel`](crate::texture::storage::mip::Texel) or
//! flag); nothing is written. `tex.sel` reads the descriptor block at the
//! address it is given, a [`TextureUnit`]'s own field, borrowed for the
//! call; `tex.tri`/`tex.bil` read texels at `base + 4·(y·2^kx + x)` with
//! `base`, `kx`, `ky` a level's from the block, which
//! [`descriptor_block`](crate::texture::coproc::descriptor_block) made from a [`LevelView`](crate::texture::storage::level::LevelView)'s first texel and
//! sides (exposing that memory's provenance), and `x < 2^kx`, `y < 2^ky` by
//! construction of the RTL (as for `tex.addr` above): texels of a view of
//! the sampler's source, borrowed by the sampler for as long as it lives.
//! So each block is `readonly` (it reads only memory Rust code may read
//! then, and the compiler completes every earlier store first) and not
//! `pure` (it depends on the unit's state: the blocks stay in program
//! order). The SoC's part of the argument: the unit reads the RAM after
//! the CPU's pending writes (`cfu_tex.v`, `mem_hold`), so it reads the
//! values the program stored.
#![allow(unsafe_code)]

use super::{BIL, BLOCK_WORDS, RAM, SEL, TEXTURE_UNIT, TRI};
use crate::units::Lod;

/// Enables VexRiscv's CFU plugin (bit 31 of CSR `0xBC0`): until then the
/// custom instructions are illegal. Idempotent.
#[inline]
pub fn enable() {
    // SAFETY: sets one bit of the CFU plugin's CSR `0xBC0` (`csrs`); no
    // memory, stack or other register is touched.
    unsafe {
        core::arch::asm!(
            "csrs 0xbc0, {m}",
            m = in(reg) 1u32 << 31,
            options(nomem, nostack, preserves_flags),
        );
    }
}

/// `tex.lvl`: the level `tex.addr` addresses next: its texel (0, 0) at byte
/// address `base`, its shape and address modes in `config`
/// ([`super::level_config`]).
#[inline(always)]
pub fn level(base: u32, config: u32) {
    // SAFETY: one custom-0 R-type instruction on registers only (module
    // docs), writing no register; its effect is co-processor state, so the
    // block is not `pure` and stays in program order.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, {f7}, x0, {a}, {b}",
            op = const super::CUSTOM0,
            f3 = const super::LVL,
            f7 = const super::ADDRESSING,
            a = in(reg) base,
            b = in(reg) config,
            options(nomem, nostack, preserves_flags),
        );
    }
}

/// `tex.addr`: the bilinear taps of `(u, v)` ([`super::coord_i4f28`]
/// operands) on the level of the last [`level`]: returns the byte address
/// of `t00` and latches the weights (as `tex.bw`) and the other three
/// addresses ([`tap`]).
#[inline(always)]
#[must_use]
pub fn addr(u: u32, v: u32) -> u32 {
    let r: u32;
    // SAFETY: as for `level`; it writes `r`.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, {f7}, {rd}, {a}, {b}",
            op = const super::CUSTOM0,
            f3 = const super::ADDR,
            f7 = const super::ADDRESSING,
            rd = lateout(reg) r,
            a = in(reg) u,
            b = in(reg) v,
            options(nomem, nostack, preserves_flags),
        );
    }
    r
}

/// `tex.tap`: the byte address of tap `F3` ([`TAP10`], [`TAP01`],
/// [`TAP11`]) of the last [`addr`].
#[inline(always)]
#[must_use]
pub fn tap<const F3: u32>() -> u32 {
    let r: u32;
    // SAFETY: as for `level`; it reads co-processor state and writes `r`.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, {f7}, {rd}, x0, x0",
            op = const super::CUSTOM0,
            f3 = const F3,
            f7 = const super::ADDRESSING,
            rd = lateout(reg) r,
            options(nomem, nostack, preserves_flags),
        );
    }
    r
}

/// `tex.ram`: the RAM the texture unit reads, `(base address, bytes)`.
#[inline]
#[must_use]
pub fn ram() -> (usize, usize) {
    let r: u32;
    // SAFETY: one custom-0 R-type instruction on registers only (module
    // docs) that writes `r`; it reads no memory.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, {f7}, {rd}, x0, x0",
            op = const super::CUSTOM0,
            f3 = const RAM,
            f7 = const TEXTURE_UNIT,
            rd = lateout(reg) r,
            options(nomem, nostack, preserves_flags),
        );
    }
    ((r & !31) as usize, 1usize << (r & 31))
}

/// A sampler's descriptor block for the texture unit, or none: a block of
/// zeros, without [`BLOCK_VALID`](super::BLOCK_VALID), which `tex.sel`
/// refuses (then [`select`](Self::select) is always `false` and the
/// sampler samples in software or through the addressing instructions).
/// The unit checks the valid bit while it reads the block, so a sample
/// loads no flag of the sampler's.
#[derive(Clone, Copy, Debug)]
pub struct TextureUnit {
    block: [u32; BLOCK_WORDS],
}

impl TextureUnit {
    /// A unit for `block` ([`descriptor_block`](crate::texture::coproc::descriptor_block) for the RAM of
    /// [`ram`]), or none.
    #[must_use]
    pub const fn new(block: Option<[u32; BLOCK_WORDS]>) -> Self {
        match block {
            Some(block) => Self { block },
            None => Self {
                block: [0; BLOCK_WORDS],
            },
        }
    }

    /// `tex.sel`: selects this block and `lod` (I8F8, through the block's
    /// window) for the next [`trilinear`] or [`bilinear`]; `false` (and
    /// nothing selected) when there is no block (no valid bit) or the
    /// unit's RAM does not hold this one (the sampler is elsewhere).
    #[inline(always)]
    #[must_use]
    pub fn select(&self, lod: Lod) -> bool {
        let r: u32;
        // SAFETY: one custom-0 R-type instruction (module docs): the unit
        // reads the block `self.block` (borrowed for this call) and writes
        // `r`; `readonly`, not `pure`.
        unsafe {
            core::arch::asm!(
                ".insn r {op}, {f3}, {f7}, {rd}, {a}, {b}",
                op = const super::CUSTOM0,
                f3 = const SEL,
                f7 = const TEXTURE_UNIT,
                rd = lateout(reg) r,
                a = in(reg) self.block.as_ptr(),
                b = in(reg) i32::from(lod.to_bits()),
                options(readonly, nostack, preserves_flags),
            );
        }
        r != 0
    }
}

/// `tex.tri`: the trilinear sample at `(u, v)` ([`super::coord_i4f28`]
/// operands) of the block and lod of the last successful
/// [`TextureUnit::select`].
#[inline(always)]
#[must_use]
pub fn trilinear(u: u32, v: u32) -> u32 {
    sample::<TRI>(u, v)
}

/// `tex.bil`: the bilinear sample of the nearest level, as [`trilinear`].
#[inline(always)]
#[must_use]
pub fn bilinear(u: u32, v: u32) -> u32 {
    sample::<BIL>(u, v)
}

/// `tex.tri` (`F3 = TRI`) or `tex.bil` (`BIL`).
#[inline(always)]
fn sample<const F3: u32>(u: u32, v: u32) -> u32 {
    let r: u32;
    // SAFETY: one custom-0 R-type instruction (module docs): the unit reads
    // texels of the selected block's levels (views the sampler borrows)
    // and writes `r`; `readonly`, not `pure`.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, {f7}, {rd}, {a}, {b}",
            op = const super::CUSTOM0,
            f3 = const F3,
            f7 = const TEXTURE_UNIT,
            rd = lateout(reg) r,
            a = in(reg) u,
            b = in(reg) v,
            options(readonly, nostack, preserves_flags),
        );
    }
    r
}
