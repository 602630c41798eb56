//! Reference vectors of the texture co-processor (`demo/softcore/pcpi_tex.v`,
//! issue 23), written by the firmware's software paths: `raymip-demo
//! pcpi-vectors FILE` writes them and the Verilator testbench
//! `demo/softcore/tb_pcpi_tex.cpp` checks every output bit of the RTL
//! against them (`scripts/softcore`).
//!
//! One vector a line, `OP RS1 RS2 RD` in hex (OP = the instruction's
//! funct3; RS1, RS2, RD 32-bit words):
//! * `0` `tex.log2pl`: `RS1`/`RS2` the low/high word of a U32F32 path length,
//!   `RD = log2_u32f32(Pl).to_bits() + 0x80` (the value the firmware's
//!   `table_lod` and `cone_lod` subtract from; see `raymip::pcpi`);
//! * `1` `tex.lod`: `RS1` the `tex.log2pl` value of `Pl` (as above), `RS2`
//!   the bits of a `Log2Pb` entry, `RD = table_lod(Pl, Pb)` sign-extended,
//!   `0x8000_0000` for `None` (untextured).
//!
//! Inputs: zero, every power of two and its neighbours, every one of the
//! 64 table intervals at its ends and middle in every octave, the U1F31
//! range the cone lod's normal term reads (`[2¹⁵, 2³¹]` as U32F32 bits),
//! and pseudo-random values with a uniformly drawn octave; entries: the
//! three markers, the finite extremes and random entries.

use std::fmt::Write as _;

use fixed::types::U32F32;
use raymip::lod::table_lod;
use raymip::log2::log2_u32f32;
use raymip::raystack::PathLength;
use raymip::rng::Rng;
use raymip::table::Log2Pb;

/// The software `tex.log2pl`: `log2 Pl` in I16F16 bits plus the I8F8
/// rounding offset `0x80`.
#[must_use]
pub fn log2pl(pl: u64) -> u32 {
    (log2_u32f32(U32F32::from_bits(pl)).to_bits() as u32).wrapping_add(0x80)
}

/// The software `tex.lod` of `(Pl, entry)`: `table_lod` sign-extended, or
/// `0x8000_0000` for `None`.
#[must_use]
pub fn lod(pl: u64, pb: Log2Pb) -> u32 {
    match table_lod(PathLength::from_bits(pl), pb) {
        Some(l) => i32::from(l.to_bits()) as u32,
        None => 0x8000_0000,
    }
}

/// Path lengths of every input class (see the module docs).
#[must_use]
pub fn path_lengths() -> Vec<u64> {
    let mut v = vec![0u64, u64::MAX];
    for s in 0..64 {
        let p = 1u64 << s;
        v.extend([p, p - 1, p.wrapping_add(1), p | (p >> 1), !0u64 >> (63 - s)]);
    }
    // Every interval (index i, weight t) of the mantissa in every octave.
    for i in 0..64u64 {
        for t in [0u64, 1, 0x7FFF, 0x8000, 0xFFFF] {
            for low in [0u64, 0x1FF] {
                let m = (1u64 << 31) | (i << 25) | (t << 9) | low;
                for s in 0..=32 {
                    v.push(m << s);
                    v.push(m >> s.min(31));
                }
            }
        }
    }
    // U1F31 |n·d| values of the cone lod (clamped to [2¹⁵, 2³¹]).
    for c in [1u64 << 15, (1 << 15) + 1, 1 << 30, (1 << 31) - 1, 1 << 31] {
        v.push(c);
    }
    let mut r = Rng::new(0x7e8_c0de);
    for _ in 0..20_000 {
        let octave = r.next_u32() % 64;
        let m = (u64::from(r.next_u32()) << 32) | u64::from(r.next_u32());
        v.push((1u64 << octave) | (m & ((1u64 << octave) - 1)));
    }
    v
}

/// `Log2Pb` entries: the markers, the finite extremes, zero and neighbours,
/// and `n` random raw values (clamped as `Log2Pb::from_bits` clamps).
#[must_use]
pub fn entries(n: usize) -> Vec<Log2Pb> {
    let mut v = vec![
        Log2Pb::UNTEXTURED,
        Log2Pb::DEGENERATE_GEOMETRY,
        Log2Pb::DEGENERATE_UV,
        Log2Pb::MIN,
        Log2Pb::MAX,
        Log2Pb::from_bits(0),
        Log2Pb::from_bits(1),
        Log2Pb::from_bits(-1),
        Log2Pb::from_bits(0x7F),
        Log2Pb::from_bits(0x80),
    ];
    let mut r = Rng::new(0x1d5_b17e);
    for _ in 0..n {
        let b = r.next_u32() as i32;
        v.push(Log2Pb::from_bits(b >> (r.next_u32() % 9)));
    }
    v
}

/// The whole vector file.
#[must_use]
pub fn vectors() -> String {
    let pls = path_lengths();
    let pbs = entries(64);
    let mut out = String::new();
    for &p in &pls {
        let _ = writeln!(
            out,
            "0 {:08x} {:08x} {:08x}",
            p as u32,
            (p >> 32) as u32,
            log2pl(p)
        );
    }
    // tex.lod: every entry with a spread of path lengths, then random pairs.
    let mut lod_line = |p: u64, pb: Log2Pb| {
        let _ = writeln!(
            out,
            "1 {:08x} {:08x} {:08x}",
            log2pl(p),
            pb.to_bits() as u32,
            lod(p, pb)
        );
    };
    for (k, &p) in pls.iter().enumerate() {
        lod_line(p, pbs[k % pbs.len()]);
        if k % 97 == 0 {
            for &pb in &pbs[..10] {
                lod_line(p, pb);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vectors against an independent f64 reference: log2 within
    /// `LOG2_MAX_ERROR`, the lod within `LOD_MAX_ERROR` (entries inside the
    /// finite range) and the untextured marker mapped to `0x8000_0000`.
    #[test]
    fn vectors_match_f64() {
        for p in path_lengths() {
            let got = f64::from(log2pl(p).wrapping_sub(0x80) as i32) / 65536.0;
            let want = (p.max(1) as f64).log2() - 32.0;
            assert!(
                (got - want).abs() <= raymip::log2::LOG2_MAX_ERROR,
                "{p:#x}: {got} vs {want}"
            );
            for pb in [Log2Pb::MIN, Log2Pb::MAX, Log2Pb::from_bits(0x12345)] {
                let l = f64::from(lod(p, pb) as i32) / 256.0;
                let want = want - f64::from(pb.to_bits()) / 65536.0;
                assert!(
                    (l - want).abs() <= raymip::lod::LOD_MAX_ERROR,
                    "{p:#x}: {l} vs {want}"
                );
            }
            assert_eq!(lod(p, Log2Pb::UNTEXTURED), 0x8000_0000);
        }
    }

    #[test]
    fn vector_file_has_both_ops_and_every_class() {
        let v = vectors();
        let n0 = v.lines().filter(|l| l.starts_with("0 ")).count();
        let n1 = v.lines().filter(|l| l.starts_with("1 ")).count();
        assert!(n0 > 20_000 && n1 > n0, "{n0} {n1}");
        assert!(
            v.contains("0 00000000 00000000 ffe00080"),
            "zero reads as 2^-32"
        );
        assert!(
            v.lines()
                .any(|l| l.starts_with("1 ") && l.ends_with(" 80000000"))
        );
    }
}
