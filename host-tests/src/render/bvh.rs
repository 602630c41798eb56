//! Binned-SAH bounding volume hierarchy over triangles (16 bins per axis,
//! leaves of at most 4 triangles), with closest-hit and any-hit queries.
//! Ray/triangle tests use Möller–Trumbore in f64.

use crate::scene::V3;

const BINS: usize = 16;
const MAX_LEAF: usize = 4;
const EPS: f64 = 1e-12;

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub lo: V3,
    /// Maximum corner.
    pub hi: V3,
}

impl Aabb {
    /// The empty box (grows to anything).
    pub const EMPTY: Self = Self {
        lo: V3::splat(f64::INFINITY),
        hi: V3::splat(f64::NEG_INFINITY),
    };
    /// Grows to contain point `p`.
    pub fn grow_p(&mut self, p: V3) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(p[k]);
            self.hi[k] = self.hi[k].max(p[k]);
        }
    }
    /// Grows to contain box `b`.
    pub fn grow(&mut self, b: &Aabb) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(b.lo[k]);
            self.hi[k] = self.hi[k].max(b.hi[k]);
        }
    }
    /// Surface area (0 for the empty box).
    #[must_use]
    pub fn area(&self) -> f64 {
        let d = self.hi - self.lo;
        if d[0] < 0.0 {
            return 0.0;
        }
        2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    }
    /// Slab test: entry distance if the box is hit within `(0, tmax)`
    /// (`inv` = per-component reciprocal of the ray direction).
    #[inline]
    #[must_use]
    pub fn hit(&self, o: V3, inv: V3, tmax: f64) -> Option<f64> {
        let mut t0 = 0.0f64;
        let mut t1 = tmax;
        for k in 0..3 {
            let a = (self.lo[k] - o[k]) * inv[k];
            let b = (self.hi[k] - o[k]) * inv[k];
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            // NaN (0·inf) compares false and leaves the interval unchanged.
            if a > t0 {
                t0 = a;
            }
            if b < t1 {
                t1 = b;
            }
        }
        (t0 <= t1).then_some(t0)
    }
}

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// Leaf: first index into `order`; inner: index of the left child (right = left + 1).
    start: u32,
    /// Leaf: triangle count (≥ 1); inner: 0.
    count: u32,
}

/// A ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (not necessarily unit) direction.
    pub t: f64,
    /// Triangle index.
    pub tri: u32,
    /// Barycentric weight of vertex 1.
    pub b1: f64,
    /// Barycentric weight of vertex 2.
    pub b2: f64,
}

/// Work counters of traversals: nodes visited (entered) and primitives
/// tested at leaves (triangles, or instances at a top level).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    /// Nodes entered.
    pub nodes: u64,
    /// Leaf primitives tested.
    pub prims: u64,
}

/// A binned-SAH hierarchy over primitive boxes (no primitives of its own):
/// the bottom level over triangles ([`Bvh`]) and top levels over instances
/// share it.
#[derive(Clone, Debug)]
pub struct Hierarchy {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Hierarchy {
    /// Builds over primitive boxes (index = primitive id).
    #[must_use]
    pub fn build(boxes: &[Aabb]) -> Self {
        let n = boxes.len();
        let cent: Vec<V3> = boxes.iter().map(|b| (b.lo + b.hi) * 0.5).collect();
        let mut order: Vec<u32> = (0..n as u32).collect();
        let mut nodes = Vec::with_capacity(2 * n.max(1));
        nodes.push(Node {
            bounds: Aabb::EMPTY,
            start: 0,
            count: n as u32,
        });
        if n > 0 {
            let mut work = vec![(0usize, 0usize, n)];
            while let Some((ni, s, e)) = work.pop() {
                let mut b = Aabb::EMPTY;
                let mut cb = Aabb::EMPTY;
                for &i in &order[s..e] {
                    b.grow(&boxes[i as usize]);
                    cb.grow_p(cent[i as usize]);
                }
                nodes[ni].bounds = b;
                nodes[ni].start = s as u32;
                nodes[ni].count = (e - s) as u32;
                if e - s <= MAX_LEAF {
                    continue;
                }
                let Some((axis, split)) = best_split(&order[s..e], boxes, &cent, &cb, b.area())
                else {
                    continue;
                };
                let (lo, ext) = (cb.lo[axis], cb.hi[axis] - cb.lo[axis]);
                let bin = |c: f64| (((c - lo) / ext * BINS as f64) as usize).min(BINS - 1);
                let mut m = s;
                for i in s..e {
                    if bin(cent[order[i] as usize][axis]) < split {
                        order.swap(i, m);
                        m += 1;
                    }
                }
                if m == s || m == e {
                    m = (s + e) / 2;
                }
                let l = nodes.len();
                nodes.push(Node {
                    bounds: Aabb::EMPTY,
                    start: 0,
                    count: 0,
                });
                nodes.push(Node {
                    bounds: Aabb::EMPTY,
                    start: 0,
                    count: 0,
                });
                nodes[ni].start = l as u32;
                nodes[ni].count = 0;
                work.push((l, s, m));
                work.push((l + 1, m, e));
            }
        }
        Self { nodes, order }
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes of the node and index arrays.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.order.len() * 4
    }

