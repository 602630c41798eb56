//! Tests of the C ABI: every function against the Rust API it wraps, and
//! the boundary cases C callers create (null, misaligned and aliasing
//! pointers, corrupt lengths).

extern crate std;
use fixed::types::{I2F30, I16F16, I32F32, U1F31};

use crate::lod::{clamp_lod, cone_lod, table_lod};
use crate::path::raystack::PathState;
use crate::setup::camera::PixelSpread;
use crate::texture::sampler::dynamic::DynSampler;
use crate::texture::sampler::state::SrgbOutput;
use crate::texture::storage::format::{ColorSpace, Format, TexelFormat};
use crate::texture::storage::image::Image;
use crate::texture::storage::mip::{Geometry, Pyramid, pyramid_len};
use crate::texture::{Mode, SamplerDesc, SamplerState};
use crate::units::{
    Accurate, Delta, Footprint, Lod, Log2Pb, PathLength, Precision, Spread, TexCoord, Width,
};

use super::*;
use proptest::prelude::*;

/// `n` pseudo-random words (a 64-bit LCG from `seed`).
fn lcg_texels(seed: u64, n: usize) -> std::vec::Vec<u32> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 32) as u32
        })
        .collect()
}

fn ok_lod(pl: u64, e: i32) -> (RmStatus, i16) {
    let mut out = i16::MIN;
    // SAFETY: `out` is a valid local.
    let s = unsafe { rm_table_lod(pl, e, &mut out) };
    (s, out)
}

/// The C numbering (`RmAddress`'s discriminants, the header's
/// `RM_ADDRESS_*`) names the modes its docs name; any other byte is none.
#[test]
fn c_address_numbers_name_their_modes() {
    use crate::texture::AddressMode::{ClampToBorder, ClampToEdge, Mirror, MirrorOnce, Wrap};
    use RmAddress as C;
    let c = [C::Wrap, C::Mirror, C::Clamp, C::MirrorOnce, C::Border];
    let modes = [Wrap, Mirror, ClampToEdge, MirrorOnce, ClampToBorder];
    for (c, mode) in c.into_iter().zip(modes) {
        assert_eq!(RmAddress::mode(c as u8), Some(mode), "{c:?}");
    }
    for n in 5..=u8::MAX {
        assert_eq!(RmAddress::mode(n), None, "{n}");
    }
}

/// The status numbers are the header's `RM_STATUS_*` values, which C
/// callers compare against: each one as the header documents it.
#[test]
fn status_numbers_are_the_headers() {
    use RmStatus as S;
    let documented = [
        (S::Ok, 0),
        (S::Untextured, 1),
        (S::NullPointer, -1),
        (S::OutOfRange, -2),
        (S::StackFull, -3),
        (S::StackEmpty, -4),
        (S::ZeroSize, -5),
        (S::BadAngle, -6),
        (S::TableFull, -7),
        (S::BufferTooShort, -8),
        (S::Misaligned, -9),
        (S::Uninitialised, -10),
    ];
    for (s, n) in documented {
        assert_eq!(s as i32, n, "{s:?}");
    }
}

/// Each set-up error reaches C as the status its doc names.
#[test]
fn set_up_errors_map_to_their_statuses() {
    use crate::setup::table::TableError;
    use crate::texture::storage::mip::MipError;
    assert_eq!(
        table::table_status(TableError::ZeroTextureSize),
        RmStatus::ZeroSize
    );
    assert_eq!(
        table::table_status(TableError::TableFull),
        RmStatus::TableFull
    );
    assert_eq!(
        table::table_status(TableError::NonFinite),
        RmStatus::OutOfRange
    );
    assert_eq!(
        table::table_status(TableError::OutOfRange),
        RmStatus::OutOfRange
    );
    assert_eq!(mip::mip_status(MipError::ZeroSize), RmStatus::ZeroSize);
    let short = MipError::BufferTooShort { needed: 2, got: 1 };
    assert_eq!(mip::mip_status(short), RmStatus::BufferTooShort);
    assert_eq!(mip::mip_status(MipError::TooLarge), RmStatus::OutOfRange);
    assert_eq!(mip::mip_status(MipError::BadLevels), RmStatus::OutOfRange);
}

