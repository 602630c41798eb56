//! sRGB transfer functions for sRGB texel formats (Vulkan specification,
//! Appendix C / the sRGB EOTF of IEC 61966-2-1), in integer tables.
//!
//! * **Decode** (before filtering): an 8-bit sRGB code `c` becomes the
//!   linear value [`DECODE`]`[c] = round(EOTF(c/255)·65535)`, 16-bit
//!   unsigned ("L16", 65535 = 1.0), with
//!   `EOTF(s) = s/12.92` for `s ≤ 0.04045`, else `((s + 0.055)/1.055)^2.4`.
//!   A 256-entry table: exact to half an L16 step.
//! * **Encode** (after filtering, [`encode`]): a linear value in L16 with 8
//!   more fractional bits (16.8, as the filters produce it) becomes the
//!   8-bit code `round(255·OETF(x))`: the number of the 255 decision
//!   thresholds [`ENCODE_THRESHOLDS`]`[k] = ceil(EOTF((k + ½)/255)·65535·256)`
//!   at or below `x`, read from a 736-byte bucket table of counts and two
//!   compares (no search). Exact for the 16.8 input: the result equals the f64
//!   rounding of `255·OETF(x)` except where `x` lies within one 16.8 step
//!   of a threshold.
//! * **Pyramids** of sRGB textures are generated in linear space
//!   ([`generate`]): the exact box filter of `mip::generate` applied to the
//!   decoded values, re-encoded once; alpha is filtered as stored.
//!
//! Both tables are literals checked against f64 in the tests below.
//!
//! # Error bound
//!
//! Decode is within 2⁻¹⁷ of the exact EOTF. An encoded result is within
//! [`SRGB_ENCODE_MAX_ERROR_LSB`] = 0.55 sRGB LSB of `255·OETF(exact linear)`:
//! ½ from rounding, plus the input's linear error times the OETF's
//! steepest slope (12.92·255 LSB per unit, 0.05 LSB per L16 step).

#[cfg(feature = "mipgen")]
use crate::texture::storage::mip::{Geometry, MipError, Texel, generate_mapped};

/// Linear L16 value (65535 = 1.0) of every 8-bit sRGB code.
pub const DECODE: [u16; 256] = [
    0, 20, 40, 60, 80, 99, 119, 139, 159, 179, 199, 219, 241, 264, 288, 313, 340, 367, 396, 427,
    458, 491, 526, 562, 599, 637, 677, 718, 761, 805, 851, 898, 947, 997, 1048, 1101, 1156, 1212,
    1270, 1330, 1391, 1453, 1517, 1583, 1651, 1720, 1790, 1863, 1937, 2013, 2090, 2170, 2250, 2333,
    2418, 2504, 2592, 2681, 2773, 2866, 2961, 3058, 3157, 3258, 3360, 3464, 3570, 3678, 3788, 3900,
    4014, 4129, 4247, 4366, 4488, 4611, 4736, 4864, 4993, 5124, 5257, 5392, 5530, 5669, 5810, 5953,
    6099, 6246, 6395, 6547, 6700, 6856, 7014, 7174, 7335, 7500, 7666, 7834, 8004, 8177, 8352, 8528,
    8708, 8889, 9072, 9258, 9445, 9635, 9828, 10022, 10219, 10417, 10619, 10822, 11028, 11235,
    11446, 11658, 11873, 12090, 12309, 12530, 12754, 12980, 13209, 13440, 13673, 13909, 14146,
    14387, 14629, 14874, 15122, 15371, 15623, 15878, 16135, 16394, 16656, 16920, 17187, 17456,
    17727, 18001, 18277, 18556, 18837, 19121, 19407, 19696, 19987, 20281, 20577, 20876, 21177,
    21481, 21787, 22096, 22407, 22721, 23038, 23357, 23678, 24002, 24329, 24658, 24990, 25325,
    25662, 26001, 26344, 26688, 27036, 27386, 27739, 28094, 28452, 28813, 29176, 29542, 29911,
    30282, 30656, 31033, 31412, 31794, 32179, 32567, 32957, 33350, 33745, 34143, 34544, 34948,
    35355, 35764, 36176, 36591, 37008, 37429, 37852, 38278, 38706, 39138, 39572, 40009, 40449,
    40891, 41337, 41785, 42236, 42690, 43147, 43606, 44069, 44534, 45002, 45473, 45947, 46423,
    46903, 47385, 47871, 48359, 48850, 49344, 49841, 50341, 50844, 51349, 51858, 52369, 52884,
    53401, 53921, 54445, 54971, 55500, 56032, 56567, 57105, 57646, 58190, 58737, 59287, 59840,
    60396, 60955, 61517, 62082, 62650, 63221, 63795, 64372, 64952, 65535,
];