    /// Bounds of everything (the empty box for no primitives).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.nodes[0].bounds
    }

    /// Front-to-back traversal of the ray `o + t·d` (`inv` = `1/d` per
    /// component) up to `tmax`. `leaf(prim, tbest)` tests one primitive
    /// and returns its hit distance if it is closer than `tbest`; with
    /// `any` the first such hit ends the traversal. Returns the closest
    /// distance found (or `tmax`).
    pub fn traverse(
        &self,
        o: V3,
        inv: V3,
        tmax: f64,
        any: bool,
        stats: &mut TraversalStats,
        mut leaf: impl FnMut(u32, f64) -> Option<f64>,
    ) -> f64 {
        let mut tbest = tmax;
        if self.order.is_empty() || self.nodes[0].bounds.hit(o, inv, tbest).is_none() {
            return tbest;
        }
        let mut stack = [0u32; 128];
        let mut sp = 0usize;
        let mut cur = 0u32;
        loop {
            let node = &self.nodes[cur as usize];
            stats.nodes += 1;
            if node.count > 0 {
                let s = node.start as usize;
                for &pi in &self.order[s..s + node.count as usize] {
                    stats.prims += 1;
                    if let Some(t) = leaf(pi, tbest)
                        && t < tbest
                    {
                        tbest = t;
                        if any {
                            return tbest;
                        }
                    }
                }
            } else {
                let l = node.start;
                let hl = self.nodes[l as usize].bounds.hit(o, inv, tbest);
                let hr = self.nodes[l as usize + 1].bounds.hit(o, inv, tbest);
                match (hl, hr) {
                    (Some(a), Some(b)) => {
                        let (near, far) = if a <= b { (l, l + 1) } else { (l + 1, l) };
                        if sp < stack.len() {
                            stack[sp] = far;
                            sp += 1;
                        }
                        cur = near;
                        continue;
                    }
                    (Some(_), None) => {
                        cur = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        cur = l + 1;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop, skipping nodes now farther than the best hit.
            loop {
                if sp == 0 {
                    return tbest;
                }
                sp -= 1;
                let n = stack[sp];
                if self.nodes[n as usize].bounds.hit(o, inv, tbest).is_some() {
                    cur = n;
                    break;
                }
            }
        }
    }
}

/// The hierarchy plus a copy of the triangle positions.
#[derive(Clone, Debug)]
pub struct Bvh {
    hierarchy: Hierarchy,
    tris: Vec<[V3; 3]>,
}

impl Bvh {
    /// Builds over triangle positions (index = triangle id).
    #[must_use]
    pub fn build(tris: Vec<[V3; 3]>) -> Self {
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| {
                let mut b = Aabb::EMPTY;
                for p in t {
                    b.grow_p(*p);
                }
                b
            })
            .collect();
        Self {
            hierarchy: Hierarchy::build(&boxes),
            tris,
        }
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.hierarchy.node_count()
    }

    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// Triangle `i`'s positions.
    #[must_use]
    pub fn triangle(&self, i: u32) -> [V3; 3] {
        self.tris[i as usize]
    }

    /// Bounds of all triangles.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.hierarchy.bounds()
    }

    /// Bytes of the hierarchy and the triangle positions.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.hierarchy.bytes() + self.tris.len() * std::mem::size_of::<[V3; 3]>()
    }

    /// Closest hit with `t ∈ (tmin, tmax)`.
    #[must_use]
    pub fn closest(&self, o: V3, d: V3, tmin: f64, tmax: f64) -> Option<Hit> {
        self.query(o, d, tmin, tmax, false, &mut TraversalStats::default())
    }

    /// Any hit with `t ∈ (tmin, tmax)` (for shadows).
    #[must_use]
    pub fn any(&self, o: V3, d: V3, tmin: f64, tmax: f64) -> Option<Hit> {
        self.query(o, d, tmin, tmax, true, &mut TraversalStats::default())
    }

