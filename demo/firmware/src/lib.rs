//! Support code of the bare-metal demo binaries: stack painting (the
//! worst-case stack measurement of the demos and budgets), the
//! pseudo-random inputs of the budget calls ([`inputs`], one home for every
//! counter that times them: QEMU traces, `minstret`, a soft core's `rdcycle`)
//! and the sampler-matrix and ray-differential probes on those inputs
//! ([`probes`]: wrappers, subjects and the order of their calls).
//!
//! This crate denies `unsafe_code`; the exceptions are the [`stack`] module
//! (it reads the stack pointer and writes/reads memory below it), the
//! `#[unsafe(no_mangle)]` attribute of the [`probes`] wrappers (stable
//! symbol names for the QEMU traces) and, on VexRiscv, the jump over the
//! alignment padding that places the timed loops of [`counters`] and the
//! byte loads that put a timed call's input in the data cache.
#![no_std]
#![deny(unsafe_code)]
#![deny(missing_docs)]

/// Measured entry points: each `fn name(args) -> Ret = callee;` becomes an
/// `#[inline(never)]` function that calls `callee(args)`, so a measurement
/// times one real call of the callee with its own code inlined into it.
#[macro_export]
macro_rules! measured_calls {
    ($( fn $name:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty = $callee:path; )+) => {
        $(
            #[inline(never)]
            fn $name($($arg: $ty),*) -> $ret {
                $callee($($arg),*)
            }
        )+
    };
}

// Output, exit and cycle counters on QEMU and on the soft core.
pub mod console;
pub mod counters;
pub mod probes;
pub use console::exit;

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

/// The inputs of the budget calls (`src/bin/budget.rs`): a deterministic
/// xorshift generator and one draw per call kind, so every measurement of
/// the same calls (QEMU instruction traces, `minstret`, cycle counters on
/// a soft core) sees the same 64 inputs in the same order; and the fixed
/// configurations those calls use (sampler states, the texture of the
/// BC1 row, the geometric-LOD selector).
pub mod inputs {
    use fixed::types::{I16F16, U1F31};
    use raymip::geomlod::{DepthToLod, LodMode, Selector};
    use raymip::texture::address::AddressMode;
    use raymip::texture::sampler::state::{SamplerDesc, SamplerState, SrgbOutput};
    use raymip::units::{
        Delta, Depth, Footprint, Lod, LodBias, Log2Pb, PathLength, TexCoord, Transition, Width,
    };

    /// One ray-differential input: state, direction, hit distance, normal
    /// and its differential (feature `raydiff`).
    #[cfg(feature = "raydiff")]
    pub type RayDiffIn = (
        raymip::path::raydiff::RayDiff,
        raymip::units::UnitVec,
        PathLength,
        raymip::units::UnitVec,
        raymip::path::raydiff::DirDiff,
    );

    /// Calls per measured function (and hits per batch).
    pub const N: usize = 64;

    /// Seed of the generator for the whole budget run.
    pub const SEED: u32 = 0x2545_F491;

    /// The inputs' generator (xorshift32; its home is `raymip::rng`).
    pub use raymip::rng::XorShift32;

    /// The inputs of the budget calls in the budgets' order, all from one
    /// generator seeded with [`SEED`]: [`N`] draws of each kind. `rng` is
    /// the generator after the last draw (the geometric-LOD instances of
    /// the budgets follow from it).
    pub struct Draws {
        /// Raw words (the empty call's inputs).
        pub empty: [u32; N],
        /// [`table_lod`] inputs.
        pub lod: [(PathLength, Log2Pb); N],
        /// [`cone_lod`] inputs.
        pub cone: [(Width, Delta, Option<U1F31>); N],
        /// [`bilinear`] inputs.
        pub bilinear: [(TexCoord, TexCoord, Lod); N],
        /// [`trilinear`] inputs.
        pub trilinear: [(TexCoord, TexCoord, Lod); N],
        /// [`aniso`] inputs.
        pub aniso: [(TexCoord, TexCoord, Footprint); N],
        /// The generator after these draws.
        pub rng: XorShift32,
    }

    impl Draws {
        /// Every kind drawn in turn from `XorShift32(SEED)`.
        #[must_use]
        pub fn new() -> Self {
            let mut rng = XorShift32(SEED);
            let empty = draw(&mut rng, XorShift32::next_u32);
            let lod = draw(&mut rng, table_lod);
            let cone = draw(&mut rng, cone_lod);
            let bilinear = draw(&mut rng, bilinear);
            let trilinear = draw(&mut rng, trilinear);
            let aniso = draw(&mut rng, aniso);
            Self {
                empty,
                lod,
                cone,
                bilinear,
                trilinear,
                aniso,
                rng,
            }
        }
    }