/// Decision thresholds of [`encode`] in 16.8 linear units: code `k + 1`
/// starts at entry `k`; entry 255 is a sentinel (`u32::MAX`).
pub const ENCODE_THRESHOLDS: [u32; 256] = [
    2547, 7639, 12731, 17823, 22916, 28008, 33100, 38192, 43285, 48377, 53490, 58875, 64564, 70560,
    76870, 83497, 90445, 97720, 105326, 113266, 121544, 130165, 139133, 148451, 158123, 168153,
    178545, 189302, 200428, 211926, 223801, 236054, 248690, 261713, 275124, 288929, 303129, 317728,
    332729, 348135, 363950, 380175, 396816, 413873, 431351, 449252, 467579, 486335, 505522, 525144,
    545203, 565703, 586645, 608032, 629867, 652153, 674893, 698088, 721742, 745857, 770435, 795479,
    820993, 846977, 873434, 900368, 927780, 955673, 984048, 1012910, 1042259, 1072098, 1102430,
    1133256, 1164580, 1196403, 1228728, 1261556, 1294890, 1328733, 1363086, 1397951, 1433331,
    1469229, 1505645, 1542582, 1580043, 1618029, 1656542, 1695585, 1735160, 1775268, 1815912,
    1857093, 1898815, 1941077, 1983884, 2027236, 2071136, 2115586, 2160587, 2206142, 2252252,
    2298919, 2346145, 2393933, 2442284, 2491200, 2540682, 2590733, 2641355, 2692549, 2744317,
    2796661, 2849583, 2903084, 2957167, 3011833, 3067085, 3122923, 3179349, 3236366, 3293975,
    3352177, 3410975, 3470371, 3530365, 3590960, 3652158, 3713959, 3776367, 3839381, 3903005,
    3967240, 4032087, 4097549, 4163626, 4230321, 4297634, 4365569, 4434126, 4503306, 4573113,
    4643546, 4714608, 4786301, 4858625, 4931583, 5005176, 5079406, 5154274, 5229782, 5305931,
    5382724, 5460160, 5538243, 5616973, 5696352, 5776381, 5857063, 5938398, 6020389, 6103036,
    6186340, 6270305, 6354931, 6440219, 6526171, 6612788, 6700073, 6788026, 6876648, 6965942,
    7055909, 7146550, 7237867, 7329860, 7422532, 7515884, 7609917, 7704633, 7800033, 7896119,
    7992892, 8090353, 8188503, 8287345, 8386879, 8487107, 8588031, 8689651, 8791969, 8894986,
    8998704, 9103124, 9208248, 9314076, 9420610, 9527852, 9635803, 9744464, 9853836, 9963921,
    10074720, 10186234, 10298466, 10411415, 10525083, 10639473, 10754584, 10870418, 10986977,
    11104262, 11222273, 11341014, 11460484, 11580684, 11701617, 11823284, 11945685, 12068822,
    12192697, 12317310, 12442663, 12568757, 12695593, 12823173, 12951497, 13080567, 13210385,
    13340951, 13472267, 13604334, 13737152, 13870725, 14005051, 14140134, 14275973, 14412571,
    14549928, 14688046, 14826925, 14966568, 15106975, 15248147, 15390085, 15532792, 15676267,
    15820512, 15965529, 16111318, 16257881, 16405219, 16553333, 16702223, 4294967295,
];

