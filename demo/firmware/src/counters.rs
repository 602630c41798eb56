//! The soft core's performance counters: `rdcycle`/`rdinstret` (PicoRV32
//! with `ENABLE_COUNTERS`, see `demo/softcore/soc.v`; VexRiscv's CSR plugin).
//!
//! Only the soft-core builds (feature `counters`) read them; elsewhere every reading is zero
//! (QEMU counts no cycles, and its budgets come from traces instead).

/// Whether every measured series runs once untimed before its timed pass
/// ([`series`]): on the cached core (VexRiscv in the LiteX SoC, feature
/// `litex`: 4 KiB direct-mapped instruction and data caches) the timed pass
/// then sees the code and the inputs' data in the caches, as a per-hit loop
/// does after its first hits; the uncached PicoRV32 counts the same either
/// way and skips it. Every
/// call's result depends on its input alone (the BC1 pairs empty their
/// texel cache in `prepare`), so the untimed pass changes no count but the
/// caches'.
pub const WARM_UP: bool = cfg!(feature = "litex");

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
    #[cfg(all(feature = "counters", target_arch = "riscv32"))]
    {
        let cycles = riscv::register::cycle::read64();
        let instret = riscv::register::instret::read64();
        Counters { cycles, instret }
    }
    #[cfg(not(all(feature = "counters", target_arch = "riscv32")))]
    {
        Counters::default()
    }
}

/// The low 32 bits of `cycle` (one `rdcycle`: the cheapest reading around
/// a short call; differences wrap correctly for calls under 2³² cycles).
#[inline(always)]
#[must_use]
pub fn cycles32() -> u32 {
    #[cfg(all(feature = "counters", target_arch = "riscv32"))]
    {
        riscv::register::cycle::read() as u32
    }
    #[cfg(not(all(feature = "counters", target_arch = "riscv32")))]
    {
        0
    }
}

/// The low 32 bits of `instret` (one `rdinstret`).
#[inline(always)]
#[must_use]
pub fn instret32() -> u32 {
    #[cfg(all(feature = "counters", target_arch = "riscv32"))]
    {
        riscv::register::instret::read() as u32
    }
    #[cfg(not(all(feature = "counters", target_arch = "riscv32")))]
    {
        0
    }
}

/// Cycles and instructions of one call of `call` (the counter reads
/// included: subtract an empty measurement).
#[inline(always)]
pub fn once<O>(call: impl FnOnce() -> O) -> (u32, u32) {
    let c0 = cycles32();
    let i0 = instret32();
    let y = call();
    let i1 = instret32();
    let c1 = cycles32();
    core::hint::black_box(y);
    (c1.wrapping_sub(c0), i1.wrapping_sub(i0))
}

/// Cycles and instructions statistics of a series of calls.
pub type Stats = (Stat, Stat);

/// Adds one call's counts (cycles, instructions) to `st`.
fn add(st: &mut Stats, (c, i): (u32, u32)) {
    st.0.add(c);
    st.1.add(i);
}

/// `x`, through a copy the compiler cannot see into (as
/// [`core::hint::black_box`]), and on the cached core (VexRiscv, feature
/// `litex`) with a byte of every 32-byte line of the copy read, so that
/// the data cache holds the copy when the timed call reads it.
///
/// The timed loop hands each input to the callee through this copy on its
/// stack, and the compiler loads it inside the timed window (after the
/// first counter read). Reading the input from the input array before
/// evicts whatever line of VexRiscv's direct-mapped 4 KiB data cache it
/// maps to; where that is the copy's line, the store of the copy does not
/// bring it back (the cache is write-through and does not allocate on a
/// write), and the timed call paid a refill for the harness's own copy (one
/// to three inputs of the 64, depending on where the image puts the stack
/// and the array). The reads here come before the first counter read; the
/// timed instructions are the same.
#[inline(always)]
fn opaque<T>(x: T) -> T {
    #[cfg(all(feature = "litex", target_arch = "riscv32"))]
    {
        let mut x = x;
        let p = core::ptr::from_mut(&mut x).cast::<u8>();
        // The bytes at 0, 32, 64, … and the last one: one in every line
        // the value touches (a constant count of loads for each `T`).
        let n = size_of::<T>();
        let mut at = 0;
        while at < n + 31 {
            // SAFETY: one byte load at `p + min(at, n − 1)`, inside the
            // local `x` (initialised, `n ≥ 1` bytes here, mutably borrowed);
            // into a scratch register; no store, no stack. Not `readonly`:
            // like `black_box`, the compiler must assume the copy changed.
            #[allow(unsafe_code)]
            unsafe {
                core::arch::asm!(
                    "lbu {t}, 0({p})",
                    p = in(reg) p.wrapping_add(at.min(n - 1)),
                    t = out(reg) _,
                    options(nostack, preserves_flags)
                );
            }
            at += 32;
        }
        x
    }
    #[cfg(not(all(feature = "litex", target_arch = "riscv32")))]
    core::hint::black_box(x)
}

