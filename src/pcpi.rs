//! The texture co-processor of the PicoRV32 soft core (feature `pcpi`,
//! `riscv32` only): one wrapper per custom instruction of
//! `demo/softcore/pcpi_tex.v` (issue 23).
//!
//! The co-processor sits on PicoRV32's co-processor port (PCPI) and claims
//! two R-type instructions of the `custom-0` opcode (`0001011`,
//! `funct7 = 0`); the RTL's header comment is their specification:
//!
//! | instruction | funct3 | rs1 | rs2 | rd |
//! |---|---|---|---|---|
//! | `tex.log2pl` | 0 | low word of a U32F32 path length | high word | `log2 Pl` in I16F16 bits `+ 0x80` |
//! | `tex.lod` | 1 | a `tex.log2pl` result | `log2 Pb` (I16F16 bits, markers included) | the I8F8 table lod sign-extended, or [`UNTEXTURED`] |
//!
//! With the feature, [`crate::lod::table_lod`] (and its batch) is these two
//! instructions, and [`crate::lod::cone_lod`] takes both of its logarithms
//! from `tex.log2pl`; the results are the software's bit for bit (the
//! Verilator testbench `demo/softcore/tb_pcpi_tex.cpp` checks every output
//! bit against vectors written by the software paths, `scripts/softcore`).
//! The FAST lod paths and the filters are unchanged.
//!
//! # Where the feature applies
//!
//! Only firmware for a PicoRV32 built with the co-processor
//! (`demo/softcore/soc.v` with `ENABLE_TEX = 1`) may enable it: on any other
//! RISC-V core the instructions are illegal and trap. On targets other than
//! `riscv32` the feature has no effect (this module is not compiled and
//! every path is the software one), so `cargo check --all-features` on the
//! host and the Cortex-M4 stays meaningful.
//!
//! # Safety
//!
//! This is the crate's only module besides `ffi` with `unsafe` code: each
//! wrapper is one `asm!` block holding exactly one `.insn` instruction that
//! reads two general-purpose registers and writes one. The co-processor
//! has no state an instruction leaves behind, reads and writes no memory,
//! and changes no other register, CSR or the stack, so the blocks are
//! declared `pure, nomem, nostack` (the compiler may merge or drop calls,
//! as for any pure function). On the hardware it is built for, an
//! instruction always completes (the co-processor answers in at most four
//! cycles, within PicoRV32's 16-cycle PCPI time-out); the remaining hazard, running
//! the firmware on a core without the co-processor, traps (illegal
//! instruction) rather than corrupting state, and is excluded by building
//! the feature only for that SoC.
#![allow(unsafe_code)]

/// The `tex.lod` result for the untextured marker ([`crate::table::Log2Pb::UNTEXTURED`]):
/// `0x8000_0000`, below every sign-extended I8F8 value (`table_lod` returns `None`).
pub const UNTEXTURED: i32 = i32::MIN;

/// `tex.log2pl`: `log2` of the U32F32 raw value `pl` in I16F16 bits plus
/// `0x80` (the I8F8 rounding offset), range `[−32·2¹⁶ + 0x80, 32·2¹⁶ + 0x80]`;
/// `pl = 0` reads as one raw unit (`−32·2¹⁶ + 0x80`). Equal to
/// `log2_u32f32(pl).to_bits() + 0x80` of [`crate::log2`] for every input.
#[inline(always)]
#[must_use]
pub fn log2pl(pl: u64) -> i32 {
    let r: i32;
    // SAFETY: one custom-0 R-type instruction on registers only (see the
    // module docs): no memory, stack or other state is touched.
    unsafe {
        core::arch::asm!(
            ".insn r 0x0b, 0, 0, {rd}, {lo}, {hi}",
            rd = lateout(reg) r,
            lo = in(reg) pl as u32,
            hi = in(reg) (pl >> 32) as u32,
            options(pure, nomem, nostack, preserves_flags),
        );
    }
    r
}

/// `tex.lod`: the table lod of a [`log2pl`] result `l` and a `log2 Pb`
/// entry `pb` (I16F16 bits): `((l − pb) >> 8)` truncated to I8F8 and
/// sign-extended, or [`UNTEXTURED`] when `pb` is the untextured marker.
#[inline(always)]
#[must_use]
pub fn lod(l: i32, pb: i32) -> i32 {
    let r: i32;
    // SAFETY: as for `log2pl`.
    unsafe {
        core::arch::asm!(
            ".insn r 0x0b, 1, 0, {rd}, {l}, {pb}",
            rd = lateout(reg) r,
            l = in(reg) l,
            pb = in(reg) pb,
            options(pure, nomem, nostack, preserves_flags),
        );
    }
    r
}
