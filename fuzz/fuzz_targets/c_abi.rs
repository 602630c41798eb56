//! C ABI call sequences driven by arbitrary bytes, through the exported
//! `extern "C"` functions with caller pointers that are valid, null,
//! misaligned or aliased (a ray-stack entry pushed onto its own stack,
//! popped into its own slot), corrupt stack lengths and short buffers.
//! Each call is checked against the Rust API it wraps (same status, same
//! bits) and against its documented contract: a refused call writes
//! nothing. Built with AddressSanitizer (cargo-fuzz, or scripts/robustness with the same flags), so an out-of-bounds
//! access in the `unsafe` glue is a crash.
#![no_main]

mod common;

use fixed::types::U1F31;
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use raymip::ffi::*;
use raymip::lod::{clamp_lod, cone_lod, table_lod};
use raymip::path::raystack::PathState;
use raymip::setup::camera::PixelSpread;
use raymip::setup::table::PbTable;
use raymip::texture::storage::mip::{Geometry, Pyramid, generate, pyramid_len};
use raymip::texture::{Mode, Sampler};
use raymip::units::{Accurate, Delta, Lod, Log2Pb, PathLength, Spread, TexCoord, Width};

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let mut stack = RmRayStack {
        entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
        len: 0,
    };
    // SAFETY: a valid local.
    assert_eq!(unsafe { rm_ray_stack_init(&mut stack) }, RmStatus::Ok);
    let mut model: Vec<RmPathState> = Vec::new();
    while !u.is_empty() {
        if step(&mut u, &mut stack, &mut model).is_err() {
            break;
        }
    }
});

/// A buffer of 8-byte-aligned storage to carve misaligned pointers from.
struct Raw([u64; 40]);

impl Raw {
    fn misaligned<T>(&mut self, u: &mut Unstructured) -> Result<*mut T> {
        let align = core::mem::align_of::<T>();
        assert!(align > 1);
        let off = u.int_in_range(1..=align - 1)?;
        // SAFETY: the offset stays inside the buffer.
        Ok(unsafe { self.0.as_mut_ptr().cast::<u8>().add(off) }.cast())
    }

    fn untouched(&self) -> bool {
        self.0.iter().all(|&x| x == 0)
    }
}

fn rm_triangle(u: &mut Unstructured) -> Result<RmTriangle> {
    let mut t = RmTriangle {
        positions: [[0; 3]; 3],
        uvs: [[0; 2]; 3],
        tex_width: u.arbitrary()?,
        tex_height: u.arbitrary()?,
        textured: u.arbitrary()?,
    };
    for v in t
        .positions
        .iter_mut()
        .flatten()
        .chain(t.uvs.iter_mut().flatten())
    {
        *v = if u.ratio(3, 4)? {
            i64::from(u.arbitrary::<i32>()?) << u.int_in_range(0..=24)?
        } else {
            u.arbitrary()?
        };
    }
    Ok(t)
}

