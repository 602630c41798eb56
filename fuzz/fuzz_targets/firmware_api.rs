//! Firmware API sequences driven by arbitrary bytes: table build and update,
//! ray stack push/pop to overflow and back, table and cone lod, pyramid
//! generation and sampling with arbitrary sizes, coordinates, lods, modes
//! and addressing. Besides "never panics, never overflows" (the fuzz build
//! has overflow checks and debug assertions on) each step checks what the
//! API documents: untouched entries stay untouched, LIFO order, the rejected
//! state handed back, lods inside the clamp, a cached sampler equal to the
//! direct one, a short buffer left unwritten.
#![no_main]

mod common;

use fixed::types::{I16F16, I32F32, U1F31};
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use raymip::lod::{clamp_lod, cone_lod, table_lod};
use raymip::path::raystack::{PathState, RayStack};
use raymip::setup::camera::PixelSpread;
use raymip::setup::table::{PbTable, TableError, TexTriangle};
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::mip::{Geometry, MipError, Pyramid, generate, pyramid_len};
use raymip::texture::{AddressMode, Mode, Sampler};
use raymip::units::{Accurate, Coord, Delta, Lod, Log2Pb, PathLength, Spread, TexCoord, Width};

const TABLE: usize = 8;
const STACK: usize = 4;

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let mut entries = [Log2Pb::UNTEXTURED; TABLE];
    let mut stack = RayStack::<(), STACK>::new();
    let mut model: Vec<PathState> = Vec::new();
    while !u.is_empty() {
        if step(&mut u, &mut entries, &mut stack, &mut model).is_err() {
            break;
        }
    }
});

fn coord(u: &mut Unstructured) -> Result<I32F32> {
    // Mostly small coordinates (areas that do not saturate), sometimes any.
    Ok(if u.ratio(3, 4)? {
        I32F32::from_bits(i64::from(u.arbitrary::<i32>()?) << u.int_in_range(0..=24)?)
    } else {
        I32F32::from_bits(u.arbitrary()?)
    })
}

fn triangle(u: &mut Unstructured) -> Result<Option<core::result::Result<TexTriangle, TableError>>> {
    if u.ratio(1, 5)? {
        return Ok(None);
    }
    let mut p = [[Coord::ZERO; 3]; 3];
    let mut uv = [[TexCoord::ZERO; 2]; 3];
    for v in &mut p {
        for c in v.iter_mut() {
            *c = Coord::from_fixed(coord(u)?);
        }
    }
    for v in &mut uv {
        for c in v.iter_mut() {
            *c = TexCoord::from_fixed(coord(u)?);
        }
    }
    let w = u.arbitrary::<u32>()?;
    let h = u.arbitrary::<u32>()?;
    let t = TexTriangle::new(p, uv, w, h);
    assert_eq!(t.is_err(), w == 0 || h == 0);
    Ok(Some(t))
}

fn path_state(u: &mut Unstructured) -> Result<PathState> {
    let spread = PixelSpread::from_angle(Spread::from_bits(u.int_in_range(1..=i32::MAX)?))
        .expect("positive angle");
    let mut s = PathState::primary(&spread, u.arbitrary()?);
    for _ in 0..u.int_in_range(0..=12)? {
        let before = s;
        s = s
            .advance(PathLength::from_bits(u.arbitrary()?))
            .bounce(Spread::from_bits(u.arbitrary()?));
        assert!(s.pl >= before.pl, "Pl never decreases");
        assert!(s.saturated >= before.saturated, "saturation is sticky");
        assert_eq!(s.depth, before.depth.saturating_add(1));
    }
    Ok(s)
}

