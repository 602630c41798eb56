//! The soft core's performance counters: `rdcycle`/`rdinstret` (PicoRV32
//! with `ENABLE_COUNTERS`, see `demo/softcore/soc.v`).
//!
//! Only the `softcore` build reads them; elsewhere every reading is zero
//! (QEMU counts no cycles, and its budgets come from traces instead).

/// min / sum / max of a per-call count over a series of calls (cycles,
/// instructions), without a heap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stat {
    /// The smallest count added (`u32::MAX` before the first).
    pub min: u32,
    /// The sum of the counts added (saturating).
    pub sum: u32,
    /// The largest count added (0 before the first).
    pub max: u32,
}

impl Stat {
    /// No count added yet.
    pub const EMPTY: Self = Self {
        min: u32::MAX,
        sum: 0,
        max: 0,
    };

    /// Adds the count of one call.
    pub fn add(&mut self, x: u32) {
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.sum = self.sum.saturating_add(x);
    }

    /// The statistics of `count − base` for each of `n` calls (`base`: the
    /// count of an empty measurement), saturating at 0.
    #[must_use]
    pub fn minus(self, base: u32, n: usize) -> Self {
        let n = u32::try_from(n).unwrap_or(u32::MAX);
        Self {
            min: self.min.saturating_sub(base),
            sum: self.sum.saturating_sub(base.saturating_mul(n)),
            max: self.max.saturating_sub(base),
        }
    }
}

/// A reading of both counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Clock cycles since reset (`cycle`, 64 bits).
    pub cycles: u64,
    /// Instructions retired since reset (`instret`, 64 bits).
    pub instret: u64,
}

/// Both 64-bit counters, cycles read first (the two reads are a few
/// instructions apart; measure differences of readings).
#[inline(always)]
#[must_use]
pub fn read() -> Counters {
    #[cfg(all(feature = "softcore", target_arch = "riscv32"))]
    {
        let cycles = riscv::register::cycle::read64();
        let instret = riscv::register::instret::read64();
        Counters { cycles, instret }
    }
    #[cfg(not(all(feature = "softcore", target_arch = "riscv32")))]
    {
        Counters::default()
    }
}

/// The low 32 bits of `cycle` (one `rdcycle`: the cheapest reading around
/// a short call; differences wrap correctly for calls under 2³² cycles).
#[inline(always)]
#[must_use]
pub fn cycles32() -> u32 {
    #[cfg(all(feature = "softcore", target_arch = "riscv32"))]
    {
        riscv::register::cycle::read() as u32
    }
    #[cfg(not(all(feature = "softcore", target_arch = "riscv32")))]
    {
        0
    }
}

/// The low 32 bits of `instret` (one `rdinstret`).
#[inline(always)]
#[must_use]
pub fn instret32() -> u32 {
    #[cfg(all(feature = "softcore", target_arch = "riscv32"))]
    {
        riscv::register::instret::read() as u32
    }
    #[cfg(not(all(feature = "softcore", target_arch = "riscv32")))]
    {
        0
    }
}