/// Pyramid and image sizes, counted by hand: 4 × 4 with 3 levels is
/// 16 + 4 + 1 texels; 8 × 2 with all 4 levels 16 + 4 + 2 + 1; a request
/// for more levels than the chain has is capped; a zero side has none.
#[test]
fn pyramid_and_image_lengths() {
    assert_eq!(rm_pyramid_len(4, 4, 3), 21);
    assert_eq!(rm_pyramid_len(8, 2, 4), 23);
    assert_eq!(rm_pyramid_len(8, 2, 200), 23);
    assert_eq!(rm_pyramid_len(1, 1, 1), 1);
    assert_eq!(rm_pyramid_len(0, 4, 3), 0);
    let rgba8 = RmFormat::Rgba8 as u8;
    let bc1 = RmFormat::Bc1 as u8;
    // RGBA8: 4 bytes a texel.
    assert_eq!(rm_image_len(4, 4, 3, rgba8), 21 * 4);
    // BC1: 8 bytes per 4 × 4 block, a level below 4 texels is one block.
    assert_eq!(rm_image_len(8, 8, 4, bc1), (4 + 1 + 1 + 1) * 8);
    for (w, h) in [(0, 4), (4, 0), (0, 0)] {
        assert_eq!(rm_image_len(w, h, 3, rgba8), 0, "{w}x{h}");
        assert_eq!(rm_image_len(w, h, 3, bc1), 0, "{w}x{h}");
    }
    assert_eq!(rm_image_len(4, 4, 3, 200), 0);
}

#[test]
fn null_pointers_are_reported() {
    // SAFETY: null pointers are the inputs under test; nothing is dereferenced.
    unsafe {
        assert_eq!(
            rm_table_lod(1, 0, core::ptr::null_mut()),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_ray_stack_init(core::ptr::null_mut()),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_ray_stack_push(core::ptr::null_mut(), core::ptr::null()),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_ray_stack_pop(core::ptr::null_mut(), core::ptr::null_mut()),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_path_advance(core::ptr::null_mut(), 1),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_path_bounce(core::ptr::null_mut(), 1),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_path_primary(1 << 20, 0, core::ptr::null_mut()),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_table_build(
                core::ptr::null_mut(),
                1,
                core::ptr::null(),
                0,
                1 << 20,
                core::ptr::null_mut()
            ),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_sampler_init(
                core::ptr::null_mut(),
                core::ptr::null(),
                RmAddressBits(RmAddress::Wrap as u8)
            ),
            RmStatus::NullPointer
        );
        assert_eq!(
            rm_sample(
                core::ptr::null_mut(),
                0,
                0,
                0,
                RmModeBits(RmMode::Trilinear as u8),
                core::ptr::null_mut()
            ),
            RmStatus::NullPointer
        );
    }
}

#[test]
fn corrupt_stack_length_is_read_as_full_and_pops_in_range() {
    let mut st = RmRayStack {
        entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
        len: 1000,
    };
    let s = RmPathState::default();
    let mut out = RmPathState::default();
    // SAFETY: valid locals.
    unsafe {
        assert_eq!(rm_ray_stack_push(&mut st, &s), RmStatus::StackFull);
        assert_eq!(rm_ray_stack_pop(&mut st, &mut out), RmStatus::Ok);
    }
    assert_eq!(st.len as usize, RM_RAY_STACK_CAPACITY - 1);
}

