//! C ABI edges: bad pointers, sizes, modes and stack lengths.

use fixed::types::{I8F8, U1F31};
use raymip::ffi::{
    self, RM_UNTEXTURED, RmAddressBits, RmModeBits, RmPathState, RmRayStack, RmSampler, RmStatus,
    RmTexture,
};
use raymip::lod::cone_lod;
use raymip::texture::storage::mip::{Geometry, generate};
use raymip::units::{Accurate, Delta, Width};

use super::setup::spread;
use super::texture::{in_range, texels_for};
use super::{Runner, bad, clamp, err, refused};

#[allow(unsafe_code)]
pub(super) fn c_abi(r: &mut Runner) {
    let sp = spread().angle().to_bits();
    r.case("null entries, len 4", "C ABI: rm_table_build", move || {
        // SAFETY: null is a documented input.
        let s = unsafe { build_empty(std::ptr::null_mut(), 4, sp) };
        refused(s, RmStatus::NullPointer, true, "NullPointer")
    });
    r.case("misaligned entries", "C ABI: rm_table_build", move || {
        let mut raw = [0i32; 4];
        let p = raw.as_mut_ptr().cast::<u8>().wrapping_add(1).cast::<i32>();
        // SAFETY: the misaligned pointer is refused before any access.
        let s = unsafe { build_empty(p, 2, sp) };
        refused(
            s,
            RmStatus::Misaligned,
            raw == [0; 4],
            "Misaligned, nothing written",
        )
    });
    for (name, bad) in [("spread 0", 0), ("spread i32::MIN", i32::MIN)] {
        r.case(name, "C ABI: rm_table_build", move || {
            let mut e = [0i32; 1];
            // SAFETY: valid pointer, one entry.
            let s = unsafe { build_empty(e.as_mut_ptr(), 1, bad) };
            refused(s, RmStatus::BadAngle, true, "BadAngle")
        });
    }
    r.case("untextured entry, null out", "C ABI: rm_table_lod", || {
        let mut out = 77i16;
        // SAFETY: valid or null pointers.
        let a = unsafe { ffi::rm_table_lod(1 << 32, RM_UNTEXTURED, &mut out) };
        let b = unsafe { ffi::rm_table_lod(1 << 32, 0, std::ptr::null_mut()) };
        if a == RmStatus::Untextured && out == 77 && b == RmStatus::NullPointer {
            err("Untextured (out untouched); NullPointer")
        } else {
            bad(format!("{a:?} {out} {b:?}"))
        }
    });
}

#[allow(unsafe_code)]
pub(super) fn c_abi_lod(r: &mut Runner) {
    r.case(
        "grazing n·d = 0, extreme width and Δ",
        "C ABI: rm_cone_lod",
        || {
            for w in [0i64, 1, i64::MIN, i64::MAX] {
                for d in [i32::MIN, 0, i32::MAX] {
                    for c in [0u32, 1, 1 << 15, u32::MAX] {
                        let got = ffi::rm_cone_lod(w, d, c);
                        let rust = cone_lod::<Accurate>(
                            Width::from_bits(w),
                            Delta::from_bits(d),
                            Some(U1F31::from_bits(c)),
                        );
                        if got != rust.to_bits() {
                            return bad(format!(
                                "w {w} Δ {d} n·d {c}: C {got} vs Rust {}",
                                rust.to_bits()
                            ));
                        }
                    }
                }
            }
            clamp("C equals Rust on 48 extreme triples (n·d clamped to 2^-16)")
        },
    );
    r.case(
        "lod i16::MIN/MAX, 0 and 255 levels",
        "C ABI: rm_clamp_lod",
        || {
            let a = ffi::rm_clamp_lod(i16::MIN, 0);
            let b = ffi::rm_clamp_lod(i16::MAX, 255);
            let want_b = I8F8::from_num(127).to_bits();
            if a == 0 && b == want_b {
                clamp(format!("{a}, {b}"))
            } else {
                bad(format!("{a}, {b}"))
            }
        },
    );
    r.case(
        "sides u32::MAX, 255 levels",
        "C ABI: rm_pyramid_len",
        || {
            let n = ffi::rm_pyramid_len(u32::MAX, u32::MAX, 255);
            if n == usize::MAX {
                clamp("usize::MAX")
            } else {
                bad(format!("{n}"))
            }
        },
    );
    r.case("storage one texel short", "C ABI: rm_mip_generate", || {
        let g = Geometry::new(64, 32, 7).map_err(|e| e.to_string())?;
        let mut buf = texels_for(&g);
        buf.pop();
        let before = buf.clone();
        // SAFETY: `buf` holds `len` texels.
        let s = unsafe { ffi::rm_mip_generate(buf.as_mut_ptr(), buf.len(), 64, 32, 7) };
        refused(
            s,
            RmStatus::BufferTooShort,
            buf == before,
            "BufferTooShort, buffer untouched",
        )
    });
}