/// One place of the timed loop: the function `$name`, whose code after its
/// entry starts `$skip` bytes past a 1 KiB boundary on the cached core.
macro_rules! timed_loop {
    ($(#[$doc:meta])* $name:ident, $skip:literal) => {
        $(#[$doc])*
        #[inline(never)]
        fn $name<S, I: Copy, O, const K: usize>(
            s: &mut S,
            xs: &[I; crate::inputs::N],
            mut prepare: impl FnMut(&mut S),
            mut call: impl FnMut(&mut S, I) -> O,
            warm: usize,
        ) -> [[(u32, u32); K]; crate::inputs::N] {
            #[cfg(all(feature = "litex", target_arch = "riscv32"))]
            // SAFETY: a jump over alignment padding to the label just
            // after it (the padding is never executed); no register but
            // the program counter, no memory, no stack.
            #[allow(unsafe_code)]
            unsafe {
                core::arch::asm!(
                    "j 2f",
                    ".balign 1024",
                    $skip,
                    "2:",
                    options(nomem, nostack, preserves_flags)
                );
            }
            let mut counts = [[(0, 0); K]; crate::inputs::N];
            // The untimed pass over the last `warm` inputs, then the timed
            // pass over all: the same loop (opaque bounds, so the compiler
            // makes no copy of it for the first pass).
            let from = core::hint::black_box([crate::inputs::N.saturating_sub(warm), 0]);
            for pass in 0..core::hint::black_box(2) {
                let from = from.get(pass).copied().unwrap_or(0);
                let xs = xs.get(from..).unwrap_or(&[]);
                let counts = counts.get_mut(from..).unwrap_or(&mut []);
                for (&x, calls) in xs.iter().zip(counts) {
                    let x = opaque(x);
                    prepare(s);
                    for count in calls {
                        let c0 = cycles32();
                        let i0 = instret32();
                        let y = call(s, x);
                        let i1 = instret32();
                        let c1 = cycles32();
                        core::hint::black_box(y);
                        *count = (c1.wrapping_sub(c0), i1.wrapping_sub(i0));
                    }
                }
            }
            counts
        }
    };
}

timed_loop!(
    /// The timed loop of [`series`], first place.
    timed_a, ".skip 0");
timed_loop!(
    /// The timed loop of [`series`], second place: the same code, 512
    /// bytes further modulo 1 KiB.
    timed_b, ".skip 512");

/// The counts (cycles, instructions) of `K` calls of `call` per input of
/// `xs`, after `prepare` (not counted) per input: the counter reads
/// included (subtract an empty measurement).
///
/// The timed loop is a function of its own per series, which only reads
/// the counters, makes the calls and stores the counts: the statistics,
/// the printing and the other series' code do not run between two timed
/// calls. On a cached core the first pass of the loop warms the caches and
/// its counts are overwritten ([`WARM_UP`]); it is the same loop, so the
/// timed pass finds the loop's own code cached too. The loop's code still
/// takes a few lines of VexRiscv's direct-mapped 4 KiB instruction cache,
/// and where the callee's code has lines at the same places each evicts
/// the other on every call: a cost of the harness, not of the callee. So
/// on the cached core the series runs from two places half a KiB apart
/// modulo 1 KiB ([`timed_a`], [`timed_b`]: their loops take different
/// lines of the cache) and the one with fewer cycles in all is kept; the
/// callee, its inputs and the timed instructions are the same in both.
#[inline(always)]
pub fn series<S, I: Copy, O, const K: usize>(
    s: &mut S,
    xs: &[I; crate::inputs::N],
    mut prepare: impl FnMut(&mut S),
    mut call: impl FnMut(&mut S, I) -> O,
) -> [[(u32, u32); K]; crate::inputs::N] {
    let warm = if WARM_UP { crate::inputs::N } else { 0 };
    let a = timed_a(s, xs, &mut prepare, &mut call, warm);
    if !WARM_UP {
        return a;
    }
    // The second loop's own untimed pass over all inputs: its code can
    // evict lines of the callee that only some inputs run (a branch taken
    // by a few inputs), which the first loop's pass had loaded.
    let b = timed_b(s, xs, prepare, call, warm);
    let total = |c: &[[(u32, u32); K]; crate::inputs::N]| {
        c.iter()
            .flatten()
            .fold(0u32, |t, &(cy, _)| t.saturating_add(cy))
    };
    if total(&b) < total(&a) { b } else { a }
}

/// The statistics of the `K` calls per input of [`series`] (taken after
/// the last timed call).
#[inline(always)]
fn stats<S, I: Copy, O, const K: usize>(
    s: &mut S,
    xs: &[I; crate::inputs::N],
    prepare: impl FnMut(&mut S),
    call: impl FnMut(&mut S, I) -> O,
) -> [Stats; K] {
    let mut st = [(Stat::EMPTY, Stat::EMPTY); K];
    for calls in series::<S, I, O, K>(s, xs, prepare, call) {
        for (k, c) in st.iter_mut().zip(calls) {
            add(k, c);
        }
    }
    st
}

/// The statistics of one call of `call` per input of `xs` ([`series`]).
#[inline(always)]
pub fn measure<I: Copy, O>(xs: &[I; crate::inputs::N], mut call: impl FnMut(I) -> O) -> Stats {
    let [st] = stats(&mut (), xs, |()| {}, |(), x| call(x));
    st
}

/// The soft core's [`Meter`](crate::probes::Meter): counts each call of a
/// row with [`series`] (a batch with [`once`]) and prints every row on the
/// console after its series, minus the counter reads
/// ([`CycleMeter::new`]), in the format `scripts/softcore.py` parses:
/// `call KEY: n 64 cycles min A sum B max C instret min D sum E max F` per
/// row, `batch KEY: n32 cycles A instret B n64 cycles C instret D` per
/// batch row.
pub struct CycleMeter {
    /// The empty measurement's minimum (cycles, instructions).
    base: (u32, u32),
}

impl CycleMeter {
    /// Measures the baseline (the counter reads alone, [`N`](crate::inputs::N)
    /// times: constant on an in-order core without caches; its minimum is
    /// subtracted from every count) and prints it:
    /// `baseline: cycles min A max B instret min C max D`.
    #[must_use]
    pub fn new() -> Self {
        let st = measure(&[(); crate::inputs::N], |()| ());
        crate::println!(
            "baseline: cycles min {} max {} instret min {} max {}",
            st.0.min,
            st.0.max,
            st.1.min,
            st.1.max
        );
        Self {
            base: (st.0.min, st.1.min),
        }
    }

    fn print(&self, key: &str, (cy, ir): Stats) {
        let n = crate::inputs::N;
        let (cy, ir) = (cy.minus(self.base.0, n), ir.minus(self.base.1, n));
        crate::println!(
            "call {key}: n {n} cycles min {} sum {} max {} instret min {} sum {} max {}",
            cy.min,
            cy.sum,
            cy.max,
            ir.min,
            ir.sum,
            ir.max
        );
    }
}

impl Default for CycleMeter {
    fn default() -> Self {
        Self::new()
    }
}

impl crate::probes::Meter for CycleMeter {
    fn row<I: Copy>(&mut self, key: &str, xs: &[I; crate::inputs::N], call: impl FnMut(I) -> u32) {
        self.print(key, measure(xs, call));
    }

    fn pairs<S, I: Copy>(
        &mut self,
        keys: [&str; 2],
        s: &mut S,
        xs: &[I; crate::inputs::N],
        prepare: impl FnMut(&mut S),
        call: impl FnMut(&mut S, I) -> u32,
    ) {
        let st: [Stats; 2] = stats(s, xs, prepare, call);
        for (key, k) in keys.into_iter().zip(st) {
            self.print(key, k);
        }
    }

    fn batch(&mut self, key: &str, mut call: impl FnMut(usize) -> usize) {
        let n = crate::inputs::N;
        if WARM_UP {
            core::hint::black_box(call(n));
        }
        let (c32, i32_) = once(|| call(n / 2));
        let (c64, i64_) = once(|| call(n));
        let (bc, bi) = self.base;
        crate::println!(
            "batch {key}: n32 cycles {} instret {} n64 cycles {} instret {}",
            c32.saturating_sub(bc),
            i32_.saturating_sub(bi),
            c64.saturating_sub(bc),
            i64_.saturating_sub(bi)
        );
    }
}