/// A partial update reports what it wrote: the items before the first
/// one without a slot (`TableFull`) or the first invalid one
/// (`ZeroSize`; a missing slot wins when both apply), counted in
/// `stats`, the entries after them untouched.
#[test]
fn partial_update_counts_what_it_wrote() {
    let unit = RmTriangle {
        positions: [[0, 0, 0], [1 << 32, 0, 0], [0, 1 << 32, 0]],
        uvs: [[0, 0], [1 << 32, 0], [0, 1 << 32]],
        tex_width: 64,
        tex_height: 64,
        textured: 1,
    };
    let plain = RmTriangle {
        textured: 0,
        ..unit
    };
    let zero = RmTriangle {
        tex_width: 0,
        ..unit
    };
    let mk = |t, u| RmBuildStats {
        textured: t,
        untextured: u,
        ..RmBuildStats::default()
    };
    for (start, tris, status, want, written) in [
        (
            1,
            &[unit, plain, unit][..],
            RmStatus::TableFull,
            mk(1, 1),
            2,
        ),
        (0, &[plain, zero, unit][..], RmStatus::ZeroSize, mk(0, 1), 1),
        (2, &[unit, zero][..], RmStatus::TableFull, mk(1, 0), 1),
        (5, &[unit][..], RmStatus::TableFull, mk(0, 0), 0),
        (0, &[unit, plain][..], RmStatus::Ok, mk(1, 1), 2),
    ] {
        let mut e = [0x5A5A_5A5A; 3];
        let mut st = RmBuildStats::default();
        // SAFETY: valid locals of the stated lengths.
        let s = unsafe {
            rm_table_update(
                e.as_mut_ptr(),
                3,
                start,
                tris.as_ptr(),
                tris.len(),
                1 << 20,
                &mut st,
            )
        };
        assert_eq!(
            (s, st),
            (status, want),
            "start {start}, {} items",
            tris.len()
        );
        let touched = e.iter().filter(|&&x| x != 0x5A5A_5A5A).count();
        assert_eq!(touched, written, "start {start}");
    }
}

/// A grazing hit (`|n·d| = 0`) through C clamps like the Rust `cone_lod`
/// (2⁻¹⁶, 16 levels coarser) instead of dropping the normal term;
/// `|n·d| = 1` is "no normal term".
#[test]
fn grazing_cone_lod_agrees_with_rust() {
    let w = I32F32::ONE;
    let grazing = cone_lod::<Accurate>(Width::from_fixed(w), Delta::ZERO, Some(U1F31::ZERO));
    assert_eq!(grazing, Lod::from_num(16));
    assert_eq!(rm_cone_lod(w.to_bits(), 0, 0), grazing.to_bits());
    assert_eq!(rm_cone_lod(w.to_bits(), 0, 1), grazing.to_bits());
    assert_eq!(rm_cone_lod(w.to_bits(), 0, 1 << 31), 0);
    assert_eq!(
        cone_lod::<Accurate>(Width::from_fixed(w), Delta::ZERO, None),
        cone_lod::<Accurate>(
            Width::from_fixed(w),
            Delta::ZERO,
            Some(U1F31::from_bits(1 << 31))
        )
    );
}

/// `rm_delta` against the f64 formula `−log2 Pb − log2 γ` (γ rounded
/// to I2F30 first); bad input is reported and nothing is written.
#[test]
fn delta_matches_f64_and_rejects_bad_input() {
    let gamma = 0.01f64;
    let spread = I2F30::from_num(gamma).to_bits();
    for pb in [-3.5f64, 0.0, 2.25, 11.0] {
        let mut d = 0i32;
        let entry = I16F16::from_num(pb).to_bits();
        // SAFETY: a valid, aligned out pointer.
        assert_eq!(unsafe { rm_delta(entry, spread, &mut d) }, RmStatus::Ok);
        let want = -pb - I2F30::from_num(gamma).to_num::<f64>().log2();
        let got = I16F16::from_bits(d).to_num::<f64>();
        assert!((got - want).abs() < 1.0 / 4096.0, "{pb}: {got} vs {want}");
    }
    let mut d = 7i32;
    // SAFETY: as above; null is reported, not dereferenced.
    unsafe {
        assert_eq!(
            rm_delta(RM_UNTEXTURED, spread, &mut d),
            RmStatus::Untextured
        );
        assert_eq!(rm_delta(0, 0, &mut d), RmStatus::BadAngle);
        assert_eq!(rm_delta(0, -5, &mut d), RmStatus::BadAngle);
        assert_eq!(
            rm_delta(0, spread, core::ptr::null_mut()),
            RmStatus::NullPointer
        );
    }
    assert_eq!(d, 7);
}