fn step(
    u: &mut Unstructured,
    entries: &mut [Log2Pb; TABLE],
    stack: &mut RayStack<(), STACK>,
    model: &mut Vec<PathState>,
) -> Result<()> {
    match u.int_in_range(0..=4u8)? {
        0 => {
            // Table build/update at an arbitrary start.
            let start = u.int_in_range(0..=TABLE + 2)?;
            let n = u.int_in_range(0..=TABLE)?;
            let angle = fixed::types::I2F30::from_bits(u.arbitrary()?);
            let Ok(spread) = PixelSpread::from_angle(Spread::from_fixed(angle)) else {
                assert!(angle <= fixed::types::I2F30::ZERO);
                return Ok(());
            };
            let mut tris = Vec::new();
            for _ in 0..n {
                match triangle(u)? {
                    None => tris.push(None),
                    Some(Ok(t)) => tris.push(Some(t)),
                    Some(Err(_)) => {}
                }
            }
            let before = *entries;
            let r = PbTable::new(entries).update(start, tris.iter().copied(), &spread);
            // No items: nothing past the end, Ok whatever the start.
            let fits = tris.is_empty() || start + tris.len() <= TABLE;
            match r {
                Ok(st) => {
                    assert!(fits);
                    let total =
                        st.textured + st.untextured + st.degenerate_geometry + st.degenerate_uv;
                    assert_eq!(total as usize, tris.len());
                }
                Err(e) => assert!(e == TableError::TableFull && !fits, "{e:?}"),
            }
            for (i, (a, b)) in before.iter().zip(entries.iter()).enumerate() {
                if i < start || i >= start + tris.len() {
                    assert_eq!(a, b, "entry {i} outside the update changed");
                }
            }
            for (k, t) in tris.iter().enumerate() {
                let Some(&e) = entries.get(start + k) else {
                    break;
                };
                match t {
                    None => assert!(e.is_untextured()),
                    Some(t) => assert_eq!(e, Log2Pb::compute(t, &spread)),
                }
                if !e.is_untextured() {
                    let v = e.to_i16f16();
                    assert!(
                        v >= Log2Pb::DEGENERATE_GEOMETRY.to_i16f16()
                            && v <= Log2Pb::DEGENERATE_UV.to_i16f16()
                    );
                }
            }
        }
        1 => {
            // Ray stack: push to overflow and pop back, against a Vec model.
            let pushes = u.int_in_range(0..=STACK + 3)?;
            for _ in 0..pushes {
                let s = path_state(u)?;
                match stack.push(s) {
                    Ok(()) => model.push(s),
                    Err(full) => {
                        assert_eq!(model.len(), STACK);
                        assert_eq!(full.0, s, "the rejected state is handed back");
                    }
                }
                assert_eq!(stack.len(), model.len());
            }
            for _ in 0..u.int_in_range(0..=STACK + 3)? {
                assert_eq!(stack.pop(), model.pop());
            }
            assert_eq!(stack.peek(), model.last());
        }
        2 => {
            // Table and cone lod over raw bit patterns.
            let pl = PathLength::from_bits(u.arbitrary()?);
            let e = Log2Pb::from_bits(u.arbitrary()?);
            let levels = u.arbitrary::<u8>()?;
            match table_lod::<Accurate>(pl, e) {
                None => assert!(e.is_untextured()),
                Some(l) => {
                    let l2 = table_lod::<Accurate>(
                        PathLength::from_bits(pl.to_bits().saturating_add(1)),
                        e,
                    )
                    .unwrap();
                    assert!(l <= l2, "table lod monotonic in Pl");
                    check_clamped(l, levels);
                }
            }
            let w = Width::from_bits(u.arbitrary()?);
            let d = I16F16::from_bits(u.arbitrary()?);
            let c = U1F31::from_bits(u.arbitrary()?);
            let l = cone_lod::<Accurate>(w, Delta::from_fixed(d), Some(c));
            let none = cone_lod::<Accurate>(w, Delta::from_fixed(d), None);
            assert!(l >= none, "the normal term never makes the lod finer");
            assert_eq!(
                none,
                cone_lod::<Accurate>(w, Delta::from_fixed(d), Some(U1F31::from_bits(1 << 31)))
            );
            check_clamped(l, levels);
        }
        _ => pyramid(u)?,
    }
    Ok(())
}

fn check_clamped(l: Lod, levels: u8) {
    let c = clamp_lod(l, levels);
    let top = i16::from(levels.clamp(1, 128) - 1) << 8;
    assert!(c.to_bits() >= 0 && c.to_bits() <= top);
}

fn pyramid(u: &mut Unstructured) -> Result<()> {
    let (w, h, levels) = common::pyramid_shape(u, 40)?;
    let want = pyramid_len(w, h, levels);
    let g = match Geometry::new(w, h, levels) {
        Ok(g) => g,
        Err(MipError::ZeroSize) => {
            assert!(w == 0 || h == 0);
            return Ok(());
        }
        Err(_) => return Ok(()),
    };
    assert_eq!(g.len(), want);
    if want > 1 << 16 {
        // Valid but too big to generate per fuzz input (sizes up to
        // MAX_SIZE are covered by the unit tests).
        return Ok(());
    }
    // The buffer: the exact length, or one texel short (must be refused).
    let short = u.ratio(1, 8)?;
    let len = if short { want - 1 } else { want };
    let mut buf: Vec<u32> = (0..len)
        .map(|i| (i as u32).wrapping_mul(0x9E37_79B9))
        .collect();
    for t in buf.iter_mut().take(64) {
        *t = u.arbitrary()?;
    }
    let before = buf.clone();
    match generate(&g, &mut buf) {
        Ok(()) => assert!(!short),
        Err(MipError::BufferTooShort { needed, got }) => {
            assert!(short && needed == want && got == len);
            assert_eq!(buf, before, "a refused buffer is not written");
            assert!(Pyramid::new(g, &buf).is_err());
            return Ok(());
        }
        Err(e) => panic!("generate: {e:?}"),
    }
    let pyr = Pyramid::new(g, &buf).expect("exact length");
    let mut direct = Sampler::with_address(pyr, AddressMode::Wrap);
    let mut cached = Sampler::with_address(TexelCache::<_, 4, 2>::new(pyr), AddressMode::Wrap);
    for _ in 0..u.int_in_range(1..=16)? {
        let address = if u.arbitrary()? {
            AddressMode::Wrap
        } else {
            AddressMode::ClampToEdge
        };
        direct = Sampler::with_address(direct.into_source(), address);
        cached = Sampler::with_address(cached.into_source(), address);
        let uu = I32F32::from_bits(u.arbitrary()?);
        let vv = I32F32::from_bits(u.arbitrary()?);
        let lod = Lod::from_bits(u.arbitrary()?);
        let Some(mode) = Mode::from_index(u.int_in_range(0..=4)?) else {
            continue;
        };
        let a = direct.sample(
            TexCoord::from_fixed(uu),
            TexCoord::from_fixed(vv),
            lod,
            mode,
        );
        let b = cached.sample(
            TexCoord::from_fixed(uu),
            TexCoord::from_fixed(vv),
            lod,
            mode,
        );
        assert_eq!(
            a, b,
            "cache changed a sample ({w}x{h}, {levels} levels, {mode:?})"
        );
        if mode == Mode::Nearest {
            assert!(buf.contains(&a), "a nearest sample is a stored texel");
        }
    }
    Ok(())
}