    impl Default for Draws {
        fn default() -> Self {
            Self::new()
        }
    }

    /// [`N`] inputs drawn by `f` in turn.
    pub fn draw<T>(rng: &mut XorShift32, mut f: impl FnMut(&mut XorShift32) -> T) -> [T; N] {
        core::array::from_fn(|_| f(rng))
    }

    /// Table lod: `Pl` over 2⁻¹⁶ .. 2¹⁶ scene units, `log2 Pb` over [−16, 16).
    pub fn table_lod(r: &mut XorShift32) -> (PathLength, Log2Pb) {
        let shift = 16 + r.next_u32() % 32;
        let pl = PathLength::from_bits((u64::from(r.next_u32()) << (shift - 16)) | 1);
        let pb = Log2Pb::from_log2(I16F16::from_bits((r.next_u32() as i32) >> 11));
        (pl, pb)
    }

    /// Cone lod: width up to 2⁸ scene units, Δ over [−64, 64), `|n·d|` ≥ 2⁻¹¹.
    pub fn cone_lod(r: &mut XorShift32) -> (Width, Delta, Option<U1F31>) {
        let w = Width::from_bits(i64::from(r.next_u32()) << (r.next_u32() % 24));
        let d = Delta::from_bits((r.next_u32() as i32) >> 10);
        let c = Some(U1F31::from_bits(r.next_u32() | (1 << 20)));
        (w, d, c)
    }

    /// Bilinear sample: `u, v ∈ [0, 1)`, lod over [0, 5).
    pub fn bilinear(r: &mut XorShift32) -> (TexCoord, TexCoord, Lod) {
        let u = TexCoord::from_bits(i64::from(r.next_u32()));
        let v = TexCoord::from_bits(i64::from(r.next_u32()));
        let lod = Lod::from_bits((r.next_u32() % (5 << 8)) as i16);
        (u, v, lod)
    }

    /// Trilinear sample: as [`bilinear`], the lod's fraction never 0 (both
    /// levels are filtered).
    pub fn trilinear(r: &mut XorShift32) -> (TexCoord, TexCoord, Lod) {
        let u = TexCoord::from_bits(i64::from(r.next_u32()));
        let v = TexCoord::from_bits(i64::from(r.next_u32()));
        let lod = Lod::from_bits((r.next_u32() % (5 << 8)) as i16 | 1);
        (u, v, lod)
    }

    /// The sampler state of the sampler-state (`ts_*`) rows that are not
    /// anisotropic: mirror on `u`, clamp-to-border on `v` (border
    /// `0x80402010`), lod bias +¼, lod clamp `[½, 4]`, sRGB results
    /// re-encoded. `None` cannot happen (the fields are in range).
    #[must_use]
    pub fn sampler_state() -> Option<SamplerState> {
        SamplerState::new(SamplerDesc {
            address_u: AddressMode::Mirror,
            address_v: AddressMode::ClampToBorder,
            border: 0x8040_2010,
            lod_bias: Lod::from_bits(64),
            min_lod: Lod::from_bits(128),
            max_lod: Lod::from_bits(4 << 8),
            max_anisotropy: 1,
            srgb_output: SrgbOutput::Encoded,
        })
        .ok()
    }

    /// The state of the wrap rows of the sampler matrix: wrap on both axes,
    /// with the bias and lod clamp of [`sampler_state`] (lod bias +¼, lod
    /// clamp `[½, 4]`). `None` cannot happen (the fields are in range).
    #[must_use]
    pub fn wrap_state() -> Option<SamplerState> {
        SamplerState::new(SamplerDesc {
            address_u: AddressMode::Wrap,
            address_v: AddressMode::Wrap,
            ..*sampler_state()?.desc()
        })
        .ok()
    }

    /// The sampler state of the anisotropic rows: wrap, no bias or clamp,
    /// at most `max_aniso` probes (`None` outside `1 ..= 16`).
    #[must_use]
    pub fn aniso_state(max_aniso: u8) -> Option<SamplerState> {
        SamplerState::new(SamplerDesc {
            max_anisotropy: max_aniso,
            ..SamplerDesc::default()
        })
        .ok()
    }

    /// Anisotropic sample: `u, v ∈ [0, 1)` and a long footprint: a major
    /// axis with components in `[−1, 1)` (up to 32 texels per component on
    /// the 32×32 demo texture) and a minor axis perpendicular to it, 16 or
    /// 32 times shorter, so every cap up to 16× is reached (probe count =
    /// the cap).
    pub fn aniso(r: &mut XorShift32) -> (TexCoord, TexCoord, Footprint) {
        let u = TexCoord::from_bits(i64::from(r.next_u32()));
        let v = TexCoord::from_bits(i64::from(r.next_u32()));
        let a = i64::from(r.next_u32() as i32) << 1;
        let b = i64::from(r.next_u32() as i32) << 1;
        let k = 4 + (r.next_u32() & 1);
        let fp = Footprint {
            x: [TexCoord::from_bits(a), TexCoord::from_bits(b)],
            y: [TexCoord::from_bits(-b >> k), TexCoord::from_bits(a >> k)],
        };
        (u, v, fp)
    }

