//! MIP generation against an f64 reference written here: the exact area
//! average (box filter) of the level below over each output texel's
//! footprint, computed by interval overlap (not by the firmware's weight
//! formula). Bound: power-of-two levels exact (the average rounded half up);
//! every level within ½ LSB of the exact average (correct rounding).

use proptest::prelude::*;
use raymip::texture::storage::mip::{
    Geometry, MipError, Texel, full_levels, generate, pyramid_len,
};

use crate::common;
use common::XorShift64;

fn channel(t: Texel, c: usize) -> f64 {
    f64::from((t >> (8 * c)) & 0xFF)
}

/// Overlap of `[a, a + 1]` with `[lo, hi]`.
fn overlap(a: f64, lo: f64, hi: f64) -> f64 {
    ((a + 1.0).min(hi) - a.max(lo)).max(0.0)
}

/// Exact box average of output texel (x, y) of a `dw × dh` level from a
/// `sw × sh` source: the footprint is `[x·sw/dw, (x+1)·sw/dw] ×
/// [y·sh/dh, (y+1)·sh/dh]` in source texel units.
fn reference_texel(src: &[Texel], sw: u32, sh: u32, dw: u32, dh: u32, x: u32, y: u32) -> [f64; 4] {
    let rx = f64::from(sw) / f64::from(dw);
    let ry = f64::from(sh) / f64::from(dh);
    let (x0, x1) = (f64::from(x) * rx, f64::from(x + 1) * rx);
    let (y0, y1) = (f64::from(y) * ry, f64::from(y + 1) * ry);
    let mut acc = [0.0; 4];
    for j in (y0.floor() as u32)..(y1.ceil() as u32).min(sh) {
        let wy = overlap(f64::from(j), y0, y1);
        for i in (x0.floor() as u32)..(x1.ceil() as u32).min(sw) {
            let w = wy * overlap(f64::from(i), x0, x1);
            let t = src[(j * sw + i) as usize];
            for (c, a) in acc.iter_mut().enumerate() {
                *a += w * channel(t, c);
            }
        }
    }
    let area = rx * ry;
    acc.map(|a| a / area)
}

/// Builds a random level 0, generates, checks every level against the
/// reference. Returns the largest |firmware − exact average| (LSB).
fn check(w: u32, h: u32, levels: u8, seed: u64) -> f64 {
    let g = Geometry::new(w, h, levels).unwrap();
    assert_eq!(g.len(), pyramid_len(w, h, levels));
    let mut rng = XorShift64(seed | 1);
    let mut buf: Vec<Texel> = vec![0; g.len()];
    for t in &mut buf[..(w * h) as usize] {
        *t = rng.next_u64() as u32;
    }
    generate(&g, &mut buf).unwrap();
    let mut worst: f64 = 0.0;
    for k in 1..levels {
        let (sw, sh) = g.level_size(k - 1);
        let (dw, dh) = g.level_size(k);
        // Reference level size, from the definition.
        assert_eq!((dw, dh), ((w >> k).max(1), (h >> k).max(1)));
        let src = &buf[g.level_offset(k - 1)..g.level_offset(k - 1) + (sw * sh) as usize];
        let dst = &buf[g.level_offset(k)..g.level_offset(k) + (dw * dh) as usize];
        let pot = sw.is_power_of_two() && sh.is_power_of_two();
        for y in 0..dh {
            for x in 0..dw {
                let want = reference_texel(src, sw, sh, dw, dh, x, y);
                let got = dst[(y * dw + x) as usize];
                for (c, &wc) in want.iter().enumerate() {
                    let e = (channel(got, c) - wc).abs();
                    worst = worst.max(e);
                    if pot {
                        // Exact: the average rounded half up.
                        assert_eq!(
                            channel(got, c),
                            (wc + 0.5).floor(),
                            "{w}x{h} level {k} ({x},{y}) ch {c}"
                        );
                    } else {
                        assert!(e <= 0.5 + 1e-9, "{w}x{h} level {k} ({x},{y}) ch {c}: {e}");
                    }
                }
            }
        }
    }
    worst
}

#[test]
fn pot_generation_exact() {
    for (w, h) in [
        (1, 1),
        (2, 2),
        (64, 64),
        (256, 16),
        (1, 128),
        (128, 1),
        (4, 1024),
    ] {
        check(w, h, full_levels(w, h), u64::from(w * 31 + h));
    }
}

#[test]
fn npot_generation_box_filter_within_half_lsb() {
    let mut worst: f64 = 0.0;
    for (w, h) in [
        (3, 3),
        (5, 1),
        (1, 7),
        (1044, 1044),
        (128, 512),
        (100, 37),
        (33, 65),
        (6, 10),
    ] {
        worst = worst.max(check(w, h, full_levels(w, h), u64::from(w * 17 + h)));
    }
    println!("NPOT generation: max |fixed − f64 box| = {worst:.4} LSB (bound 0.5)");
}

#[test]
fn big_4096_generation_exact() {
    check(4096, 4096, 13, 4096);
}

#[test]
fn partial_chains_and_errors() {
    // Fewer levels than the full chain: only those are written.
    let g = Geometry::new(16, 16, 2).unwrap();
    let mut buf = vec![0xFFFF_FFFFu32; g.len() + 1];
    buf[g.len()] = 7;
    generate(&g, &mut buf).unwrap();
    assert_eq!(buf[g.len()], 7);
    assert!(buf[..g.len()].iter().all(|&t| t == 0xFFFF_FFFF));
    assert_eq!(
        generate(&g, &mut vec![0; g.len() - 1]),
        Err(MipError::BufferTooShort {
            needed: g.len(),
            got: g.len() - 1
        })
    );
    assert_eq!(Geometry::new(3, 3, 3), Err(MipError::BadLevels));
    assert_eq!(Geometry::new(0, 0, 1), Err(MipError::ZeroSize));
    assert!(!MipError::ZeroSize.to_string().is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Any size up to 70×70 and any level count: within ½ LSB of the exact
    /// box, exact where both sides are powers of two.
    #[test]
    fn any_size_within_bound(w in 1u32..70, h in 1u32..70, seed in any::<u64>(), lv in 0u8..8) {
        let levels = 1 + lv % full_levels(w, h);
        check(w, h, levels, seed);
    }

    /// pyramid_len equals the sum of the level sizes of the definition.
    #[test]
    fn pyramid_len_matches_definition(w in 1u32..=32768, h in 1u32..=32768, levels in 0u8..20) {
        let n = levels.min(full_levels(w, h));
        let want: u64 = (0..n).map(|k| u64::from((w >> k).max(1)) * u64::from((h >> k).max(1))).sum();
        prop_assert_eq!(pyramid_len(w, h, levels) as u64, want);
        prop_assert_eq!(u32::from(full_levels(w, h)), 1 + 31 - w.max(h).leading_zeros());
    }
}