/// Error bound of a re-encoded filtered result against the f64 sRGB
/// encoding of the exact linear filter, in 8-bit sRGB LSB (with
/// 12-bit bilinear weights the position error adds to it; see
/// `crate::texture::kernel::srgb`).
pub const SRGB_ENCODE_MAX_ERROR_LSB: f64 = 0.55;

/// Tier boundary of [`ENCODE_BUCKETS`]: values below `2²⁰` fall into
/// buckets of 2¹² (the thresholds there are at least 5092 apart: at most
/// one per bucket), values above into buckets of 2¹⁵ (thresholds at least
/// 29 000 apart there: at most two per bucket). Tested.
const ENCODE_TIER: u32 = 1 << 20;

/// `ENCODE_BUCKETS[b]`: the number of [`ENCODE_THRESHOLDS`] entries at or
/// below the start of bucket `b` (`x >> 12` below [`ENCODE_TIER`], then
/// `224 + (x >> 15)`, up to `x < 2²⁴`; larger values are clamped to the
/// last bucket, whose count is 255).
const ENCODE_BUCKETS: [u8; 736] = {
    let mut t = [0u8; 736];
    let mut b = 0;
    while b < 736 {
        let start: u32 = if b < 256 {
            (b as u32) << 12
        } else {
            ((b as u32) - 224) << 15
        };
        let mut c = 0;
        while c < 255 && ENCODE_THRESHOLDS[c] <= start {
            c += 1;
        }
        t[b] = c as u8;
        b += 1;
    }
    t
};

/// 8-bit sRGB code of a linear 16.8 value `x` (65535·256 = 1.0; larger
/// values give 255): `round(255·OETF(x))`, the number of
/// [`ENCODE_THRESHOLDS`] entries at or below `x`: the count below the
/// bucket of `x` (the private table `ENCODE_BUCKETS`) plus the (at most
/// two) thresholds inside it that `x` reaches. Never panics.
#[inline]
#[must_use]
pub fn encode(x: u32) -> u8 {
    let x = x.min((1 << 24) - 1);
    let b = if x < ENCODE_TIER {
        x >> 12
    } else {
        224 + (x >> 15)
    };
    let c = ENCODE_BUCKETS.get(b as usize).copied().unwrap_or(255);
    // Entry 255 is the sentinel `u32::MAX`: `c + 1 ≤ 255` reads it at most.
    let at = |k: u8| {
        ENCODE_THRESHOLDS
            .get(usize::from(k))
            .copied()
            .unwrap_or(u32::MAX)
    };
    c + u8::from(x >= at(c)) + u8::from(x >= at(c.saturating_add(1)))
}

/// The linear L16 value of sRGB code `c`.
#[inline(always)]
#[must_use]
pub fn decode(c: u8) -> u16 {
    DECODE[usize::from(c)]
}