/// Sets up a C ABI sampler for `tex` with addressing `address` and, if that
/// succeeds, samples it once at `(u, u)`, lod `lod`, filter `mode`.
#[allow(unsafe_code)]
pub(super) fn sample_once(
    tex: &RmTexture,
    u: i64,
    lod: i16,
    mode: u8,
    address: u8,
    out: &mut u32,
) -> RmStatus {
    let mut sm = RmSampler {
        opaque: [0; ffi::RM_SAMPLER_WORDS],
    };
    // SAFETY: `tex` describes a live buffer that outlives `sm`; `sm` and
    // `out` are writable locals.
    unsafe {
        match ffi::rm_sampler_init(&mut sm, tex, RmAddressBits(address)) {
            RmStatus::Ok => ffi::rm_sample(&mut sm, u, u, lod, RmModeBits(mode), out),
            s => s,
        }
    }
}

pub(super) fn c_abi_sample(r: &mut Runner) {
    let g = Geometry::new(8, 8, 4).expect("8×8");
    let mut tex_buf = texels_for(&g);
    generate(&g, &mut tex_buf).expect("exact");
    let tex = RmTexture {
        texels: tex_buf.as_ptr(),
        len: tex_buf.len(),
        width: 8,
        height: 8,
        levels: 4,
    };
    for (name, u, lod, mode, address, want) in [
        (
            "mode 255",
            0i64,
            0i16,
            255u8,
            0u8,
            Some(RmStatus::OutOfRange),
        ),
        ("address 255", 0, 0, 0, 255, Some(RmStatus::OutOfRange)),
        ("u,v i64::MIN, lod i16::MIN", i64::MIN, i16::MIN, 0, 0, None),
        ("u,v i64::MAX, lod i16::MAX", i64::MAX, i16::MAX, 3, 1, None),
    ] {
        r.case(name, "C ABI: rm_sampler_init/rm_sample", move || {
            let mut out = 0u32;
            let s = sample_once(&tex, u, lod, mode, address, &mut out);
            match (s, want) {
                (s, Some(w)) if s == w && out == 0 => err(format!("{s:?}, nothing written")),
                (RmStatus::Ok, None) if in_range(out) => clamp("a texel in range"),
                o => bad(format!("{o:?} {out:08x}")),
            }
        });
    }
    r.case(
        "texture len one texel short",
        "C ABI: rm_sampler_init/rm_sample",
        move || {
            let short = RmTexture {
                len: tex.len - 1,
                ..tex
            };
            let mut out = 0u32;
            let s = sample_once(&short, 0, 0, 0, 0, &mut out);
            refused(s, RmStatus::BufferTooShort, out == 0, "BufferTooShort")
        },
    );
    r.case(
        "push capacity + 1, pop capacity + 1",
        "C ABI: rm_ray_stack_push/pop",
        || {
            let mut st = RmRayStack {
                entries: [RmPathState::default(); ffi::RM_RAY_STACK_CAPACITY],
                len: 0,
            };
            let mut pushed = Vec::new();
            for d in 0..=ffi::RM_RAY_STACK_CAPACITY as u8 {
                let e = RmPathState {
                    depth: d,
                    pl: u64::from(d) << 32,
                    ..RmPathState::default()
                };
                // SAFETY: valid pointers.
                pushed.push(unsafe { ffi::rm_ray_stack_push(&mut st, &e) });
            }
            let mut popped = Vec::new();
            let mut out = RmPathState::default();
            // SAFETY: valid pointers.
            while unsafe { ffi::rm_ray_stack_pop(&mut st, &mut out) } == RmStatus::Ok {
                popped.push(out.depth);
            }
            let want: Vec<u8> = (0..ffi::RM_RAY_STACK_CAPACITY as u8).rev().collect();
            if pushed.last() == Some(&RmStatus::StackFull) && popped == want {
                err(format!(
                    "StackFull on push {}; {} entries kept, LIFO",
                    ffi::RM_RAY_STACK_CAPACITY + 1,
                    ffi::RM_RAY_STACK_CAPACITY
                ))
            } else {
                bad(format!("{pushed:?} {popped:?}"))
            }
        },
    );
}