/// Pushing an entry of the same stack
/// (`rm_ray_stack_push(&s, &s.entries[i])`) is a natural C idiom; the
/// state must be read before the stack is borrowed mutably (Miri reports
/// undefined behaviour otherwise).
#[test]
fn push_an_entry_of_the_same_stack() {
    let mut st = RmRayStack {
        entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
        len: 0,
    };
    let p: *mut RmRayStack = &mut st;
    let first = RmPathState {
        pl: 42,
        depth: 3,
        ..RmPathState::default()
    };
    // SAFETY: `p` points to a valid local stack; `entry` points into it
    // (the aliasing under test).
    unsafe {
        assert_eq!(rm_ray_stack_push(p, &first), RmStatus::Ok);
        let entry: *const RmPathState = core::ptr::addr_of!((*p).entries[0]);
        assert_eq!(rm_ray_stack_push(p, entry), RmStatus::Ok);
        assert_eq!((*p).len, 2);
        assert_eq!((*p).entries[1], first);
        // Pop into the slot being popped (out aliases the stack too).
        let out: *mut RmPathState = core::ptr::addr_of_mut!((*p).entries[1]);
        assert_eq!(rm_ray_stack_pop(p, out), RmStatus::Ok);
        assert_eq!((*p).len, 1);
        assert_eq!((*p).entries[1], first);
    }
}

/// A misaligned caller pointer is an
/// error, never dereferenced (`from_raw_parts` and `*p` require
/// alignment; debug builds panic on it, release builds are UB).
#[test]
fn misaligned_pointers_are_rejected() {
    let mut raw = [0u64; 64];
    let base = raw.as_mut_ptr().cast::<u8>();
    // SAFETY: offsets stay inside `raw`; the misaligned pointers are only
    // handed to the entry points, which must not dereference them.
    unsafe {
        let mis = base.add(1);
        assert_eq!(rm_table_lod(1 << 32, 0, mis.cast()), RmStatus::Misaligned);
        assert_eq!(rm_ray_stack_init(base.add(4).cast()), RmStatus::Misaligned);
        let good = RmPathState::default();
        assert_eq!(
            rm_ray_stack_push(base.add(4).cast(), &good),
            RmStatus::Misaligned
        );
        let mut st = RmRayStack {
            entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
            len: 0,
        };
        assert_eq!(
            rm_ray_stack_push(&mut st, base.add(4).cast()),
            RmStatus::Misaligned
        );
        assert_eq!(st.len, 0);
        assert_eq!(
            rm_ray_stack_pop(&mut st, base.add(4).cast()),
            RmStatus::Misaligned
        );
        assert_eq!(
            rm_path_primary(1 << 20, 0, base.add(4).cast()),
            RmStatus::Misaligned
        );
        assert_eq!(rm_path_advance(base.add(4).cast(), 1), RmStatus::Misaligned);
        assert_eq!(rm_path_bounce(base.add(4).cast(), 1), RmStatus::Misaligned);
        assert_eq!(
            rm_mip_generate(base.add(2).cast(), 21, 4, 4, 3),
            RmStatus::Misaligned
        );
        let tri = RmTriangle {
            positions: [[0; 3]; 3],
            uvs: [[0; 2]; 3],
            tex_width: 1,
            tex_height: 1,
            textured: 0,
        };
        assert_eq!(
            rm_table_build(mis.cast(), 1, &tri, 1, 1 << 20, core::ptr::null_mut()),
            RmStatus::Misaligned
        );
        let mut e = [0i32; 1];
        assert_eq!(
            rm_table_build(
                e.as_mut_ptr(),
                1,
                base.add(4).cast(),
                1,
                1 << 20,
                core::ptr::null_mut()
            ),
            RmStatus::Misaligned
        );
        assert_eq!(
            rm_table_build(e.as_mut_ptr(), 1, &tri, 1, 1 << 20, base.add(2).cast()),
            RmStatus::Misaligned
        );
        let texels = [0u32; 1];
        let tex = RmTexture {
            texels: base.add(2).cast(),
            len: 1,
            width: 1,
            height: 1,
            levels: 1,
        };
        let wrap = RmAddressBits(RmAddress::Wrap as u8);
        let mut sm = RmSampler {
            opaque: [0; RM_SAMPLER_WORDS],
        };
        assert_eq!(rm_sampler_init(&mut sm, &tex, wrap), RmStatus::Misaligned);
        let tex_ok = RmTexture {
            texels: texels.as_ptr(),
            ..tex
        };
        assert_eq!(
            rm_sampler_init(base.add(4).cast(), &tex_ok, wrap),
            RmStatus::Misaligned
        );
        assert_eq!(
            rm_sampler_init(&mut sm, base.add(4).cast(), wrap),
            RmStatus::Misaligned
        );
        let tri = RmModeBits(RmMode::Trilinear as u8);
        let mut out = 0u32;
        assert_eq!(
            rm_sample(&mut sm, 0, 0, 0, tri, &mut out),
            RmStatus::Uninitialised
        );
        assert_eq!(rm_sampler_init(&mut sm, &tex_ok, wrap), RmStatus::Ok);
        assert_eq!(
            rm_sample(base.add(4).cast(), 0, 0, 0, tri, &mut out),
            RmStatus::Misaligned
        );
        assert_eq!(
            rm_sample(&mut sm, 0, 0, 0, tri, base.add(2).cast()),
            RmStatus::Misaligned
        );
        assert_eq!(rm_sample(&mut sm, 0, 0, 0, tri, &mut out), RmStatus::Ok);
    }
    assert!(
        raw.iter().all(|&x| x == 0),
        "a misaligned pointer was written through"
    );
}