fn step(u: &mut Unstructured, stack: &mut RmRayStack, model: &mut Vec<RmPathState>) -> Result<()> {
    let mut raw = Raw([0; 40]);
    match u.int_in_range(0..=6u8)? {
        0 => {
            // rm_table_update against PbTable::update.
            let len = u.int_in_range(0..=8usize)?;
            let start = u.int_in_range(0..=10usize)?;
            let count = u.int_in_range(0..=6usize)?;
            let spread = u.arbitrary::<i32>()?;
            let tris = (0..count)
                .map(|_| rm_triangle(u))
                .collect::<Result<Vec<_>>>()?;
            let mut entries = vec![0x5A5A_5A5Ai32; len];
            let mut stats = RmBuildStats::default();
            // rm_table_update of these lengths, `start` and `spread` on the
            // given entry and triangle pointers.
            let mut update = |entries: *mut i32, tris: *const RmTriangle| {
                // SAFETY: each call below states its pointers.
                unsafe { rm_table_update(entries, len, start, tris, count, spread, &mut stats) }
            };
            match u.int_in_range(0..=3u8)? {
                0 if len > 0 => {
                    // A misaligned pointer: must be refused unread.
                    let s = update(raw.misaligned(u)?, tris.as_ptr());
                    assert_eq!(s, RmStatus::Misaligned);
                    assert!(raw.untouched());
                    return Ok(());
                }
                1 if count > 0 => {
                    // Null triangles with a count: must be refused.
                    let s = update(entries.as_mut_ptr(), core::ptr::null());
                    assert_eq!(s, RmStatus::NullPointer);
                    return Ok(());
                }
                _ => {}
            }
            // Valid buffers of the stated lengths.
            let s = update(entries.as_mut_ptr(), tris.as_ptr());
            let Ok(sp) = PixelSpread::from_angle(Spread::from_bits(spread)) else {
                assert_eq!(s, RmStatus::BadAngle);
                assert!(entries.iter().all(|&e| e == 0x5A5A_5A5A));
                return Ok(());
            };
            // The Rust API on the triangles up to the first invalid one.
            let mut rust = vec![Log2Pb::UNTEXTURED; len];
            let valid: Vec<_> = tris.iter().map_while(|t| t.tex_triangle().ok()).collect();
            let r = PbTable::new(&mut rust).update(start, valid.iter().copied(), &sp);
            for (i, (&c, r)) in entries.iter().zip(&rust).enumerate() {
                if i >= start && i - start < valid.len() {
                    assert_eq!(c, r.to_i16f16().to_bits(), "entry {i}");
                } else {
                    assert_eq!(c, 0x5A5A_5A5A, "entry {i} outside the update was written");
                }
            }
            // Items in order: the first one without a slot gives TableFull,
            // the first invalid one (zero texture side) ZeroSize.
            let slots = len.saturating_sub(start);
            let want = if valid.len() < tris.len().min(slots) {
                RmStatus::ZeroSize
            } else if tris.len() > slots {
                RmStatus::TableFull
            } else {
                RmStatus::Ok
            };
            assert_eq!(s, want);
            assert_eq!(r.is_ok(), valid.len() <= slots);
        }
        1 => {
            // Lods.
            let (pl, e, w, d, c, lod, levels) = (
                u.arbitrary::<u64>()?,
                u.arbitrary::<i32>()?,
                u.arbitrary::<i64>()?,
                u.arbitrary::<i32>()?,
                u.arbitrary::<u32>()?,
                u.arbitrary::<i16>()?,
                u.arbitrary::<u8>()?,
            );
            let mut out = 0x7777i16;
            // SAFETY: valid local.
            let s = unsafe { rm_table_lod(pl, e, &mut out) };
            match table_lod::<Accurate>(PathLength::from_bits(pl), Log2Pb::from_bits(e)) {
                Some(l) => assert_eq!((s, out), (RmStatus::Ok, l.to_bits())),
                None => assert_eq!((s, out), (RmStatus::Untextured, 0x7777)),
            }
            // SAFETY: misaligned pointer: refused unwritten.
            assert_eq!(
                unsafe { rm_table_lod(pl, e, raw.misaligned(u)?) },
                RmStatus::Misaligned
            );
            assert!(raw.untouched());
            let want = cone_lod::<Accurate>(
                Width::from_bits(w),
                Delta::from_bits(d),
                Some(U1F31::from_bits(c)),
            );
            assert_eq!(rm_cone_lod(w, d, c), want.to_bits());
            assert_eq!(
                rm_clamp_lod(lod, levels),
                clamp_lod(Lod::from_bits(lod), levels).to_bits()
            );
        }
        2 => {
            // Push: a fresh state, an entry of the same stack, null or misaligned.
            let before = *stack;
            let which = u.int_in_range(0..=3u8)?;
            let (s, pushed) = match which {
                0 => {
                    let mut st = RmPathState::default();
                    // SAFETY: valid locals.
                    let p = unsafe { rm_path_primary(u.arbitrary()?, u.arbitrary()?, &mut st) };
                    if p != RmStatus::Ok {
                        assert_eq!(p, RmStatus::BadAngle);
                        return Ok(());
                    }
                    for _ in 0..u.int_in_range(0..=11)? {
                        let r = PathState::from(st);
                        let (t, b) = (u.arbitrary::<u64>()?, u.arbitrary::<i32>()?);
                        // SAFETY: valid local.
                        unsafe {
                            assert_eq!(rm_path_advance(&mut st, t), RmStatus::Ok);
                            assert_eq!(rm_path_bounce(&mut st, b), RmStatus::Ok);
                        }
                        assert_eq!(
                            PathState::from(st),
                            r.advance(PathLength::from_bits(t))
                                .bounce(Spread::from_bits(b))
                        );
                    }
                    // SAFETY: valid locals.
                    (unsafe { rm_ray_stack_push(stack, &st) }, Some(st))
                }
                1 if !model.is_empty() => {
                    let i = u.int_in_range(0..=model.len() - 1)?;
                    let p: *mut RmRayStack = stack;
                    // SAFETY: `state` points into the stack itself (allowed).
                    let s = unsafe { rm_ray_stack_push(p, core::ptr::addr_of!((*p).entries[i])) };
                    (s, Some(model[i]))
                }
                2 => {
                    // SAFETY: null state: refused.
                    let s = unsafe { rm_ray_stack_push(stack, core::ptr::null()) };
                    assert_eq!(s, RmStatus::NullPointer);
                    (s, None)
                }
                _ => {
                    // SAFETY: misaligned state: refused unread.
                    let s = unsafe { rm_ray_stack_push(stack, raw.misaligned(u)?) };
                    assert_eq!(s, RmStatus::Misaligned);
                    (s, None)
                }
            };
            match (s, pushed) {
                (RmStatus::Ok, Some(st)) => {
                    assert!(model.len() < RM_RAY_STACK_CAPACITY);
                    model.push(st);
                }
                (RmStatus::StackFull, Some(_)) => {
                    assert_eq!(model.len(), RM_RAY_STACK_CAPACITY);
                    assert_eq!(*stack, before);
                }
                (_, None) => assert_eq!(*stack, before),
                (other, _) => panic!("push: {other:?}"),
            }
            assert_eq!(stack.len as usize, model.len());
        }
        3 => {
            // Pop: into a local, into the stack's own top slot, or misaligned.
            let p: *mut RmRayStack = stack;
            let top = model.len().checked_sub(1);
            let own = u.arbitrary::<bool>()?;
            let mut out = RmPathState::default();
            let dst: *mut RmPathState = match (own, top) {
                // SAFETY: inside the stack.
                (true, Some(i)) => unsafe { core::ptr::addr_of_mut!((*p).entries[i]) },
                _ => &mut out,
            };
            if u.ratio(1, 6)? {
                // SAFETY: misaligned out: refused, the stack unchanged.
                let s = unsafe { rm_ray_stack_pop(p, raw.misaligned(u)?) };
                assert_eq!(s, RmStatus::Misaligned);
                assert!(raw.untouched());
                return Ok(());
            }
            // SAFETY: valid pointers (dst may alias the stack: allowed).
            let s = unsafe { rm_ray_stack_pop(p, dst) };
            // SAFETY: dst is valid.
            let got = unsafe { dst.read() };
            match model.pop() {
                Some(want) => assert_eq!((s, got), (RmStatus::Ok, want)),
                None => assert_eq!(s, RmStatus::StackEmpty),
            }
            assert_eq!(stack.len as usize, model.len());
        }
        4 => {
            // Corrupt length: read as full, pops stay in range.
            let len = u.arbitrary::<u32>()?;
            stack.len = len;
            let mut out = RmPathState::default();
            // SAFETY: valid locals.
            let s = unsafe { rm_ray_stack_pop(stack, &mut out) };
            if len == 0 {
                assert_eq!(s, RmStatus::StackEmpty);
            } else {
                assert_eq!(s, RmStatus::Ok);
                assert!((stack.len as usize) < RM_RAY_STACK_CAPACITY);
            }
            // Resynchronise the model with what the stack now holds.
            model.clear();
            model.extend_from_slice(&stack.entries[..stack.len as usize]);
        }
        _ => pyramid(u, &mut raw)?,
    }
    Ok(())
}