#[allow(unsafe_code)]
pub(super) fn c_abi_stack(r: &mut Runner) {
    let sp = spread().angle().to_bits();
    r.case(
        "corrupt len u32::MAX",
        "C ABI: rm_ray_stack_push/pop",
        || {
            let mut st = RmRayStack {
                entries: [RmPathState::default(); ffi::RM_RAY_STACK_CAPACITY],
                len: u32::MAX,
            };
            let e = RmPathState::default();
            let mut out = RmPathState {
                depth: 7,
                ..RmPathState::default()
            };
            // SAFETY: valid pointers; the length is corrupt on purpose.
            let a = unsafe { ffi::rm_ray_stack_push(&mut st, &e) };
            let b = unsafe { ffi::rm_ray_stack_pop(&mut st, &mut out) };
            if a == RmStatus::StackFull
                && b == RmStatus::Ok
                && st.len as usize == ffi::RM_RAY_STACK_CAPACITY - 1
            {
                clamp("read as full: push StackFull, pop the top entry")
            } else {
                bad(format!("{a:?} {b:?} len {}", st.len))
            }
        },
    );
    r.case(
        "spread 0, t = u64::MAX × 12",
        "C ABI: rm_path_primary/advance",
        || {
            let mut s = RmPathState::default();
            // SAFETY: valid pointers.
            let a = unsafe { ffi::rm_path_primary(0, 1, &mut s) };
            let b = unsafe { ffi::rm_path_primary(sp, 1, &mut s) };
            for _ in 0..12 {
                // SAFETY: valid pointer.
                unsafe { ffi::rm_path_advance(&mut s, u64::MAX) };
            }
            if a == RmStatus::BadAngle && b == RmStatus::Ok && s.pl == u64::MAX && s.saturated != 0
            {
                clamp("BadAngle; Pl saturated at MAX, flagged")
            } else {
                bad(format!("{a:?} {b:?} {s:?}"))
            }
        },
    );
}

/// `rm_table_build` of `len` entries at `entries` from no triangles, no
/// statistics.
///
/// # Safety
/// `entries` is null, misaligned (both refused before any access) or valid
/// for `len` writes.
#[allow(unsafe_code)]
unsafe fn build_empty(entries: *mut i32, len: usize, spread: i32) -> RmStatus {
    // SAFETY: `entries` as this function's contract; no triangles, no stats.
    unsafe {
        ffi::rm_table_build(
            entries,
            len,
            std::ptr::null(),
            0,
            spread,
            std::ptr::null_mut(),
        )
    }
}
