//! Texel cache: results identical with and without the cache (every mode,
//! both addressings, several cache shapes including a thrashing one),
//! identical fetch counters, hit/miss accounting against a reference LRU
//! model written here, and block numbering properties.

use std::collections::HashSet;

use proptest::prelude::*;
use raymip::texture::storage::cache::{BLOCK, BlockCache, BlockLayout, TexelCache};
use raymip::texture::storage::mip::{Geometry, Pyramid, TexelSource, full_levels};
use raymip::texture::{AddressMode, Mode, Sampler};
use raymip::units::{Lod, TexCoord};

use crate::common;
use common::{XorShift64, random_texture};

fn compare<const S: usize, const W: usize>(w: u32, h: u32) -> f64 {
    let (g, buf) = random_texture(w, h, full_levels(w, h), u64::from(w * h)).unwrap();
    let p = Pyramid::new(g, &buf).unwrap();
    let mut rng = XorShift64(7);
    let mut rate = 0.0;
    for a in [AddressMode::Wrap, AddressMode::ClampToEdge] {
        let mut plain = Sampler::with_address(p, a);
        let mut cached = Sampler::with_address(TexelCache::<Pyramid<'_>, S, W>::new(p), a);
        for i in 0..20_000u32 {
            // Mix coherent walks and random jumps.
            let (u, v) = if i % 3 == 0 {
                (
                    TexCoord::from_bits((rng.next_u64() >> 30) as i64 - (1 << 33)),
                    TexCoord::from_bits((rng.next_u64() >> 30) as i64 - (1 << 33)),
                )
            } else {
                (
                    TexCoord::from_num(f64::from(i % 500) / 437.0),
                    TexCoord::from_num(f64::from(i / 500) / 41.0),
                )
            };
            let lod = Lod::from_bits((rng.next_u64() % 4000) as i16 - 500);
            let mode = Mode::from_index((i % 4) as u8).unwrap();
            assert_eq!(
                plain.sample(u, v, lod, mode),
                cached.sample(u, v, lod, mode),
                "{w}x{h} {a:?} {i}"
            );
        }
        assert_eq!(plain.stats(), cached.stats());
        let st = cached.source().stats();
        assert_eq!(st.hits + st.misses, cached.stats().fetched);
        rate = st.hit_rate();
    }
    rate
}

#[test]
fn cache_and_no_cache_identical() {
    for (w, h) in [(1, 1), (1, 64), (64, 1), (1044, 1044), (128, 512), (37, 13)] {
        let r1 = compare::<1, 1>(w, h);
        let r2 = compare::<4, 2>(w, h);
        let r3 = compare::<64, 4>(w, h);
        println!("{w}x{h}: hit rate 1x1 {r1:.3}, 4x2 {r2:.3}, 64x4 {r3:.3}");
        assert!(r3 >= r1);
    }
}

/// Reference LRU model: per set a list, most recent last.
struct ModelLru {
    sets: Vec<Vec<u32>>,
    ways: usize,
}
impl ModelLru {
    fn access(&mut self, a: u32) -> bool {
        let n = self.sets.len();
        let set = &mut self.sets[a as usize % n];
        if let Some(p) = set.iter().position(|&x| x == a) {
            set.remove(p);
            set.push(a);
            true
        } else {
            if set.len() == self.ways {
                set.remove(0);
            }
            set.push(a);
            false
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// BlockCache agrees with the reference LRU model for any address stream.
    #[test]
    fn block_cache_matches_lru_model(addrs in proptest::collection::vec(prop_oneof![any::<u32>(), 0u32..40, (u32::MAX - 8)..=u32::MAX], 1..400)) {
        let mut c: BlockCache<4, 3> = BlockCache::new();
        let mut m = ModelLru { sets: vec![Vec::new(); 4], ways: 3 };
        let mut hits = 0;
        for &a in &addrs {
            let h = c.access(a);
            prop_assert_eq!(h, m.access(a));
            hits += u64::from(h);
        }
        prop_assert_eq!(c.stats().hits, hits);
        prop_assert_eq!(c.stats().misses, addrs.len() as u64 - hits);
    }

    /// Block numbers: below the layout length, equal exactly for texels of one block.
    #[test]
    fn block_index_unique_per_block(w in 1u32..300, h in 1u32..300, seed in any::<u64>()) {
        let g = Geometry::new(w, h, full_levels(w, h)).unwrap();
        let layout = BlockLayout::new(&g);
        let mut rng = XorShift64(seed | 1);
        for _ in 0..50 {
            let k = (rng.next_u64() % u64::from(g.levels())) as u8;
            let (lw, lh) = g.level_size(k);
            let (x1, y1) = ((rng.next_u64() % u64::from(lw)) as u32, (rng.next_u64() % u64::from(lh)) as u32);
            let (x2, y2) = ((rng.next_u64() % u64::from(lw)) as u32, (rng.next_u64() % u64::from(lh)) as u32);
            let (a, b) = (layout.index(k, x1, y1), layout.index(k, x2, y2));
            prop_assert!(a < layout.len() && b < layout.len());
            prop_assert_eq!(a == b, (x1 / BLOCK, y1 / BLOCK) == (x2 / BLOCK, y2 / BLOCK));
        }
    }
}

#[test]
fn block_index_dense_for_pot_and_bounded_for_npot() {
    let g = Geometry::new(256, 64, 1).unwrap();
    let layout = BlockLayout::new(&g);
    let all: HashSet<u32> = (0..64)
        .flat_map(|y| (0..256).map(move |x| (x, y)))
        .map(|(x, y)| layout.index(0, x, y))
        .collect();
    assert_eq!(all.len() as u32, 64 * 16);
    assert_eq!(layout.len(), 64 * 16);
    // NPOT: at most 4× the block count (padding to powers of two per side).
    let g = Geometry::new(1044, 1044, 11).unwrap();
    let blocks: u32 = (0..11)
        .map(|k| {
            let (w, h) = g.level_size(k);
            w.div_ceil(4) * h.div_ceil(4)
        })
        .sum();
    let n = BlockLayout::new(&g).len();
    assert!(n >= blocks && n <= 4 * blocks);
    // Morton: the 2×2 blocks of an aligned quad are 4 consecutive numbers.
    let layout = BlockLayout::new(&Geometry::new(64, 64, 1).unwrap());
    let q: Vec<u32> = [(8, 8), (12, 8), (8, 12), (12, 12)]
        .iter()
        .map(|&(x, y)| layout.index(0, x, y))
        .collect();
    assert_eq!(q[1], q[0] + 1);
    assert_eq!(q[2], q[0] + 2);
    assert_eq!(q[3], q[0] + 3);
}

#[test]
fn texel_cache_reads_each_block_once_when_it_fits() {
    let (g, buf) = random_texture(16, 16, full_levels(16, 16), 3).unwrap();
    let p = Pyramid::new(g, &buf).unwrap();
    let mut c: TexelCache<Pyramid<'_>, 32, 1> = TexelCache::new(p);
    for _ in 0..3 {
        for y in 0..16 {
            for x in 0..16 {
                assert_eq!(c.texel(0, x, y), p.get(0, x, y));
            }
        }
    }
    // 16 blocks, one miss each; everything else hits.
    assert_eq!(c.stats().misses, 16);
    assert_eq!(c.stats().hits, 3 * 256 - 16);
}
