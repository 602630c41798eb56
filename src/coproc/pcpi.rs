//! The texture co-processor of the PicoRV32 soft core (feature `pcpi`,
//! `riscv32` only): one wrapper per custom instruction of
//! `demo/softcore/pcpi_tex.v`.
//!
//! The co-processor sits on PicoRV32's co-processor port (PCPI) and claims
//! six R-type instructions of the `custom-0` opcode (`0001011`,
//! `funct7 = 0`; the encoding shared with the CFU unit is in [`super`]);
//! the RTL's header comment is their specification:
//!
//! | instruction | funct3 | rs1 | rs2 | rd |
//! |---|---|---|---|---|
//! | `tex.log2pl` | 0 | low word of a U32F32 path length | high word | `log2 Pl` in I16F16 bits `+ 0x80` |
//! | `tex.lod` | 1 | a `tex.log2pl` result | `log2 Pb` (I16F16 bits, markers included) | the I8F8 table lod sign-extended, or [`UNTEXTURED`] |
//! | `tex.bw` | 2 | `fx ∈ [0, 4096]` | `fy ∈ [0, 4096]` | (none: latches the footprint's weights) |
//! | `tex.bt` | 3 | `t00` | `t10` | (none: latches the top row's four channels) |
//! | `tex.bb` | 4 | `t01` | `t11` | the footprint filtered and rounded (`bilerp_rounded`); its 8.16 value kept |
//! | `tex.blend` | 5 | `t ∈ [0, 256]` | — | the blend of the last two `tex.bb` values (`blend_wide_in_range`) |
//!
//! With the feature, [`crate::lod::table_lod`] (and its batch) is these two
//! instructions, and [`crate::lod::cone_lod`] takes both of its logarithms
//! from `tex.log2pl`; the results are the software's bit for bit (the
//! Verilator testbench `demo/softcore/tb_pcpi_tex.cpp` checks every output
//! bit against vectors written by the software paths, `scripts/softcore`).
//! The ACCURATE linear kernel's bilinear and trilinear filtering
//! ([`crate::texture::kernel::Kernel::bilinear_texel`] and the trilinear
//! levels [`crate::texture::kernel::Kernel::level`] /
//! [`crate::texture::kernel::Kernel::finish_blend`] of `(Linear, Accurate)`)
//! is [`bw`], [`bt`], [`bb`] per level and [`blend`];
//! its wide values (aniso probes) and the FAST, nearest and sRGB kernels
//! stay software.
//!
//! # Where the feature applies
//!
//! Only firmware for a PicoRV32 built with the co-processor
//! (`demo/softcore/soc.v` with `ENABLE_TEX = 1`) or for a VexRiscv with the
//! CFU unit (feature `cfu`, which turns this one on: the same instruction
//! words) may enable it: on any other RISC-V core the instructions are
//! illegal and trap. On targets other than
//! `riscv32` the feature has no effect (this module is not compiled and
//! every path is the software one), so `cargo check --all-features` on the
//! host and the Cortex-M4 stays meaningful.
//!
//! # Safety
//!
//! The crate's other `unsafe` code is the C ABI (`ffi`), the texel reads
//! of the level views (`texture::storage::pow2`) and the CFU wrappers
//! (`coproc::cfu`; the list is at the top of `lib.rs`). Here each
//! wrapper is one `asm!` block holding exactly one `.insn` instruction that
//! reads general-purpose registers and writes at most one. No instruction
//! reads or writes memory or changes any other register, CSR or the
//! stack (`nomem, nostack`). `tex.log2pl` and `tex.lod` have no state an
//! instruction leaves behind, so their blocks are also `pure` (the
//! compiler may merge or drop calls, as for any pure function). The filter
//! instructions keep state in the co-processor (the weights, the top row,
//! the last two levels' values), so their blocks are not `pure`: the
//! compiler keeps every one, in program order, even when its result is
//! unused; their only effect is that co-processor state, which nothing
//! but these wrappers reads. A sequence [`bw`] … [`blend`] runs with
//! no other filter instruction between (each sampler call issues its
//! sequence whole; the firmware has no interrupt handler that filters) —
//! were one interleaved, the results would be wrong texels, never
//! undefined behaviour. On the hardware it is built for, an instruction
//! always completes (the co-processor holds `pcpi_wait` and answers within
//! nine cycles); the remaining hazard, running
//! the firmware on a core without the co-processor, traps (illegal
//! instruction) rather than corrupting state, and is excluded by building
//! the feature only for that SoC.
#![allow(unsafe_code)]

