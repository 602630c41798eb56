//! Console output and exit of the demo binaries, on every machine they run
//! on: semihosting under QEMU (feature `qemu`, the default), the console and
//! exit registers of the PicoRV32 SoC in `demo/softcore/soc.v` (feature
//! `softcore`), LiteX's UART and the exit register of the LiteX SoC in
//! `demo/softcore/litex_soc.py` (feature `litex`). The binaries use
//! [`println!`](crate::println) and [`exit`] from here, never a machine's
//! own API.

#[cfg(any(
    all(feature = "qemu", feature = "softcore"),
    all(feature = "qemu", feature = "litex"),
    all(feature = "softcore", feature = "litex")
))]
compile_error!(
    "features `qemu`, `softcore` and `litex` are exclusive: build a soft core with --no-default-features --features softcore (or litex)"
);
#[cfg(not(any(feature = "qemu", feature = "softcore", feature = "litex")))]
compile_error!("enable feature `qemu` (the default), `softcore` or `litex`");

/// Prints a formatted line on the console (semihosting under QEMU, the
/// console register on the soft core).
#[cfg(feature = "qemu")]
#[macro_export]
macro_rules! println {
    ($($arg:tt)*) => { $crate::console::semihosting::println!($($arg)*) };
}

/// Prints a formatted line on the console (semihosting under QEMU, the
/// console register or UART on the soft core).
#[cfg(any(feature = "softcore", feature = "litex"))]
#[macro_export]
macro_rules! println {
    ($($arg:tt)*) => {{
        use core::fmt::Write as _;
        // The console never fails (`write_str` returns Ok).
        let _ = writeln!($crate::console::Console, $($arg)*);
    }};
}

#[cfg(feature = "qemu")]
#[doc(hidden)]
pub use semihosting;

/// Ends the program with exit code `code` (0 = success): semihosting exit
/// under QEMU, a write to the exit register on the soft core.
#[cfg(feature = "qemu")]
pub fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}

#[cfg(any(feature = "softcore", feature = "litex"))]
pub use exit_register::exit;
#[cfg(feature = "litex")]
pub use litex::Console;
#[cfg(feature = "softcore")]
pub use softcore::Console;

/// Exit and panics on a soft-core SoC: a write to its exit register
/// (`softcore::EXIT` or `litex::SIM_EXIT`).
#[cfg(any(feature = "softcore", feature = "litex"))]
#[allow(unsafe_code)]
mod exit_register {
    #[cfg(feature = "litex")]
    use super::litex::SIM_EXIT as EXIT;
    #[cfg(feature = "softcore")]
    use super::softcore::EXIT;

    /// Ends the program with exit code `code` (0 = success).
    pub fn exit(code: i32) -> ! {
        // SAFETY: EXIT is the SoC's exit register (a device register that
        // accepts any word write; nothing else lives at that address); the
        // write stops the simulation.
        unsafe { core::ptr::write_volatile(EXIT as *mut u32, code as u32) };
        // The simulator stops at the write; a SoC without the register (a
        // board) would go on: stay here.
        loop {
            core::hint::spin_loop();
        }
    }

    /// Panics print their message and exit with code 101.
    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
        crate::println!("panic: {info}");
        exit(101)
    }
}

/// The memory-mapped registers of the soft-core SoC (`demo/softcore/soc.v`).
#[cfg(feature = "softcore")]
#[allow(unsafe_code)]
mod softcore {
    /// Console register: a byte written here is printed.
    const CONSOLE: usize = 0x1000_0000;
    /// Exit register: a write ends the simulation with that exit code.
    pub(super) const EXIT: usize = 0x1000_0004;

    /// The console as a [`core::fmt::Write`] sink.
    #[derive(Clone, Copy, Debug)]
    pub struct Console;

    impl core::fmt::Write for Console {
        fn write_str(&mut self, s: &str) -> core::fmt::Result {
            for b in s.bytes() {
                // SAFETY: CONSOLE is the SoC's console register (soc.v), a
                // device register that accepts any byte write; nothing else
                // lives at that address.
                unsafe { core::ptr::write_volatile(CONSOLE as *mut u32, u32::from(b)) };
            }
            Ok(())
        }
    }

    /// riscv-rt's start-up hook for the trap vector: PicoRV32 has no
    /// `mtvec` (any CSR other than the counters is an illegal
    /// instruction), and the demos enable no interrupt, so there is nothing
    /// to set up.
    #[riscv_rt::setup_interrupts]
    fn setup_interrupts() {}
}

/// The LiteX SoC's UART and exit register (`demo/softcore/litex_soc.py`,
/// which checks these addresses against the CSR map it generates), and the
/// trap handler.
#[cfg(feature = "litex")]
#[allow(unsafe_code)]
mod litex {
    /// LiteX UART `rxtx`: a byte written here is sent.
    const UART_RXTX: usize = 0xf000_1000;
    /// LiteX UART `txfull`: non-zero while the transmit FIFO is full.
    const UART_TXFULL: usize = 0xf000_1004;
    /// The SoC's `sim_exit_code` register: a write ends the simulation with
    /// that exit code.
    pub(super) const SIM_EXIT: usize = 0xf000_1800;

    /// The console as a [`core::fmt::Write`] sink.
    #[derive(Clone, Copy, Debug)]
    pub struct Console;

    impl core::fmt::Write for Console {
        fn write_str(&mut self, s: &str) -> core::fmt::Result {
            for b in s.bytes() {
                // SAFETY: UART_TXFULL and UART_RXTX are LiteX UART CSRs
                // (one 32-bit register each, nothing else at those
                // addresses): reading `txfull` has no side effect, a write
                // of `rxtx` queues one byte.
                unsafe {
                    while core::ptr::read_volatile(UART_TXFULL as *const u32) != 0 {}
                    core::ptr::write_volatile(UART_RXTX as *mut u32, u32::from(b));
                }
            }
            Ok(())
        }
    }

    /// With feature `cfu`: VexRiscv's CFU plugin takes custom instructions
    /// only once enabled; before `main` (riscv-rt's post-init hook).
    #[cfg(feature = "cfu")]
    #[riscv_rt::post_init]
    fn enable_cfu() {
        raymip::coproc::cfu::enable();
    }

    /// Every exception (illegal instruction, e.g. a co-processor
    /// instruction on a core without it, or a bus error) prints its cause
    /// and address and exits with code 3, the PicoRV32 driver's status for
    /// a trap.
    #[unsafe(export_name = "ExceptionHandler")]
    fn exception_handler(_frame: &riscv_rt::TrapFrame) -> ! {
        let cause = riscv::register::mcause::read().bits();
        let pc = riscv::register::mepc::read();
        let tval = riscv::register::mtval::read();
        crate::println!("trap: mcause {cause:#x} mepc {pc:#010x} mtval {tval:#010x}");
        super::exit(3)
    }
}