    /// Closest (or, with `any`, any) hit with `t ∈ (tmin, tmax)`, adding the
    /// work to `stats`.
    pub fn query(
        &self,
        o: V3,
        d: V3,
        tmin: f64,
        tmax: f64,
        any: bool,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        let inv = V3::new(1.0 / d[0], 1.0 / d[1], 1.0 / d[2]);
        let mut best: Option<Hit> = None;
        self.hierarchy
            .traverse(o, inv, tmax, any, stats, |ti, tbest| {
                let (t, b1, b2) = intersect(&self.tris[ti as usize], o, d)?;
                (t > tmin && t < tbest).then(|| {
                    best = Some(Hit { t, tri: ti, b1, b2 });
                    t
                })
            });
        best
    }
}

fn best_split(
    idx: &[u32],
    boxes: &[Aabb],
    cent: &[V3],
    cb: &Aabb,
    parent_area: f64,
) -> Option<(usize, usize)> {
    let mut best = (f64::INFINITY, 0usize, 0usize);
    for axis in 0..3 {
        let ext = cb.hi[axis] - cb.lo[axis];
        if ext <= EPS {
            continue;
        }
        let mut bb = [Aabb::EMPTY; BINS];
        let mut cnt = [0usize; BINS];
        for &i in idx {
            let c = cent[i as usize][axis];
            let b = (((c - cb.lo[axis]) / ext * BINS as f64) as usize).min(BINS - 1);
            bb[b].grow(&boxes[i as usize]);
            cnt[b] += 1;
        }
        let mut right_area = [0.0; BINS];
        let mut right_cnt = [0usize; BINS];
        let mut acc = Aabb::EMPTY;
        let mut c = 0;
        for b in (1..BINS).rev() {
            acc.grow(&bb[b]);
            c += cnt[b];
            right_area[b] = acc.area();
            right_cnt[b] = c;
        }
        let mut acc = Aabb::EMPTY;
        let mut c = 0;
        for split in 1..BINS {
            acc.grow(&bb[split - 1]);
            c += cnt[split - 1];
            if c == 0 || right_cnt[split] == 0 {
                continue;
            }
            let cost = acc.area() * c as f64 + right_area[split] * right_cnt[split] as f64;
            if cost < best.0 {
                best = (cost, axis, split);
            }
        }
    }
    // Leaf cost vs split cost (traversal cost 1, intersection cost 1).
    if best.0.is_finite()
        && (best.0 / parent_area.max(EPS) < idx.len() as f64 + 1.0 || idx.len() > 16)
    {
        Some((best.1, best.2))
    } else {
        None
    }
}

/// Möller–Trumbore: `(t, b1, b2)` or `None` (parallel or outside).
#[inline]
#[must_use]
pub fn intersect(tri: &[V3; 3], o: V3, d: V3) -> Option<(f64, f64, f64)> {
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-300 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let tv = o - tri[0];
    let b1 = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let qv = tv.cross(e1);
    let b2 = d.dot(qv) * inv;
    if b2 < 0.0 || b1 + b2 > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    Some((t, b1, b2))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(s: &mut u64) -> f64 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*s >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn matches_brute_force() {
        let mut s = 7u64;
        let mut tris = Vec::new();
        for _ in 0..500 {
            let c = V3::new(lcg(&mut s) * 10.0, lcg(&mut s) * 10.0, lcg(&mut s) * 10.0);
            let mut t = [V3::ZERO; 3];
            for p in &mut t {
                *p = V3::new(
                    c[0] + lcg(&mut s) - 0.5,
                    c[1] + lcg(&mut s) - 0.5,
                    c[2] + lcg(&mut s) - 0.5,
                );
            }
            tris.push(t);
        }
        let bvh = Bvh::build(tris.clone());
        let mut hits = 0;
        for _ in 0..2000 {
            let o = V3::new(lcg(&mut s) * 12.0 - 1.0, lcg(&mut s) * 12.0 - 1.0, -5.0);
            let d = V3::new(lcg(&mut s) - 0.5, lcg(&mut s) - 0.5, 1.0).normalize_or_zero();
            let mut want: Option<(f64, u32)> = None;
            for (i, t) in tris.iter().enumerate() {
                if let Some((tt, _, _)) = intersect(t, o, d)
                    && tt > 1e-9
                    && want.is_none_or(|w| tt < w.0)
                {
                    want = Some((tt, i as u32));
                }
            }
            let got = bvh.closest(o, d, 1e-9, f64::INFINITY);
            assert_eq!(got.map(|h| h.tri), want.map(|w| w.1));
            assert_eq!(bvh.any(o, d, 1e-9, f64::INFINITY).is_some(), want.is_some());
            hits += usize::from(want.is_some());
        }
        assert!(hits > 100, "test rays must hit something ({hits})");
    }
}