/// The `tex.lod` result for the untextured marker ([`crate::units::Log2Pb::UNTEXTURED`]):
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
            ".insn r {op}, {f3}, 0, {rd}, {lo}, {hi}",
            op = const super::CUSTOM0,
            f3 = const super::LOG2PL,
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
            ".insn r {op}, {f3}, 0, {rd}, {l}, {pb}",
            op = const super::CUSTOM0,
            f3 = const super::LOD,
            rd = lateout(reg) r,
            l = in(reg) l,
            pb = in(reg) pb,
            options(pure, nomem, nostack, preserves_flags),
        );
    }
    r
}

/// `tex.bw`: latches the weights `fx, fy ∈ [0, 4096]` (12 fractional
/// bits) of the footprint whose [`bt`] and [`bb`] follow.
#[inline(always)]
pub fn bw(fx: u32, fy: u32) {
    // SAFETY: one custom-0 R-type instruction on registers only (module
    // docs), writing no register (rd = x0); its effect is co-processor
    // state, so the block is not `pure` and stays in program order.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, 0, x0, {fx}, {fy}",
            op = const super::CUSTOM0,
            f3 = const super::BW,
            fx = in(reg) fx,
            fy = in(reg) fy,
            options(nomem, nostack, preserves_flags),
        );
    }
}

/// `tex.bt`: latches the top row `t00, t10` of the footprint, per channel
/// `t00_c·(4096 − fx) + t10_c·fx` with the [`bw`] weights.
#[inline(always)]
pub fn bt(t00: u32, t10: u32) {
    // SAFETY: as for `bw`.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, 0, x0, {a}, {b}",
            op = const super::CUSTOM0,
            f3 = const super::BT,
            a = in(reg) t00,
            b = in(reg) t10,
            options(nomem, nostack, preserves_flags),
        );
    }
}

/// `tex.bb`: the bottom row `t01, t11`; returns the footprint filtered and
/// rounded, channel `c` `(X_c + 2⁷ + 2²³) >> 24` with `X_c` the corner sum
/// of the [`bw`] weights, equal to [`crate::texture::kernel::accurate`]'s
/// `bilerp_rounded`. The co-processor keeps the level's 8.16 value
/// `(X_c + 2⁷) >> 8` for [`blend`] (the previous one's becomes the first of
/// the pair).
#[inline(always)]
#[must_use]
pub fn bb(t01: u32, t11: u32) -> u32 {
    let r: u32;
    // SAFETY: one custom-0 R-type instruction on registers only (module
    // docs); it reads and changes co-processor state, so the block is not
    // `pure`: kept, in program order, even when `r` is unused.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, 0, {rd}, {c}, {d}",
            op = const super::CUSTOM0,
            f3 = const super::BB,
            rd = lateout(reg) r,
            c = in(reg) t01,
            d = in(reg) t11,
            options(nomem, nostack, preserves_flags),
        );
    }
    r
}

/// `tex.blend`: the level blend of the last two [`bb`] values (`a` the
/// earlier, `b` the later) with the fraction `t ∈ [0, 256]`, channel `c`
/// `(a_c·(256 − t) + b_c·t + 2²³) >> 24`, equal to
/// [`crate::texture::kernel::accurate`]'s `blend_wide_in_range(a, b, t)`.
#[inline(always)]
#[must_use]
pub fn blend(t: u32) -> u32 {
    let r: u32;
    // SAFETY: one custom-0 R-type instruction on registers only (module
    // docs); it reads co-processor state and changes none; not `pure`, so
    // it stays after the `bb` it blends.
    unsafe {
        core::arch::asm!(
            ".insn r {op}, {f3}, 0, {rd}, {t}, x0",
            op = const super::CUSTOM0,
            f3 = const super::BLEND,
            rd = lateout(reg) r,
            t = in(reg) t,
            options(nomem, nostack, preserves_flags),
        );
    }
    r
}
