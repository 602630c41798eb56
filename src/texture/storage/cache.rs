//! Texel cache: a const-generic set-associative LRU cache of 4×4-texel
//! blocks in front of slow texel memory.
//!
//! # Layout: 4×4 blocks in Morton order
//!
//! A block of [`BLOCK`]` × `[`BLOCK`] RGBA8 texels is 64 bytes, one cache
//! line of the external memory. A bilinear footprint (2×2 texels) touches
//! one block in 9 of 16 positions and at most four neighbouring blocks, and
//! a square block serves a ray's footprint equally in every direction (rays
//! hit textures at arbitrary orientation, unlike a rasterizer's scanlines).
//!
//! Blocks are numbered ([`BlockLayout::index`]) level by level, and within a level
//! in Morton (Z) order: the bits of the block column and row are
//! interleaved, so blocks that are close in 2-D get close numbers. With the
//! set index `block % SETS`, a 2×2 group of blocks around any even-aligned
//! position falls into four *different* consecutive sets, and a whole
//! `2^k × 2^k` neighbourhood spreads over `4^k` sets before any set repeats.
//! Row-major numbering would instead map vertically adjacent blocks to sets
//! one row pitch apart, which for power-of-two pitches are the same set, so
//! a 2×2 footprint straddling a row of blocks would contend for one set.
//!
//! Non-square levels use the rectangular Morton order: the low
//! `min(log2 bw, log2 bh)` bits of column and row are interleaved and the
//! remaining high bits of the longer side are placed above them. Block
//! counts per side are padded to powers of two, so numbers are dense for
//! power-of-two textures and at most 4× sparse otherwise
//! ([`BlockLayout::len`]).
//!
//! # Replacement
//!
//! True LRU per set: every way holds the value of a 64-bit access clock at
//! its last use; a miss replaces an empty way, else the way with the
//! smallest stamp. Counters: [`CacheStats`]. The clock counts every
//! access, so a hit only advances the clock and writes its way's stamp:
//! the hit count is the clock's advance since the counters were zeroed
//! minus the misses.
//!
//! # Footprint memo
//!
//! A [`TexelCache`] remembers, per level parity, the last footprint it
//! looked up: its level, block columns and rows, and the way holding each
//! texel's block. A footprint in the same blocks (a trilinear sample's
//! level next to the last one's, or the same sample again) is four hits
//! in those ways: it advances the clock and reads the texels with no tag
//! compare, and the stamps the lookups would have written are written
//! before the next lookup. A fill forgets every memo naming the way it
//! refills and [`TexelCache::invalidate`] forgets both, so the texels,
//! counters and LRU order are those of one access per texel read.

use crate::texture::storage::mip::{Geometry, MAX_LEVELS, Pyramid, Texel, TexelSource};

/// Side of a cache block in texels (4 × 4 RGBA8 texels = 64 bytes).
pub const BLOCK: u32 = 4;

/// `log2(BLOCK)`.
const BLOCK_SHIFT: u32 = 2;

/// Texels per block (16).
pub const BLOCK_TEXELS: usize = (BLOCK * BLOCK) as usize;

/// Spreads the low 16 bits of `x` to the even bit positions.
#[inline(always)]
const fn part1by1(x: u32) -> u32 {
    let mut x = x & 0xFFFF;
    x = (x | (x << 8)) & 0x00FF_00FF;
    x = (x | (x << 4)) & 0x0F0F_0F0F;
    x = (x | (x << 2)) & 0x3333_3333;
    (x | (x << 1)) & 0x5555_5555
}

/// `part1by1` of every byte (the even bit positions of 16 bits).
const SPREAD: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = part1by1(i as u32) as u16;
        i += 1;
    }
    t
};

/// `part1by1(x)` for `x < 2¹⁶` by two reads of [`SPREAD`] (a block
/// coordinate's part of its Morton number).
#[inline(always)]
fn spread(x: u32) -> u32 {
    let lo = SPREAD[(x & 0xFF) as usize];
    let hi = SPREAD[((x >> 8) & 0xFF) as usize];
    u32::from(lo) | (u32::from(hi) << 16)
}

/// Morton (Z-order) code of `(x, y)` for `x, y < 2¹⁶`: bit `i` of `x` goes
/// to bit `2i`, bit `i` of `y` to bit `2i + 1`.
#[inline]
#[must_use]
#[cfg(test)]
pub(crate) const fn morton2(x: u32, y: u32) -> u32 {
    part1by1(x) | (part1by1(y) << 1)
}

/// Block numbering of one pyramid (see module docs): per-level offsets and
/// padded block-grid sizes.
///
/// # Example
/// ```
/// use raymip::{BlockLayout, Geometry};
/// // 8×8 level 0: 2×2 blocks of 4×4; levels 1 and 2 (4×4, 2×2) one block each.
/// let layout = BlockLayout::new(&Geometry::new(8, 8, 3)?);
/// assert_eq!(layout.len(), 4 + 1 + 1);
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockLayout {
    geometry: Geometry,
    /// `geometry.top_level()`.
    top: u8,
    /// The numbering of each level `0 ..= top` (entries above unused).
    grids: [LevelGrid; MAX_LEVELS as usize],
    /// Block numbers used by all levels.
    total: u32,
}

/// `ceil(n / BLOCK)` rounded up to a power of two, as its `log2`.
const fn padded_log2(texels: u32) -> u8 {
    let blocks = texels.div_ceil(BLOCK);
    blocks.next_power_of_two().trailing_zeros() as u8
}

impl BlockLayout {
    /// The block layout of `geometry`.
    #[must_use]
    pub const fn new(geometry: &Geometry) -> Self {
        let mut grids = [LevelGrid {
            offset: 0,
            last: [0; 2],
            log2: [0; 2],
        }; MAX_LEVELS as usize];
        let mut total = 0u32;
        let mut k = 0u8;
        while k < MAX_LEVELS {
            if k < geometry.levels() {
                let kk = k as u32;
                let w = geometry.width() >> kk;
                let h = geometry.height() >> kk;
                let lx = padded_log2(if w == 0 { 1 } else { w });
                let ly = padded_log2(if h == 0 { 1 } else { h });
                // The texel clamp of `TexelSource::texel` (stored levels;
                // sides ≤ 2¹⁵, so `side − 1` fits 16 bits).
                let (sw, sh) = geometry.level_size(k);
                grids[k as usize] = LevelGrid {
                    offset: total,
                    last: [(sw - 1) as u16, (sh - 1) as u16],
                    log2: [lx, ly],
                };
                // Sides ≤ 2¹⁵ texels: ≤ 2²⁶ blocks in level 0, sum < 2²⁸.
                total += 1 << (lx as u32 + ly as u32);
            }
            k += 1;
        }
        Self {
            geometry: *geometry,
            top: geometry.top_level(),
            grids,
            total,
        }
    }