    /// Pseudo-random bytes (the stored blocks of the BC1 row: every
    /// 8-byte pattern is a valid BC1 block, both colour modes occur).
    pub fn bytes<const L: usize>(r: &mut XorShift32) -> [u8; L] {
        let mut b = [0u8; L];
        for x in &mut b {
            *x = (r.next_u32() >> 24) as u8;
        }
        b
    }

    /// Instances of the geometric-LOD rows: ids counting from `first`,
    /// camera-space depths over `[−2, 70)` scene units (16 fractional
    /// bits; some before `z_near` and beyond `z_far` of [`selector`]).
    pub fn instances<const L: usize>(r: &mut XorShift32, first: u32) -> [(u32, Depth); L] {
        let mut out = [(0, Depth::ZERO); L];
        for (i, x) in (first..).zip(out.iter_mut()) {
            let z = i64::from(r.next_u32() % (72 << 16)) - (2 << 16);
            *x = (i, Depth::from_bits(z << 16));
        }
        out
    }

    /// The geometric-LOD selector of the budget rows: 8 LODs from
    /// `z_near` = 2 to `z_far` = 66 scene units, bias −¼ level, in `mode`
    /// (`None` cannot happen with these constants).
    #[must_use]
    pub fn selector(mode: LodMode) -> Option<Selector> {
        let range = DepthToLod::new(
            Depth::from_num(2),
            Depth::from_num(66),
            8,
            LodBias::from_bits(-(1 << 14)),
        )
        .ok()?;
        Selector::new(range, mode).ok()
    }

    /// The transition interval of the stochastic row: ½.
    pub const TRANSITION: Transition = Transition::from_bits(1 << 15);

    /// One ray leaving the scene (feature `envmap`): a cone spread in
    /// `[2⁻¹², 2⁻⁸)` radians, a direction of any latitude (components up to
    /// `±1`, `z` up to `−½`), and direction differentials up to 2⁻⁸.
    #[cfg(feature = "envmap")]
    pub fn envmap(
        r: &mut XorShift32,
    ) -> (
        raymip::units::Spread,
        raymip::units::UnitVec,
        [fixed::types::I2F30; 3],
        [fixed::types::I2F30; 3],
    ) {
        use fixed::types::I2F30;
        let g = raymip::units::Spread::from_bits(((r.next_u32() >> 12) | (1 << 18)) as i32);
        let mut f = |sh: u32| I2F30::from_bits((r.next_u32() as i32) >> sh);
        let d = [f(1), f(1), f(2)];
        let dx = [f(9), f(9), f(9)];
        let dy = [f(9), f(9), f(9)];
        (g, raymip::units::UnitVec::new(d), dx, dy)
    }

    /// Ray differentials (feature `raydiff`): one ray of a primary-like
    /// state (`|∂O|` up to 2⁻⁶, `|∂D|` up to 2⁻⁸), direction roughly
    /// `(±½, ±½, −0.7)`, a normal near `+z` with small differentials, hit
    /// distance in [1, 65) scene units.
    #[cfg(feature = "raydiff")]
    pub fn raydiff(r: &mut XorShift32) -> RayDiffIn {
        use fixed::types::{I2F30, I32F32};
        use raymip::path::raydiff::{DirDiff, PosDiff, RayDiff};
        let mut f = |sh: u32| I2F30::from_bits((r.next_u32() as i32) >> sh);
        let d = [f(2), f(2), I2F30::from_num(-0.7)];
        let n = [f(4), f(4), I2F30::from_num(0.99)];
        let dn = [f(10), f(10), f(10)];
        let dd = [[f(9), f(9), f(9)], [f(9), f(9), f(9)]];
        let mut g = |_| I32F32::from_bits(i64::from(r.next_u32() as i32) >> 7);
        let o: [[I32F32; 3]; 2] = [core::array::from_fn(&mut g), core::array::from_fn(&mut g)];
        let t = PathLength::from_bits(u64::from(r.next_u32() >> 6) + (1 << 32));
        let s = RayDiff::new(
            PosDiff::from_i32f32(o[0]),
            PosDiff::from_i32f32(o[1]),
            DirDiff::from_i2f30(dd[0]),
            DirDiff::from_i2f30(dd[1]),
        );
        (
            s,
            raymip::units::UnitVec::new(d),
            t,
            raymip::units::UnitVec::new(n),
            DirDiff::from_i2f30(dn),
        )
    }
}