/// Fills levels `1 .. levels` of an sRGB RGBA8 pyramid from level 0 like
/// [`mip::generate`](crate::texture::storage::mip::generate), but averaging RGB in linear
/// space (decoded by [`DECODE`], the exact box weights of `mip`, re-encoded
/// once by [`encode`] after rounding to 16.8); alpha is averaged as stored
/// and rounded half up.
///
/// # Errors
/// [`MipError::BufferTooShort`] when `buf` is shorter than the geometry.
///
/// Feature `mipgen`.
#[cfg(feature = "mipgen")]
pub fn generate(geometry: &Geometry, buf: &mut [Texel]) -> Result<(), MipError> {
    generate_mapped(
        geometry,
        buf,
        |t| {
            let [r, g, b, a] = t.to_le_bytes();
            [
                u32::from(decode(r)),
                u32::from(decode(g)),
                u32::from(decode(b)),
                u32::from(a),
            ]
        },
        |sum, den| {
            let den = den.max(1);
            let mut out = [0u8; 4];
            for (c, (o, s)) in out.iter_mut().zip(sum).enumerate() {
                // Half up: floor((2S·k + D) / 2D) with k = 256 (16.8) or 1.
                *o = if c < 3 {
                    let x = (s.saturating_mul(512).saturating_add(den)) / (2 * den);
                    encode(u32::try_from(x).unwrap_or(u32::MAX))
                } else {
                    u8::try_from((2 * s + den) / (2 * den)).unwrap_or(255)
                };
            }
            u32::from_le_bytes(out)
        },
    )
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    fn eotf(s: f64) -> f64 {
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    }

    fn oetf(l: f64) -> f64 {
        if l <= 0.0031308 {
            l * 12.92
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        }
    }

    #[test]
    fn tables_match_f64() {
        for (c, &d) in DECODE.iter().enumerate() {
            let want = (eotf(c as f64 / 255.0) * 65535.0).round();
            assert_eq!(f64::from(d), want, "decode {c}");
        }
        for (k, &t) in ENCODE_THRESHOLDS.iter().take(255).enumerate() {
            let want = (eotf((k as f64 + 0.5) / 255.0) * 65535.0 * 256.0).ceil();
            assert_eq!(f64::from(t), want, "threshold {k}");
        }
        assert_eq!(ENCODE_THRESHOLDS[255], u32::MAX);
    }

    /// The bucketed encode equals the binary search over every input of
    /// the 16.8 range and beyond, and the buckets hold at most one (below
    /// 2²⁰) or two thresholds.
    #[test]
    fn encode_equals_the_search() {
        let search = |x: u32| {
            let mut code = 0usize;
            for step in [128, 64, 32, 16, 8, 4, 2, 1] {
                if x >= ENCODE_THRESHOLDS[(code + step - 1) & 0xFF] {
                    code += step;
                }
            }
            code as u8
        };
        let step = if cfg!(miri) { 9973 } else { 1 };
        for x in (0..(1u32 << 24) + 4096).step_by(step) {
            assert_eq!(encode(x), search(x), "{x}");
        }
        for x in [u32::MAX, u32::MAX - 1, 1 << 31] {
            assert_eq!(encode(x), search(x), "{x}");
        }
        for w in ENCODE_THRESHOLDS[..255].windows(2) {
            let gap = w[1] - w[0];
            assert!(gap > 1 << 12, "{w:?}");
            assert!(w[0] < ENCODE_TIER || gap > 1 << 14, "{w:?}");
        }
    }

    #[test]
    fn encode_inverts_decode() {
        for c in 0..=255u8 {
            assert_eq!(encode(u32::from(decode(c)) << 8), c);
        }
        assert_eq!(encode(0), 0);
        assert_eq!(encode(u32::MAX), 255);
    }

    proptest! {
        /// encode is the f64 rounding of 255·OETF(x) within the bound.
        #[test]
        fn encode_matches_f64(x in 0u32..=(65535 * 256)) {
            let exact = 255.0 * oetf(f64::from(x) / (65535.0 * 256.0));
            let got = f64::from(encode(x));
            prop_assert!((got - exact).abs() <= 0.5 + 1e-9, "{x}: {got} vs {exact}");
        }

        /// Linear-space pyramids: every level-1 texel against the f64
        /// linear box of its four sources, re-encoded.
        #[test]
        #[cfg(feature = "mipgen")]
        fn generate_in_linear_space(texels in proptest::collection::vec(any::<u32>(), 16)) {
            let g = Geometry::new(4, 4, 3).unwrap();
            let mut buf = std::vec![0u32; g.len()];
            buf[..16].copy_from_slice(&texels);
            generate(&g, &mut buf).unwrap();
            for y in 0..2usize {
                for x in 0..2usize {
                    let out = buf[16 + y * 2 + x].to_le_bytes();
                    for (c, &o) in out.iter().enumerate() {
                        let mut acc = 0.0;
                        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                            let v = f64::from(texels[(2 * y + dy) * 4 + 2 * x + dx].to_le_bytes()[c]);
                            acc += if c < 3 { eotf(v / 255.0) } else { v } / 4.0;
                        }
                        let exact = if c < 3 { 255.0 * oetf(acc) } else { acc };
                        prop_assert!((f64::from(o) - exact).abs() <= SRGB_ENCODE_MAX_ERROR_LSB,
                            "channel {c}: {o} vs {exact}");
                    }
                }
            }
        }
    }
}