    /// Number of block numbers used (every [`index`](Self::index) is below
    /// it; at least 1): a base stride for giving several pyramids disjoint
    /// global block addresses.
    #[must_use]
    #[allow(clippy::len_without_is_empty)] // a pyramid has at least one block
    pub const fn len(&self) -> u32 {
        self.total
    }

    /// `level` clamped to the top level, and its numbering ([`LevelGrid`]).
    #[inline(always)]
    fn grid(&self, level: u8) -> (u8, LevelGrid) {
        let level = level.min(self.top);
        // `top < MAX_LEVELS`: the mask changes nothing and spares a check.
        (level, self.grids[usize::from(level) % MAX_LEVELS as usize])
    }

    /// Block number of block `(bx, by)` of `level` (level clamped to the
    /// top stored level, `bx`/`by` to the level's padded block grid).
    #[inline]
    #[must_use]
    pub(crate) fn index_of_block(&self, level: u8, bx: u32, by: u32) -> u32 {
        let (_, g) = self.grid(level);
        g.index(g.col_clamped(bx), g.row_clamped(by))
    }

    /// Block number of the block holding texel `(x, y)` of `level`
    /// (clamped like [`Geometry::texel_index`]).
    #[inline]
    #[must_use]
    pub fn index(&self, level: u8, x: u32, y: u32) -> u32 {
        let (w, h) = self.geometry.level_size(level);
        self.index_of_block(
            level,
            x.min(w - 1) >> BLOCK_SHIFT,
            y.min(h - 1) >> BLOCK_SHIFT,
        )
    }
}

/// The block numbering of one level of a [`BlockLayout`], split by axis:
/// the number of block `(bx, by)` (inside the padded grid, `bx ≤ max[0]`,
/// `by ≤ max[1]`) is `offset + (col(bx) | row(by))`. The interleaved low
/// `low` bits of both coordinates are `part1by1(bx) | part1by1(by) << 1`,
/// and the high bits of the longer side (the other side has none) sit
/// above them; both terms are an OR of one part per axis. A footprint
/// computes each axis's parts once for the (up to four) blocks it touches.
/// Also the level's last texel column and row (the texel clamp), so that
/// a footprint reads one record per level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct LevelGrid {
    /// Block number of the level's first block.
    offset: u32,
    /// The last texel column and row of the level (`side − 1`).
    last: [u16; 2],
    /// `log2` of the padded block columns and rows (each ≤ 13).
    log2: [u8; 2],
}

impl LevelGrid {
    /// `min(log2 columns, log2 rows)`: the interleaved bits per axis.
    #[inline(always)]
    fn low(&self) -> u32 {
        u32::from(self.log2[0].min(self.log2[1]))
    }

    /// The largest block column and row of the padded grid.
    #[inline(always)]
    fn max(&self) -> [u32; 2] {
        self.log2.map(|l| (1u32 << (l & 15)) - 1)
    }

    /// The column part of the block number of column `bx ≤ max[0]`.
    #[inline(always)]
    fn col(&self, bx: u32) -> u32 {
        let low = self.low();
        let mask = (1u32 << low) - 1;
        spread(bx & mask) | ((bx >> low) << (2 * low))
    }

    /// The row part of the block number of row `by ≤ max[1]`.
    #[inline(always)]
    fn row(&self, by: u32) -> u32 {
        let low = self.low();
        let mask = (1u32 << low) - 1;
        (spread(by & mask) << 1) | ((by >> low) << (2 * low))
    }

    /// [`col`](Self::col) of `bx` clamped to the grid.
    #[inline(always)]
    fn col_clamped(&self, bx: u32) -> u32 {
        self.col(bx.min(self.max()[0]))
    }

    /// [`row`](Self::row) of `by` clamped to the grid.
    #[inline(always)]
    fn row_clamped(&self, by: u32) -> u32 {
        self.row(by.min(self.max()[1]))
    }

    /// The block number of the parts `col` and `row`.
    #[inline(always)]
    fn index(&self, col: u32, row: u32) -> u32 {
        self.offset + (col | row)
    }
}

/// Hit and miss counters.
///
/// # Example
/// ```
/// use raymip::BlockCache;
/// use raymip::texture::storage::cache::CacheStats;
/// let mut tags: BlockCache<2, 1> = BlockCache::new(); // two sets, one way
/// // Blocks 0 and 2 share set 0 and evict each other; 1 stays in set 1.
/// for block in [0, 1, 0, 1, 2, 0] {
///     let _ = tags.access(block);
/// }
/// // Misses: the first 0, the first 1, 2, and 0 again; hits: 0 and 1 once.
/// assert_eq!(tags.stats(), CacheStats { hits: 2, misses: 4 });
/// assert_eq!(tags.stats().hit_rate(), 2.0 / 6.0);
/// tags.reset_stats();
/// assert_eq!(tags.stats().hit_rate(), 0.0); // no accesses
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheStats {
    /// Accesses that found their block.
    pub hits: u64,
    /// Accesses that had to load their block.
    pub misses: u64,
}

impl CacheStats {
    /// `hits / (hits + misses)` in `[0, 1]`; 0 with no accesses. Reporting
    /// only (uses a float division).
    #[must_use]
    pub fn hit_rate(&self) -> f64 {
        let total = self.hits.saturating_add(self.misses);
        if total == 0 {
            0.0
        } else {
            self.hits as f64 / total as f64
        }
    }
}

/// Tags of a `SETS`-set, `WAYS`-way set-associative cache with true LRU
/// replacement, for any `u32` block address (set = `address % SETS`).
/// Holds no data: use it alone to model a cache (hit rates), or through
/// [`TexelCache`]. `SETS` and `WAYS` must be ≥ 1 (checked at compile
/// time); power-of-two `SETS` make the set index a mask.
///
/// # Example
/// ```
/// use raymip::BlockCache;
/// let mut tags: BlockCache<1, 2> = BlockCache::new(); // one set, two ways
/// assert!(!tags.access(7)); // miss
/// assert!(tags.access(7)); // hit
/// assert!(!tags.access(8)); // miss: both ways in use
/// assert!(!tags.access(9)); // miss: evicts 7, the least recently used
/// assert!(!tags.access(7));
/// assert_eq!((tags.stats().hits, tags.stats().misses), (1, 4));
/// ```
#[derive(Clone, Debug)]
pub struct BlockCache<const SETS: usize, const WAYS: usize> {
    tags: [[u32; WAYS]; SETS],
    /// Access clock at last use; 0 = empty way.
    stamps: [[u64; WAYS]; SETS],
    /// Accesses since construction (wrapping: 2⁶⁴ accesses are beyond
    /// any run).
    clock: u64,
    /// The clock when the counters were last zeroed.
    since: u64,
    /// Misses since then.
    misses: u64,
}

