//! Support code of the bare-metal demo binaries: stack painting (the
//! worst-case stack measurement of the demos and budgets).
//!
//! This crate denies `unsafe_code`; the [`stack`] module is the one
//! exception (it reads the stack pointer and writes/reads memory below it).
#![no_std]
#![deny(unsafe_code)]
#![deny(missing_docs)]

/// Stack painting: fill the free stack below the current stack pointer with
/// a pattern, run code, then find the lowest word that changed. Exact to 4
/// bytes for code that runs without interrupts (as the demos do).
#[allow(unsafe_code)]
pub mod stack {
    /// The paint pattern.
    pub const PAINT: u32 = 0xC0DE_5AFE;

    /// The current stack pointer.
    #[inline(always)]
    #[must_use]
    pub fn sp() -> usize {
        let sp: usize;
        // SAFETY: reads the stack pointer register into a general register;
        // no memory access, no side effect.
        unsafe {
            #[cfg(target_arch = "arm")]
            core::arch::asm!("mov {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags));
            #[cfg(target_arch = "riscv32")]
            core::arch::asm!("mv {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags));
            #[cfg(not(any(target_arch = "arm", target_arch = "riscv32")))]
            {
                sp = 0;
            }
        }
        sp
    }

    /// Paints `bytes` (multiple of 4) of free stack below `top` (a stack
    /// pointer value read by [`sp`] in the caller, which must not call
    /// anything between reading it and calling this: this function is
    /// always inlined, so it runs in the caller's frame).
    #[inline(always)]
    pub fn paint(top: usize, bytes: usize) {
        let mut p = top - bytes;
        while p < top {
            // SAFETY: [top − bytes, top) lies below the caller's stack
            // pointer: free stack that nothing else uses (no interrupts are
            // enabled in the demos) and inside RAM (memory.x reserves more
            // than `bytes` of stack; callers use at most 16 KiB).
            unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
            p += 4;
        }
    }

    /// Bytes of stack used below `top` since [`paint`] of the same region:
    /// `top` minus the lowest changed word (0 when none changed).
    #[inline(always)]
    #[must_use]
    pub fn used(top: usize, bytes: usize) -> usize {
        let mut p = top - bytes;
        while p < top {
            // SAFETY: the same region [`paint`] wrote: free stack in RAM.
            if unsafe { core::ptr::read_volatile(p as *const u32) } != PAINT {
                return top - p;
            }
            p += 4;
        }
        0
    }
}
