//! Console output and exit of the demo binaries, on every machine they run
//! on: semihosting under QEMU (feature `qemu`, the default), the console and
//! exit registers of the PicoRV32 SoC in `demo/softcore/soc.v` (feature
//! `softcore`). The binaries use [`println!`](crate::println) and [`exit`]
//! from here, never a machine's own API.

#[cfg(all(feature = "qemu", feature = "softcore"))]
compile_error!(
    "features `qemu` and `softcore` are exclusive: build the soft core with --no-default-features --features softcore"
);
#[cfg(not(any(feature = "qemu", feature = "softcore")))]
compile_error!("enable feature `qemu` (the default) or `softcore`");

/// Prints a formatted line on the console (semihosting under QEMU, the
/// console register on the soft core).
#[cfg(feature = "qemu")]
#[macro_export]
macro_rules! println {
    ($($arg:tt)*) => { $crate::console::semihosting::println!($($arg)*) };
}

/// Prints a formatted line on the console (semihosting under QEMU, the
/// console register on the soft core).
#[cfg(feature = "softcore")]
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

#[cfg(feature = "softcore")]
pub use softcore::{Console, exit};

/// The memory-mapped registers of the soft-core SoC (`demo/softcore/soc.v`).
#[cfg(feature = "softcore")]
#[allow(unsafe_code)]
mod softcore {
    /// Console register: a byte written here is printed.
    const CONSOLE: usize = 0x1000_0000;
    /// Exit register: a write ends the simulation with that exit code.
    const EXIT: usize = 0x1000_0004;

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

    /// Ends the program with exit code `code` (0 = success).
    pub fn exit(code: i32) -> ! {
        // SAFETY: EXIT is the SoC's exit register (soc.v); the write stops
        // the simulation.
        unsafe { core::ptr::write_volatile(EXIT as *mut u32, code as u32) };
        // The simulator stops at the write; a real SoC without the register
        // would go on: stay here.
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

    /// riscv-rt's start-up hook for the trap vector: PicoRV32 has no
    /// `mtvec` (any CSR other than the counters is an illegal
    /// instruction), and the demos enable no interrupt, so there is nothing
    /// to set up.
    #[riscv_rt::setup_interrupts]
    fn setup_interrupts() {}
}