impl<const SETS: usize, const WAYS: usize> Default for BlockCache<SETS, WAYS> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const SETS: usize, const WAYS: usize> BlockCache<SETS, WAYS> {
    const VALID_SHAPE: () = assert!(SETS > 0 && WAYS > 0, "SETS and WAYS must be at least 1");

    /// An empty cache.
    #[must_use]
    pub const fn new() -> Self {
        let () = Self::VALID_SHAPE;
        Self {
            tags: [[0; WAYS]; SETS],
            stamps: [[0; WAYS]; SETS],
            clock: 0,
            since: 0,
            misses: 0,
        }
    }

    /// Capacity in blocks (`SETS · WAYS`).
    #[must_use]
    pub const fn capacity(&self) -> usize {
        SETS * WAYS
    }

    /// Looks up `block_address`, counts a hit or miss and, on a miss,
    /// allocates the least recently used way. Returns `(hit, set, way)`.
    #[inline]
    fn lookup(&mut self, block_address: u32) -> (bool, usize, usize) {
        self.lookup_n(block_address, 1)
    }

    /// `n ≥ 1` consecutive accesses of `block_address` as one lookup: the
    /// same tags, stamps and counters as `n` calls of
    /// [`lookup`](Self::lookup) (the first hits or misses, the others hit
    /// the block it found or loaded; the clock advances by `n` and the
    /// stamp is the last access's). Returns `(first hit, set, way)`.
    #[inline]
    fn lookup_n(&mut self, block_address: u32, n: u32) -> (bool, usize, usize) {
        let n = u64::from(n.max(1));
        self.clock = self.clock.wrapping_add(n);
        let set = block_address as usize % SETS;
        let (Some(tags), Some(stamps)) = (self.tags.get_mut(set), self.stamps.get_mut(set)) else {
            return (false, 0, 0);
        };
        // Tags first: a hit in a later way reads no earlier way's stamp
        // beyond the valid test.
        for (way, (tag, stamp)) in tags.iter().zip(stamps.iter_mut()).enumerate() {
            if *tag == block_address && *stamp != 0 {
                *stamp = self.clock;
                return (true, set, way);
            }
        }
        // A miss: the first empty way (stamp 0), else the least recently
        // used (the first smallest stamp).
        let mut victim = 0;
        let mut oldest = u64::MAX;
        for (way, &stamp) in stamps.iter().enumerate() {
            if stamp < oldest {
                oldest = stamp;
                victim = way;
            }
        }
        if let (Some(t), Some(s)) = (tags.get_mut(victim), stamps.get_mut(victim)) {
            *t = block_address;
            *s = self.clock;
        }
        self.misses = self.misses.wrapping_add(1);
        (false, set, victim)
    }

    /// Accesses `block_address`: `true` on a hit; on a miss the block
    /// replaces the set's least recently used way.
    #[inline]
    pub fn access(&mut self, block_address: u32) -> bool {
        self.lookup(block_address).0
    }

    /// Counters since construction or the last [`reset_stats`](Self::reset_stats).
    #[must_use]
    pub fn stats(&self) -> CacheStats {
        CacheStats {
            hits: self
                .clock
                .wrapping_sub(self.since)
                .wrapping_sub(self.misses),
            misses: self.misses,
        }
    }

    /// Zeroes the counters (contents stay).
    pub fn reset_stats(&mut self) {
        self.since = self.clock;
        self.misses = 0;
    }

    /// Empties the cache (counters stay).
    pub fn invalidate(&mut self) {
        self.stamps = [[0; WAYS]; SETS];
    }
}

/// Slow texel memory, read in whole blocks (the cache's backing store).
pub trait TexelMemory {
    /// The pyramid's geometry.
    fn geometry(&self) -> Geometry;
    /// Reads block `(bx, by)` of `level` (texels `4bx .. 4bx+4` ×
    /// `4by .. 4by+4`, row-major into `out`). Texels beyond the level's
    /// edge are filled with the nearest edge texel. Never panics.
    fn read_block(&mut self, level: u8, bx: u32, by: u32, out: &mut [Texel; BLOCK_TEXELS]);
}

impl TexelMemory for Pyramid<'_> {
    fn geometry(&self) -> Geometry {
        TexelSource::geometry(self)
    }

    fn read_block(&mut self, level: u8, bx: u32, by: u32, out: &mut [Texel; BLOCK_TEXELS]) {
        let x0 = bx.saturating_mul(BLOCK);
        let y0 = by.saturating_mul(BLOCK);
        for (i, t) in out.iter_mut().enumerate() {
            let (dx, dy) = ((i % 4) as u32, (i / 4) as u32);
            *t = self.get(level, x0.saturating_add(dx), y0.saturating_add(dy));
        }
    }
}

/// A texel cache (tags and data) of `SETS × WAYS` blocks of 4×4 texels in
/// front of a [`TexelMemory`]; itself a [`TexelSource`], returning exactly
/// what the memory holds. One access per texel read. Size of the data:
/// `SETS · WAYS · 64` bytes (e.g. 64 × 4 = 16 KiB).
///
/// # Example
/// ```
/// use raymip::{Geometry, Lod, Mode, Pyramid, Sampler, TexCoord, TexelCache};
/// let texels: Vec<u32> = (0..64).collect(); // 8×8, one level
/// let pyramid = Pyramid::new(Geometry::new(8, 8, 1)?, &texels)?;
/// // 4 sets × 2 ways of 4×4-texel blocks (512 bytes of data) in front of memory.
/// let cache: TexelCache<_, 4, 2> = TexelCache::new(pyramid);
/// let mut cached = Sampler::wrap(cache);
/// let mut direct = Sampler::wrap(pyramid);
/// let (u, v) = (TexCoord::from_num(0.3), TexCoord::from_num(0.7));
/// let mode = Mode::BilinearNearestLevel;
/// // The cache returns exactly what memory holds.
/// assert_eq!(cached.sample(u, v, Lod::ZERO, mode), direct.sample(u, v, Lod::ZERO, mode));
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Debug)]
pub struct TexelCache<M: TexelMemory, const SETS: usize, const WAYS: usize> {
    memory: M,
    layout: BlockLayout,
    tags: BlockCache<SETS, WAYS>,
    data: [[[Texel; BLOCK_TEXELS]; WAYS]; SETS],
    /// The last footprint read of an even level (entry 0) and of an odd
    /// one (entry 1): a trilinear sample's two levels keep one each.
    memo: [Memo; 2],
}