fn pyramid(u: &mut Unstructured, raw: &mut Raw) -> Result<()> {
    let (w, h, levels) = common::pyramid_shape(u, 24)?;
    let n = rm_pyramid_len(w, h, levels);
    assert_eq!(n, pyramid_len(w, h, levels));
    if n > 4096 {
        return Ok(());
    }
    let len = n.saturating_sub(u.int_in_range(0..=1usize)?);
    let mut buf: Vec<u32> = (0..len)
        .map(|i| (i as u32).wrapping_mul(0x9E37_79B9))
        .collect();
    for t in buf.iter_mut().take(32) {
        *t = u.arbitrary()?;
    }
    let mut rust = buf.clone();
    // SAFETY: `buf` holds `len` texels.
    let s = unsafe { rm_mip_generate(buf.as_mut_ptr(), len, w, h, levels) };
    let r = Geometry::new(w, h, levels).and_then(|g| generate(&g, &mut rust).map(|()| g));
    assert_eq!(buf, rust, "C and Rust generation differ");
    let Ok(g) = r else {
        assert_ne!(s, RmStatus::Ok);
        return Ok(());
    };
    assert_eq!(s, RmStatus::Ok);
    // SAFETY: misaligned texels: refused unwritten.
    assert_eq!(
        unsafe { rm_mip_generate(raw.misaligned(u)?, 4, 2, 2, 1) },
        RmStatus::Misaligned
    );
    assert!(raw.untouched());
    let tex = RmTexture {
        texels: buf.as_ptr(),
        len: u
            .int_in_range(0..=len)?
            .max(if u.ratio(7, 8)? { len } else { 0 }),
        width: w,
        height: h,
        levels,
    };
    // One sampler set up for the texture, then up to 8 samples through it.
    // 0..=4 name the five modes (`RmAddress`), 5 is out of range.
    let address = u.int_in_range(0..=5u8)?;
    let mut sm = RmSampler {
        opaque: [0; RM_SAMPLER_WORDS],
    };
    // SAFETY: valid texture (outlives `sm`) and sampler storage.
    let init = unsafe { rm_sampler_init(&mut sm, &tex, RmAddressBits(address)) };
    let p = match (RmAddress::mode(address), Pyramid::new(g, &buf[..tex.len])) {
        (Some(a), Ok(p)) => {
            assert_eq!(init, RmStatus::Ok);
            (a, p)
        }
        (Some(_), Err(_)) => {
            assert_eq!(init, RmStatus::BufferTooShort);
            return Ok(());
        }
        (None, _) => {
            assert_eq!(init, RmStatus::OutOfRange);
            return Ok(());
        }
    };
    for _ in 0..u.int_in_range(1..=8)? {
        let (uu, vv, lod) = (
            u.arbitrary::<i64>()?,
            u.arbitrary::<i64>()?,
            u.arbitrary::<i16>()?,
        );
        let mode = u.int_in_range(0..=4u8)?;
        let mut out = 0xDEAD_BEEFu32;
        // SAFETY: `sm` set up above, valid out.
        let s = unsafe { rm_sample(&mut sm, uu, vv, lod, RmModeBits(mode), &mut out) };
        match Mode::from_index(mode) {
            Some(m) => {
                // A Rust sampler built afresh for every sample.
                let want = Sampler::with_address(p.1, p.0).sample(
                    TexCoord::from_bits(uu),
                    TexCoord::from_bits(vv),
                    Lod::from_bits(lod),
                    m,
                );
                assert_eq!((s, out), (RmStatus::Ok, want));
            }
            None => assert_eq!((s, out), (RmStatus::OutOfRange, 0xDEAD_BEEF)),
        }
    }
    Ok(())
}
