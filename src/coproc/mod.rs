//! Co-processors: wrappers of the custom instructions of texture units
//! built beside a soft core, one module per co-processor. Each is compiled
//! only for the core and feature it belongs to; without one every path is
//! the software one, with the same bits.
//!
//! * `pcpi` (feature `pcpi`, `riscv32` only): the PicoRV32 texture
//!   co-processor on the PCPI port.

#[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
pub mod pcpi;