/// Where the blocks of a footprint are: its level and block columns and
/// rows, and the way (`set · WAYS + way`) holding each texel's block, all
/// four blocks cached there at once. Kept true by
/// [`TexelCache::fill`], which empties every memo naming the way it
/// refills, and [`TexelCache::invalidate`], which empties them all.
///
/// A footprint read through the memo writes no stamp: `replayed` keeps
/// the clock after its four accesses, and [`settle`] writes their stamps
/// before the next lookup, the only reader of stamps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Memo {
    /// The footprint's level as given to `footprint_in_level`, or
    /// [`Memo::EMPTY`].
    level: u32,
    /// Its two texel columns; only the block columns (`x >> 2`) are
    /// compared.
    x: [u32; 2],
    /// Its two texel rows; only the block rows are compared.
    y: [u32; 2],
    /// The way of the block of texels `(x0, y0)`, `(x1, y0)`, `(x0, y1)`,
    /// `(x1, y1)`, as an index into the flattened ways (`< SETS · WAYS`).
    way: [u32; 4],
    /// The clock after the last read through the memo whose stamps are
    /// not written yet (the stamp of `way[i]` is `replayed − 3 + i`), or
    /// 0 when there is none (the clock is at least 4 after a read).
    replayed: u64,
}

impl Memo {
    /// `level` of a memo that matches no footprint (levels are `u8`).
    const EMPTY: u32 = u32::MAX;

    /// A memo that matches no footprint.
    const NONE: Self = Self {
        level: Self::EMPTY,
        x: [0; 2],
        y: [0; 2],
        way: [0; 4],
        replayed: 0,
    };

    /// Makes the memo match no footprint (two stores, not a copy of
    /// [`NONE`](Self::NONE)).
    #[inline(always)]
    fn clear(&mut self) {
        self.level = Self::EMPTY;
        self.replayed = 0;
    }

    /// Whether the footprint `(level, x, y)` touches this memo's blocks,
    /// in the same places: the same level, block columns and block rows.
    #[inline(always)]
    fn matches(&self, level: u8, x: [u32; 2], y: [u32; 2]) -> bool {
        let blocks =
            (x[0] ^ self.x[0]) | (x[1] ^ self.x[1]) | (y[0] ^ self.y[0]) | (y[1] ^ self.y[1]);
        u32::from(level) == self.level && blocks >> BLOCK_SHIFT == 0
    }
}

impl<M: TexelMemory, const SETS: usize, const WAYS: usize> TexelCache<M, SETS, WAYS> {
    /// An empty cache in front of `memory`.
    pub fn new(memory: M) -> Self {
        let geometry = memory.geometry();
        Self {
            memory,
            layout: BlockLayout::new(&geometry),
            tags: BlockCache::new(),
            data: [[[0; BLOCK_TEXELS]; WAYS]; SETS],
            memo: [Memo::NONE; 2],
        }
    }

    /// Hit and miss counters.
    #[must_use]
    pub fn stats(&self) -> CacheStats {
        self.tags.stats()
    }

    /// Zeroes the counters (contents stay).
    pub fn reset_stats(&mut self) {
        self.tags.reset_stats();
    }

    /// Empties the cache (counters stay).
    pub fn invalidate(&mut self) {
        self.tags.invalidate();
        self.memo = [Memo::NONE; 2];
    }

    /// The backing memory.
    #[must_use]
    pub fn memory(&self) -> &M {
        &self.memory
    }

    /// Gives the backing memory back.
    #[must_use]
    pub fn into_memory(self) -> M {
        self.memory
    }
}

impl<M: TexelMemory, const SETS: usize, const WAYS: usize> TexelSource
    for TexelCache<M, SETS, WAYS>
{
    fn geometry(&self) -> Geometry {
        self.layout.geometry
    }

    #[inline]
    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
        let (level, g) = self.layout.grid(level);
        let [lx, ly] = g.last.map(u32::from);
        let (x, y) = (x.min(lx), y.min(ly));
        let (bx, by) = (x >> BLOCK_SHIFT, y >> BLOCK_SHIFT);
        let address = g.index(g.col_clamped(bx), g.row_clamped(by));
        settle(&mut self.tags, &mut self.memo);
        let way = self.way_of(level, bx, by, address, 1);
        self.read(way, in_block(x, y))
    }

    /// The footprint with one lookup per block it touches (one in 9 of 16
    /// positions, at most four), in the order of the texel reads, each
    /// counted as that many accesses: the same texels, counters and LRU
    /// stamps as four [`texel`](Self::texel) calls.
    #[inline]
    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        // The clamp of `texel`: the texel to the stored level's size.
        let (_, g) = self.layout.grid(level);
        let [lx, ly] = g.last.map(u32::from);
        self.footprint_in_level(level, x.map(|x| x.min(lx)), y.map(|y| y.min(ly)))
    }

    /// [`footprint`](Self::footprint) without the texel clamp (an index
    /// past the level reads a texel of another block). A footprint in the
    /// same blocks as the last one of its level parity (the memo) repeats
    /// that footprint's lookups without a tag compare: all four are hits
    /// in the ways the memo names, so they only advance the clock and
    /// write the stamps, exactly as the lookups would. Any other footprint
    /// is looked up (`footprint_lookups`).
    /// Out of line: one copy per cache type, however many sampler keys
    /// read the cache (flash).
    #[inline(never)]
    fn footprint_in_level(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        let memo = self.memo[usize::from(level & 1)];
        if !memo.matches(level, x, y) {
            return self.footprint_lookups(level, x, y);
        }
        let ways = memo.way.map(|w| w as usize);
        // Four hits: the clock advances, the stamps are written by
        // `settle`.
        let clock = self.tags.clock.wrapping_add(4);
        self.tags.clock = clock;
        if let Some(m) = self.memo.get_mut(usize::from(level & 1)) {
            m.replayed = clock;
        }
        [
            self.read(ways[0], in_block(x[0], y[0])),
            self.read(ways[1], in_block(x[1], y[0])),
            self.read(ways[2], in_block(x[0], y[1])),
            self.read(ways[3], in_block(x[1], y[1])),
        ]
    }
}

/// Index of texel `(x, y)` in its 4×4 block.
#[inline(always)]
fn in_block(x: u32, y: u32) -> usize {
    (((y & (BLOCK - 1)) << BLOCK_SHIFT) | (x & (BLOCK - 1))) as usize
}

/// Writes the stamps of the footprints read through `memo` since the last
/// lookup: for each memo with a read pending, the stamps its four
/// accesses would have written (the `i`-th texel's way gets the `i`-th
/// access's clock, in texel order, so a way named twice keeps the later
/// one), the older memo first (both can name the same ways when two levels
/// past the top are read as the top level). Called before every lookup,
/// it leaves the stamps those reads' lookups would have left.
#[inline(always)]
fn settle<const SETS: usize, const WAYS: usize>(
    tags: &mut BlockCache<SETS, WAYS>,
    memo: &mut [Memo; 2],
) {
    if memo[0].replayed | memo[1].replayed != 0 {
        write_replayed(tags, memo);
    }
}