proptest! {
    /// The C entry points agree with the Rust API for every input.
    #[test]
    fn c_lod_equals_rust_lod(pl in any::<u64>(), e in any::<i32>(), w in any::<i64>(), d in any::<i32>(), c in any::<u32>(), lod in any::<i16>(), levels in any::<u8>()) {
        let (s, out) = ok_lod(pl, e);
        match table_lod::<Accurate>(PathLength::from_bits(pl), Log2Pb::from_bits(e)) {
            Some(l) => prop_assert_eq!((s, out), (RmStatus::Ok, l.to_bits())),
            None => prop_assert_eq!((s, e), (RmStatus::Untextured, RM_UNTEXTURED)),
        }
        let want = cone_lod::<Accurate>(Width::from_bits(w), Delta::from_bits(d), Some(U1F31::from_bits(c)));
        prop_assert_eq!(rm_cone_lod(w, d, c), want.to_bits());
        prop_assert_eq!(rm_clamp_lod(lod, levels), clamp_lod(Lod::from_bits(lod), levels).to_bits());
    }

    /// A sampler set up once gives, sample after sample, the texel of
    /// the Rust `Sampler` built afresh for each sample (what `rm_sample`
    /// did before it took a set-up sampler); bad modes and addresses are
    /// `OutOfRange`.
    #[test]
    fn set_up_sampler_equals_fresh_rust_sampler(
        w in 1u32..9, h in 1u32..9, seed in any::<u64>(), address in 0u8..7,
        samples in proptest::collection::vec((any::<i64>(), any::<i64>(), -512i16..4096, 0u8..5), 1..24),
    ) {
        let levels = crate::texture::storage::mip::full_levels(w, h);
        let n = pyramid_len(w, h, levels);
        let texels = lcg_texels(seed, n);
        let tex = RmTexture { texels: texels.as_ptr(), len: n, width: w, height: h, levels };
        let mut sm = RmSampler { opaque: [0; RM_SAMPLER_WORDS] };
        // SAFETY: valid locals; `texels` outlives `sm`'s use.
        let st = unsafe { rm_sampler_init(&mut sm, &tex, RmAddressBits(address)) };
        let Some(addr) = RmAddress::mode(address) else {
            prop_assert_eq!(st, RmStatus::OutOfRange);
            return Ok(());
        };
        prop_assert_eq!(st, RmStatus::Ok);
        let g = Geometry::new(w, h, levels).unwrap();
        for (u, v, lod, mode) in samples {
            let mut out = 0u32;
            // SAFETY: `sm` set up above, `out` a valid local.
            let s = unsafe { rm_sample(&mut sm, u, v, lod, RmModeBits(mode), &mut out) };
            match Mode::from_index(mode) {
                Some(m) => {
                    let fresh = crate::texture::Sampler::with_address(Pyramid::new(g, &texels).unwrap(), addr)
                        .sample(TexCoord::from_bits(u), TexCoord::from_bits(v), Lod::from_bits(lod), m);
                    prop_assert_eq!((s, out), (RmStatus::Ok, fresh));
                }
                None => prop_assert_eq!(s, RmStatus::OutOfRange),
            }
        }
    }

    /// A sampler set up from an `RmSamplerDesc` (any address pair,
    /// border, bias, clamps, anisotropy, tier) samples, batches and
    /// filters anisotropically exactly as the Rust sampler of the same
    /// settings; out-of-range fields are `OutOfRange` and leave the
    /// sampler unchanged.
    #[test]
    fn desc_sampler_equals_rust(
        w in 1u32..17, h in 1u32..17, seed in any::<u64>(),
        au in 0u8..6, av in 0u8..6, border in any::<u32>(),
        bias in -5000i16..5000, lo in any::<i16>(), hi in any::<i16>(),
        aniso in 0u8..18, srgb_output in 0u8..3, precision in 0u8..3, mode in 0u8..4,
        samples in proptest::collection::vec((any::<i64>(), any::<i64>(), -512i16..4096, any::<[i32; 4]>()), 1..20),
    ) {
        let levels = crate::texture::storage::mip::full_levels(w, h);
        let n = pyramid_len(w, h, levels);
        let texels = lcg_texels(seed, n);
        let tex = RmTexture { texels: texels.as_ptr(), len: n, width: w, height: h, levels };
        let desc = RmSamplerDesc {
            border, lod_bias: bias, min_lod: lo, max_lod: hi,
            address_u: RmAddressBits(au), address_v: RmAddressBits(av),
            max_anisotropy: aniso, srgb_output, precision,
        };
        let mut sm = RmSampler { opaque: [0x77; RM_SAMPLER_WORDS] };
        // SAFETY: valid locals; `texels` outlives `sm`'s use.
        let st = unsafe { rm_sampler_init_desc(&mut sm, &tex, &desc) };
        // The Rust settings, built here from the C fields' documented meaning.
        let want = (|| {
            let state = SamplerState::new(SamplerDesc {
                address_u: RmAddress::mode(au)?,
                address_v: RmAddress::mode(av)?,
                border,
                lod_bias: Lod::from_bits(bias),
                min_lod: Lod::from_bits(lo),
                max_lod: Lod::from_bits(hi),
                max_anisotropy: aniso,
                srgb_output: [SrgbOutput::Encoded, SrgbOutput::Linear].get(usize::from(srgb_output)).copied()?,
            }).ok()?;
            let precision = [Precision::Accurate, Precision::Fast].get(usize::from(precision)).copied()?;
            Some((state, precision))
        })();
        let Some((state, prec)) = want else {
            prop_assert_eq!(st, RmStatus::OutOfRange);
            prop_assert!(sm.opaque.iter().all(|&x| x == 0x77), "a rejected set-up wrote the sampler");
            return Ok(());
        };
        prop_assert_eq!(st, RmStatus::Ok);
        let g = Geometry::new(w, h, levels).unwrap();
        let mut rust = DynSampler::new(Pyramid::new(g, &texels).unwrap(), state, ColorSpace::Linear, prec);
        let m = Mode::from_index(mode).unwrap();
        let hits: std::vec::Vec<RmHit> = samples.iter().map(|&(u, v, lod, _)| RmHit { u, v, lod }).collect();
        let mut batch = std::vec![0u32; hits.len()];
        // SAFETY: `sm` set up above; `hits` and `batch` valid, of length `hits.len()`.
        let sb = unsafe { rm_sample_batch(&mut sm, hits.as_ptr(), hits.len(), RmModeBits(mode), batch.as_mut_ptr()) };
        prop_assert_eq!(sb, RmStatus::Ok);
        for (i, &(u, v, lod, d)) in samples.iter().enumerate() {
            let (fu, fv) = (I32F32::from_bits(u), I32F32::from_bits(v));
            let want = rust.sample(TexCoord::from_fixed(fu), TexCoord::from_fixed(fv), Lod::from_bits(lod), m);
            let mut out = 0u32;
            // SAFETY: `sm` set up above, `out` a valid local.
            let s = unsafe { rm_sample(&mut sm, u, v, lod, RmModeBits(mode), &mut out) };
            prop_assert_eq!((s, out, batch[i]), (RmStatus::Ok, want, want));
            // Footprints up to ±8 texture widths per pixel.
            let [a, b, c, e] = d.map(|x| i64::from(x) << 3);
            let fp = RmFootprint { dudx: a, dvdx: b, dudy: c, dvdy: e };
            let want = rust.sample_aniso(TexCoord::from_fixed(fu), TexCoord::from_fixed(fv), &Footprint {
                x: [TexCoord::from_bits(a), TexCoord::from_bits(b)],
                y: [TexCoord::from_bits(c), TexCoord::from_bits(e)],
            });
            // SAFETY: as above; `fp` a valid local.
            let s = unsafe { rm_sample_aniso(&mut sm, u, v, &fp, &mut out) };
            prop_assert_eq!((s, out), (RmStatus::Ok, want));
        }
    }

    /// An image in any format and colour space samples exactly as the
    /// Rust sampler over the same `Image`; wrong formats, sRGB flags
    /// and short buffers are refused.
    #[test]
    fn image_sampler_equals_rust(
        w in 1u32..13, h in 1u32..13, seed in any::<u64>(), format in 0u8..12, srgb in 0u8..3,
        precision in 0u8..2, short in any::<bool>(),
        samples in proptest::collection::vec((any::<i64>(), any::<i64>(), -512i16..4096, 0u8..4), 1..16),
    ) {
        let levels = crate::texture::storage::mip::full_levels(w, h);
        let len = rm_image_len(w, h, levels, format);
        let words = lcg_texels(seed, len / 4 + 1);
        let bytes: std::vec::Vec<u8> = words.iter().flat_map(|x| x.to_le_bytes()).take(len).collect();
        let given = if short && len > 0 { len - 1 } else { len };
        let img = RmImage { bytes: bytes.as_ptr(), len: given, width: w, height: h, levels, format, srgb };
        let desc = RmSamplerDesc { precision, ..RmSamplerDesc::default() };
        let mut sm = RmSampler { opaque: [0; RM_SAMPLER_WORDS] };
        // SAFETY: valid locals; `bytes` outlives `sm`'s use.
        let st = unsafe { rm_sampler_init_image(&mut sm, &img, &desc) };
        let space = [ColorSpace::Linear, ColorSpace::Srgb].get(usize::from(srgb)).copied();
        let fmt = TexelFormat::from_index(format).zip(space).and_then(|(f, s)| Format::new(f, s).ok());
        let Some(fmt) = fmt else {
            prop_assert_eq!(st, RmStatus::OutOfRange);
            return Ok(());
        };
        if short {
            prop_assert_eq!(st, RmStatus::BufferTooShort);
            return Ok(());
        }
        prop_assert_eq!(st, RmStatus::Ok);
        let g = Geometry::new(w, h, levels).unwrap();
        let prec = [Precision::Accurate, Precision::Fast][usize::from(precision)];
        let state = SamplerState::new(SamplerDesc::default()).unwrap();
        let mut rust = DynSampler::new(Image::new(g, fmt, &bytes).unwrap(), state, fmt.space(), prec);
        for (u, v, lod, mode) in samples {
            let m = Mode::from_index(mode).unwrap();
            let want = rust.sample(TexCoord::from_bits(u), TexCoord::from_bits(v), Lod::from_bits(lod), m);
            let mut out = 0u32;
            // SAFETY: `sm` set up above, `out` a valid local.
            let s = unsafe { rm_sample(&mut sm, u, v, lod, RmModeBits(mode), &mut out) };
            prop_assert_eq!((s, out), (RmStatus::Ok, want));
        }
    }

    /// Path state round-trips and advances exactly as `PathState`.
    #[test]
    fn c_path_state_equals_rust(g in 1i32..i32::MAX, ts in proptest::collection::vec(any::<u64>(), 0..12), beta in any::<i32>()) {
        let mut c = RmPathState::default();
        // SAFETY: valid local.
        prop_assert_eq!(unsafe { rm_path_primary(g, 7, &mut c) }, RmStatus::Ok);
        let spread = PixelSpread::from_angle(Spread::from_bits(g)).unwrap();
        let mut r = PathState::primary(&spread, 7);
        for &t in &ts {
            // SAFETY: valid local.
            unsafe {
                rm_path_advance(&mut c, t);
                rm_path_bounce(&mut c, beta);
            }
            r = r.advance(PathLength::from_bits(t)).bounce(Spread::from_bits(beta));
            prop_assert_eq!(PathState::from(c), r);
        }
    }
}