/// [`settle`] with a read pending: out of line, one copy per cache type.
#[inline(never)]
fn write_replayed<const SETS: usize, const WAYS: usize>(
    tags: &mut BlockCache<SETS, WAYS>,
    memo: &mut [Memo; 2],
) {
    let older = usize::from(memo[1].replayed < memo[0].replayed);
    let stamps = tags.stamps.as_flattened_mut();
    let n = stamps.len();
    for k in [older, 1 - older] {
        let Some(m) = memo.get_mut(k) else { continue };
        if m.replayed != 0 {
            for (i, way) in (0..4u64).rev().zip(m.way) {
                // `way < n`: the remainder changes nothing and spares a check.
                if let Some(s) = stamps.get_mut(way as usize % n) {
                    *s = m.replayed.wrapping_sub(i);
                }
            }
            m.replayed = 0;
        }
    }
}

impl<M: TexelMemory, const SETS: usize, const WAYS: usize> TexelCache<M, SETS, WAYS> {
    /// [`footprint_in_level`](TexelSource::footprint_in_level) by one
    /// lookup per block the footprint touches, in the order of the texel
    /// reads, each counted as the accesses it stands for; then the
    /// footprint's memo (its level parity's) names the ways read. The
    /// block numbers come from one `LevelGrid` part per block column and
    /// row of the footprint; they are clamped to the padded grid, which a
    /// trimmed level past the last stored one can exceed. (Where one read
    /// of a block could evict another block of the same footprint in
    /// between, a one-way set shared by two side-by-side blocks, the four
    /// reads are made one by one.)
    #[inline(never)]
    fn footprint_lookups(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        settle(&mut self.tags, &mut self.memo);
        // This footprint's memo is written afresh below (or stays empty):
        // the fills on the way need not look at it.
        if let Some(m) = self.memo.get_mut(usize::from(level & 1)) {
            m.clear();
        }
        let (clamped, g) = self.layout.grid(level);
        let bx = [x[0] >> BLOCK_SHIFT, x[1] >> BLOCK_SHIFT];
        let by = [y[0] >> BLOCK_SHIFT, y[1] >> BLOCK_SHIFT];
        let c0 = g.col_clamped(bx[0]);
        let r0 = g.row_clamped(by[0]);
        let a = g.index(c0, r0);
        // Each texel is read right after its block's lookup: a later
        // lookup of the footprint may refill the way.
        let at = [
            in_block(x[0], y[0]),
            in_block(x[1], y[0]),
            in_block(x[0], y[1]),
            in_block(x[1], y[1]),
        ];
        let (way, address, texels) = if bx[0] == bx[1] && by[0] == by[1] {
            let w = self.way_of(clamped, bx[0], by[0], a, 4);
            ([w; 4], [a; 4], at.map(|k| self.read(w, k)))
        } else if bx[0] == bx[1] {
            // Reads t00, t10 (top block), t01, t11 (bottom block).
            let top = self.way_of(clamped, bx[0], by[0], a, 2);
            let (t00, t10) = (self.read(top, at[0]), self.read(top, at[1]));
            let c = g.index(c0, g.row_clamped(by[1]));
            let bottom = self.way_of(clamped, bx[0], by[1], c, 2);
            let (t01, t11) = (self.read(bottom, at[2]), self.read(bottom, at[3]));
            (
                [top, top, bottom, bottom],
                [a, a, c, c],
                [t00, t10, t01, t11],
            )
        } else {
            let c1 = g.col_clamped(bx[1]);
            let b = g.index(c1, r0);
            if by[0] != by[1] {
                // Four different blocks, each read once: four single
                // accesses in the order of the texel reads.
                let r1 = g.row_clamped(by[1]);
                let (c, d) = (g.index(c0, r1), g.index(c1, r1));
                let w00 = self.way_of(clamped, bx[0], by[0], a, 1);
                let t00 = self.read(w00, at[0]);
                let w10 = self.way_of(clamped, bx[1], by[0], b, 1);
                let t10 = self.read(w10, at[1]);
                let w01 = self.way_of(clamped, bx[0], by[1], c, 1);
                let t01 = self.read(w01, at[2]);
                let w11 = self.way_of(clamped, bx[1], by[1], d, 1);
                let t11 = self.read(w11, at[3]);
                ([w00, w10, w01, w11], [a, b, c, d], [t00, t10, t01, t11])
            } else if WAYS > 1 || a as usize % SETS != b as usize % SETS {
                // Reads alternate left, right, left, right. Neither block
                // can evict the other in between, so the left block's
                // three accesses (its second read is the third access)
                // then the right block's last one keep every tag, stamp
                // and counter of the four reads.
                let left = self.way_of(clamped, bx[0], by[0], a, 3);
                let (t00, t01) = (self.read(left, at[0]), self.read(left, at[2]));
                let right = self.way_of(clamped, bx[1], by[0], b, 1);
                let (t10, t11) = (self.read(right, at[1]), self.read(right, at[3]));
                (
                    [left, right, left, right],
                    [a, b, a, b],
                    [t00, t10, t01, t11],
                )
            } else {
                // One way shared by both blocks: each read may evict the
                // other block, so four single lookups, each texel read
                // before the next lookup, and no memo.
                let mut texels = [0; 4];
                for (i, t) in texels.iter_mut().enumerate() {
                    let (bx, address) = if i & 1 == 0 { (bx[0], a) } else { (bx[1], b) };
                    let w = self.way_of(clamped, bx, by[0], address, 1);
                    *t = self.read(w, at[i]);
                }
                return texels;
            }
        };
        self.remember(level, x, y, way, address);
        texels
    }

    /// Makes `(level, x, y)`, read from the flattened ways `way`, whose
    /// blocks are numbered `address`, its level parity's memo, if each
    /// way still holds its block (a later block of the footprint may have
    /// evicted an earlier one from a shared set); otherwise that memo
    /// stays empty.
    #[inline(always)]
    fn remember(
        &mut self,
        level: u8,
        x: [u32; 2],
        y: [u32; 2],
        way: [usize; 4],
        address: [u32; 4],
    ) {
        let tags = self.tags.tags.as_flattened();
        let n = tags.len();
        let held = way
            .iter()
            .zip(address)
            .all(|(&w, a)| tags.get(w % n) == Some(&a));
        if held {
            self.memo[usize::from(level & 1)] = Memo {
                level: u32::from(level),
                x,
                y,
                // `way < SETS · WAYS`, which a cache in memory keeps far
                // below 2³².
                way: way.map(|w| w as u32),
                replayed: 0,
            };
        }
    }

    /// Texel `k` (`< 16`) of the block in the flattened way `way` (`< SETS
    /// · WAYS`).
    #[inline(always)]
    fn read(&self, way: usize, k: usize) -> Texel {
        let blocks = self.data.as_flattened();
        // Both remainders change nothing and spare the checks.
        blocks
            .get(way % blocks.len())
            .map_or(0, |b| b[k % BLOCK_TEXELS])
    }

    /// The flattened way (`set · WAYS + way`) that holds block `(bx, by)`
    /// of `level` (`level` at most the top level, `bx`, `by` inside its
    /// block grid), whose block number is `address`, after `n` accesses
    /// to it: looked up once ([`BlockCache`]'s `lookup_n`, inlined),
    /// filled from memory on a miss ([`fill`](Self::fill), out of line).
    #[inline(always)]
    fn way_of(&mut self, level: u8, bx: u32, by: u32, address: u32, n: u32) -> usize {
        let (hit, set, way) = self.tags.lookup_n(address, n);
        if !hit {
            self.fill(level, bx, by, set, way);
        }
        set * WAYS + way
    }

    /// Reads block `(bx, by)` of `level` from memory into way `way` of set
    /// `set` (a miss: out of line, so that the hits stay short), and
    /// empties every memo that names that way.
    #[cold]
    #[inline(never)]
    fn fill(&mut self, level: u8, bx: u32, by: u32, set: usize, way: usize) {
        let flat = (set * WAYS + way) as u32;
        for memo in &mut self.memo {
            if memo.level != Memo::EMPTY && memo.way.contains(&flat) {
                memo.clear();
            }
        }
        if let Some(block) = self.data.get_mut(set).and_then(|s| s.get_mut(way)) {
            self.memory.read_block(level, bx, by, block);
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    /// A pyramid's texels with every texel different (a multiplicative
    /// hash of its index), so that a wrong texel read shows.
    fn hashed_texels(g: Geometry) -> Vec<Texel> {
        (0..g.len() as u32)
            .map(|i| i.wrapping_mul(2_654_435_761))
            .collect()
    }

    #[test]
    fn morton_interleaves() {
        // Bit i of x goes to bit 2i, bit i of y to bit 2i + 1 (16-bit
        // coordinates), one bit at a time.
        let interleave = |x: u32, y: u32| {
            (0..16).fold(0u32, |m, i| {
                m | ((x >> i) & 1) << (2 * i) | ((y >> i) & 1) << (2 * i + 1)
            })
        };
        // Every 257th coordinate (every 4369th under Miri) and the edges.
        let step = if cfg!(miri) { 4369 } else { 257 };
        let coords = (0..=0xFFFF).step_by(step).chain([1, 2, 3, 0xFFFE, 0xFFFF]);
        for x in coords.clone() {
            for y in coords.clone() {
                assert_eq!(morton2(x, y), interleave(x, y), "({x}, {y})");
            }
        }
        assert_eq!(morton2(3, 3), 15);
        assert_eq!(morton2(0xFFFF, 0), 0x5555_5555);
    }

    #[test]
    fn block_numbers_unique_and_bounded() {
        for (w, h, l) in [
            (64, 64, 7),
            (16, 256, 9),
            (1044 / 4, 13, 9),
            (1, 1, 1),
            (37, 5, 6),
        ] {
            let g = Geometry::new(w, h, l).unwrap();
            let layout = BlockLayout::new(&g);
            let mut seen = Vec::new();
            for k in 0..l {
                let (lw, lh) = g.level_size(k);
                for by in 0..lh.div_ceil(4) {
                    for bx in 0..lw.div_ceil(4) {
                        let i = layout.index(k, bx * 4, by * 4);
                        assert!(i < layout.len());
                        assert_eq!(i, layout.index(k, bx * 4 + 1, by * 4));
                        seen.push(i);
                    }
                }
            }
            let n = seen.len();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len(), n, "{w}x{h}");
            if w.is_power_of_two() && h.is_power_of_two() && w >= 4 && h >= 4 && l == 1 {
                assert_eq!(n as u32, layout.len());
            }
        }
        let g = Geometry::new(64, 64, 1).unwrap();
        assert_eq!(BlockLayout::new(&g).len(), 256);
    }

    /// A texel past the level's last column or row is in the last
    /// texel's block, as [`Geometry::texel_index`] clamps it: also where
    /// the padded block grid has a column or row past the level's blocks
    /// (sides that are multiples of the block but not powers of two),
    /// whose numbers a clamp to the wrong side would reach.
    #[test]
    fn texels_past_the_edge_are_in_the_last_block() {
        for (w, h, l) in [(12, 20, 3), (24, 40, 4), (37, 5, 6), (64, 64, 7)] {
            let g = Geometry::new(w, h, l).unwrap();
            let layout = BlockLayout::new(&g);
            for k in 0..l {
                let (lw, lh) = g.level_size(k);
                for past in [0, 1, 4, 5, u32::MAX - lw.max(lh)] {
                    for y in [0, lh / 2, lh - 1] {
                        let want = layout.index(k, lw - 1, y);
                        assert_eq!(layout.index(k, lw + past, y), want, "{w}x{h} {k} x {past}");
                    }
                    for x in [0, lw / 2, lw - 1] {
                        let want = layout.index(k, x, lh - 1);
                        assert_eq!(layout.index(k, x, lh + past), want, "{w}x{h} {k} y {past}");
                    }
                }
            }
        }
    }

    /// The per-axis parts of [`LevelGrid`] give the block numbers of the
    /// interleaved definition (the low bits of column and row interleaved,
    /// the high bits of the longer side above them, plus the level's
    /// offset) for every block of square, long, tall and odd-sized levels,
    /// unclamped as a footprint computes them.
    #[test]
    fn grid_parts_equal_interleaved_numbers() {
        for (w, h, l) in [
            (64, 64, 7),
            (16, 256, 9),
            (261, 13, 9),
            (1, 1, 1),
            (37, 5, 6),
        ] {
            let g = Geometry::new(w, h, l).unwrap();
            let layout = BlockLayout::new(&g);
            // Block columns and rows of each level, padded to powers of two.
            let padded = |k: u8| {
                let (lw, lh) = g.level_size(k);
                let n = |s: u32| s.div_ceil(BLOCK).next_power_of_two();
                (n(lw), n(lh))
            };
            let mut offset = 0;
            for k in 0..l {
                let (pw, ph) = padded(k);
                let low = pw.min(ph).trailing_zeros();
                let (_, grid) = layout.grid(k);
                let (lw, lh) = g.level_size(k);
                assert_eq!(grid.last, [(lw - 1) as u16, (lh - 1) as u16]);
                assert_eq!(grid.max(), [pw - 1, ph - 1]);
                for by in 0..lh.div_ceil(BLOCK) {
                    for bx in 0..lw.div_ceil(BLOCK) {
                        let m = (1 << low) - 1;
                        let high = (bx >> low) | (by >> low);
                        let want = offset + (morton2(bx & m, by & m) | (high << (2 * low)));
                        assert_eq!(
                            grid.index(grid.col(bx), grid.row(by)),
                            want,
                            "{k} {bx} {by}"
                        );
                        assert_eq!(layout.index_of_block(k, bx, by), want);
                    }
                }
                offset += pw * ph;
            }
            assert_eq!(layout.len(), offset);
        }
    }

    #[test]
    fn lru_replacement() {
        let mut c: BlockCache<1, 2> = BlockCache::new();
        assert!(!c.access(7));
        assert!(!c.access(u32::MAX));
        assert!(c.access(7));
        assert!(!c.access(0)); // evicts u32::MAX (least recently used)
        assert!(c.access(7));
        assert!(!c.access(u32::MAX));
        assert_eq!(c.stats(), CacheStats { hits: 2, misses: 4 });
        assert!((c.stats().hit_rate() - 1.0 / 3.0).abs() < 1e-12);
        c.reset_stats();
        assert_eq!(c.stats().hit_rate(), 0.0);
        c.invalidate();
        assert!(!c.access(7));
    }

    /// A miss fills the first empty way of its set (ways in order), then
    /// the least recently used one; a hit names the way that holds it.
    #[test]
    fn misses_fill_the_first_empty_way() {
        let mut c: BlockCache<1, 4> = BlockCache::new();
        assert_eq!(c.lookup(7), (false, 0, 0));
        assert_eq!(c.lookup(9), (false, 0, 1));
        assert_eq!(c.lookup(7), (true, 0, 0));
        assert_eq!(c.lookup(11), (false, 0, 2));
        assert_eq!(c.lookup(13), (false, 0, 3));
        // Way 1 (block 9) is now the least recently used.
        assert_eq!(c.lookup(15), (false, 0, 1));
        // Then way 0 (block 7, last used at the third access).
        assert_eq!(c.lookup(9), (false, 0, 0));
    }

    /// `capacity()` is the number of blocks the cache holds at once: a
    /// pass over `capacity()` consecutive blocks (`WAYS` per set) leaves
    /// every one cached, so a second pass only hits, while one block more
    /// puts `WAYS + 1` blocks in set 0 and a second pass misses. Sets and
    /// ways differ (4 × 3), so a sum, quotient or constant in place of
    /// `SETS · WAYS` fails.
    #[test]
    fn capacity_is_the_number_of_blocks_held() {
        fn second_pass_misses(blocks: u32) -> u64 {
            let mut c: BlockCache<4, 3> = BlockCache::new();
            for b in 0..blocks {
                let _ = c.access(b);
            }
            c.reset_stats();
            for b in 0..blocks {
                let _ = c.access(b);
            }
            c.stats().misses
        }
        let cap = BlockCache::<4, 3>::new().capacity();
        assert_eq!(cap, 12);
        let cap = u32::try_from(cap).unwrap();
        assert_eq!(second_pass_misses(cap), 0);
        assert!(second_pass_misses(cap + 1) > 0);
    }

    /// A footprint read with one lookup per block gives the texels, hit
    /// and miss counts and later behaviour of four single reads, for every
    /// block pattern (one block, two side by side, two above each other,
    /// four; wrapped taps), and caches of one and two ways.
    #[test]
    fn footprint_equals_four_texel_reads() {
        fn run<const S: usize, const W: usize>(p: Pyramid<'_>, g: Geometry) {
            let mut a: TexelCache<Pyramid<'_>, S, W> = TexelCache::new(p);
            let mut b: TexelCache<Pyramid<'_>, S, W> = TexelCache::new(p);
            let mut x = 0x2545_F491u32;
            for _ in 0..if cfg!(miri) { 60 } else { 3000 } {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                let level = (x % 4) as u8;
                let (w, h) = g.level_size(level);
                let (x0, y0) = ((x >> 8) % (w + 1), (x >> 20) % (h + 1));
                // The second tap: the next texel, wrapped, or the same.
                let x1 = [x0 + 1, 0, x0][(x >> 4) as usize % 3];
                let y1 = [y0 + 1, 0, y0][(x >> 6) as usize % 3];
                let want = [
                    b.texel(level, x0, y0),
                    b.texel(level, x1, y0),
                    b.texel(level, x0, y1),
                    b.texel(level, x1, y1),
                ];
                assert_eq!(a.footprint(level, [x0, x1], [y0, y1]), want);
                assert_eq!(a.stats(), b.stats(), "{level} {x0} {x1} {y0} {y1}");
            }
        }
        let g = Geometry::new(32, 16, 4).unwrap();
        let buf = hashed_texels(g);
        let p = Pyramid::new(g, &buf).unwrap();
        run::<1, 1>(p, g);
        run::<2, 1>(p, g);
        run::<4, 1>(p, g);
        run::<2, 2>(p, g);
        run::<8, 2>(p, g);
    }

    /// The tags, stamps, clock and counters of `a` equal `b`'s (tags
    /// only where a way is in use), and every memo of `a` names ways
    /// that hold its blocks: the memo never names an evicted block.
    fn assert_same_state<const S: usize, const W: usize>(
        a: &TexelCache<Pyramid<'_>, S, W>,
        b: &TexelCache<Pyramid<'_>, S, W>,
        what: &str,
    ) {
        // The stamps of `a` with the memo reads written.
        let (mut ta, mut memo) = (a.tags.clone(), a.memo);
        settle(&mut ta, &mut memo);
        let (ta, tb) = (&ta, &b.tags);
        assert_eq!(ta.stamps, tb.stamps, "{what}");
        assert_eq!(
            (ta.clock, ta.since, ta.misses),
            (tb.clock, tb.since, tb.misses),
            "{what}"
        );
        for (set, stamps) in ta.stamps.iter().enumerate() {
            for (way, &stamp) in stamps.iter().enumerate() {
                if stamp != 0 {
                    assert_eq!(ta.tags[set][way], tb.tags[set][way], "{what} {set} {way}");
                }
            }
        }
        assert_eq!(a.stats(), b.stats(), "{what}");
        for memo in a.memo.iter().filter(|m| m.level != Memo::EMPTY) {
            let level = memo.level as u8;
            let corners = [(0, 0), (1, 0), (0, 1), (1, 1)];
            for (&way, (i, j)) in memo.way.iter().zip(corners) {
                let block = a.layout.index(level, memo.x[i], memo.y[j]);
                let (set, w) = (way as usize / W, way as usize % W);
                assert_eq!(ta.tags[set][w], block, "{what}: memo {memo:?}");
                assert_ne!(ta.stamps[set][w], 0, "{what}: memo {memo:?}");
            }
        }
    }

    /// Footprints that repeat the blocks of a recent one (the memo path),
    /// new footprints, single texel reads (fills outside any footprint),
    /// invalidations and zeroed counters, interleaved: the texels, the
    /// counters, every stamp and tag equal four single reads per
    /// footprint, and no memo names a block that is no longer where it
    /// says, for caches whose sets are shared or not by a footprint's
    /// blocks (one to four ways, set counts not powers of two). Levels 4
    /// and 5 of the 4-level pyramid read level 3, so that the memos of
    /// both parities can name the same blocks.
    #[test]
    fn memo_keeps_the_state_of_texel_reads() {
        fn run<const S: usize, const W: usize>(p: Pyramid<'_>, g: Geometry) {
            let mut a: TexelCache<Pyramid<'_>, S, W> = TexelCache::new(p);
            let mut b: TexelCache<Pyramid<'_>, S, W> = TexelCache::new(p);
            let mut x = 0x9E37_79B9u32;
            let mut recent = [(0u8, [0u32; 2], [0u32; 2]); 4];
            let mut memo_hits = 0;
            for step in 0..if cfg!(miri) { 80 } else { 4000 } {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                match x % 16 {
                    0 => {
                        let level = ((x >> 4) % 6) as u8;
                        let (w, h) = g.level_size(level);
                        let (tx, ty) = ((x >> 8) % w, (x >> 20) % h);
                        assert_eq!(a.texel(level, tx, ty), b.texel(level, tx, ty));
                    }
                    1 if x >> 4 & 15 == 0 => {
                        a.invalidate();
                        b.invalidate();
                    }
                    1 if x >> 4 & 15 == 1 => {
                        a.reset_stats();
                        b.reset_stats();
                    }
                    k => {
                        let (level, fx, fy) = if k < 10 {
                            // Taps that move inside the blocks of a
                            // recent footprint.
                            let (level, mut fx, mut fy) = recent[(x >> 4) as usize % 4];
                            let (w, h) = g.level_size(level);
                            for (t, s) in fx.iter_mut().zip([8, 10]) {
                                *t = ((*t & !3) | (x >> s & 3)).min(w - 1);
                            }
                            for (t, s) in fy.iter_mut().zip([12, 14]) {
                                *t = ((*t & !3) | (x >> s & 3)).min(h - 1);
                            }
                            (level, fx, fy)
                        } else {
                            let level = ((x >> 4) % 6) as u8;
                            let (w, h) = g.level_size(level);
                            let (x0, y0) = ((x >> 8) % w, (x >> 20) % h);
                            let x1 = [(x0 + 1) % w, 0, x0][(x >> 6) as usize % 3];
                            let y1 = [(y0 + 1) % h, 0, y0][(x >> 7) as usize % 3];
                            (level, [x0, x1], [y0, y1])
                        };
                        recent[step % 4] = (level, fx, fy);
                        let before = a.memo[usize::from(level & 1)];
                        if before.matches(level, fx, fy) {
                            memo_hits += 1;
                        }
                        let want = [
                            b.texel(level, fx[0], fy[0]),
                            b.texel(level, fx[1], fy[0]),
                            b.texel(level, fx[0], fy[1]),
                            b.texel(level, fx[1], fy[1]),
                        ];
                        let got = if k % 2 == 0 {
                            a.footprint_in_level(level, fx, fy)
                        } else {
                            a.footprint(level, fx, fy)
                        };
                        assert_eq!(got, want, "{level} {fx:?} {fy:?}");
                    }
                }
                assert_same_state(&a, &b, &std::format!("{S}x{W} step {step}"));
            }
            assert!(
                memo_hits > if cfg!(miri) { 5 } else { 500 },
                "{S}x{W}: {memo_hits}"
            );
        }
        let g = Geometry::new(32, 16, 4).unwrap();
        let buf = hashed_texels(g);
        let p = Pyramid::new(g, &buf).unwrap();
        run::<1, 1>(p, g);
        run::<2, 1>(p, g);
        run::<4, 1>(p, g);
        run::<3, 1>(p, g);
        run::<1, 4>(p, g);
        run::<2, 2>(p, g);
        run::<3, 2>(p, g);
        run::<8, 2>(p, g);
    }

    /// A texel cache's counters restart from zero at `reset_stats`
    /// (contents stay: the next read hits), and `invalidate` empties it
    /// (counters stay: the next read misses), for single texels and for
    /// footprints.
    #[test]
    fn texel_cache_reset_and_invalidate() {
        let g = Geometry::new(9, 6, 4).unwrap();
        let buf = hashed_texels(g);
        let mut p = Pyramid::new(g, &buf).unwrap();
        let mut c: TexelCache<Pyramid<'_>, 2, 2> = TexelCache::new(p);
        let _ = c.texel(0, 1, 1);
        let _ = c.texel(0, 2, 1);
        assert_eq!(c.stats(), CacheStats { hits: 1, misses: 1 });
        c.reset_stats();
        assert_eq!(c.stats(), CacheStats::default());
        assert_eq!(c.texel(0, 1, 2), p.texel(0, 1, 2));
        assert_eq!(c.stats(), CacheStats { hits: 1, misses: 0 });
        c.invalidate();
        assert_eq!(c.texel(0, 1, 2), p.texel(0, 1, 2));
        assert_eq!(c.stats(), CacheStats { hits: 1, misses: 1 });
        let want = p.footprint_in_level(0, [0, 1], [0, 1]);
        assert_eq!(c.footprint_in_level(0, [0, 1], [0, 1]), want);
        assert_eq!(c.footprint_in_level(0, [0, 1], [0, 1]), want);
        c.reset_stats();
        c.invalidate();
        assert_eq!(c.footprint_in_level(0, [0, 1], [0, 1]), want);
        assert_eq!(c.stats(), CacheStats { hits: 3, misses: 1 });
    }

    #[test]
    fn cache_returns_memory_contents() {
        let g = Geometry::new(9, 6, 4).unwrap();
        let buf = hashed_texels(g);
        let mut p = Pyramid::new(g, &buf).unwrap();
        let mut c: TexelCache<Pyramid<'_>, 2, 2> = TexelCache::new(p);
        for k in 0..5u8 {
            for y in 0..8 {
                for x in 0..11 {
                    assert_eq!(c.texel(k, x, y), p.texel(k, x, y), "{k} {x} {y}");
                }
            }
        }
        assert!(c.stats().hits > 0 && c.stats().misses > 0);
    }
}
