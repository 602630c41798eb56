//! The dense procedural mesh of `builtin:instances` and its chain of
//! geometric LODs: a displaced icosphere (subdivided 6 times: 81 920
//! triangles, 40 962 shared vertices, radius about 1) simplified with
//! meshoptimizer (the `meshopt` crate) to about half the triangles per
//! level, so the 8th LOD has about 128× fewer triangles than the first.

use std::collections::HashMap;

use crate::scene::V3;

/// An indexed triangle mesh (f32 positions, as the simplifier takes them).
#[derive(Clone, Debug, PartialEq)]
pub struct IndexedMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Three vertex indices per triangle.
    pub indices: Vec<u32>,
}

impl IndexedMesh {
    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Triangle positions in f64 (the BVH's input).
    #[must_use]
    pub fn triangles(&self) -> Vec<[V3; 3]> {
        self.indices
            .chunks_exact(3)
            .map(|t| {
                let p = |i: u32| {
                    let q = self.positions[i as usize];
                    V3::new(f64::from(q[0]), f64::from(q[1]), f64::from(q[2]))
                };
                [p(t[0]), p(t[1]), p(t[2])]
            })
            .collect()
    }
}

/// Radial displacement of the unit sphere at direction `n`: smooth bumps
/// of three frequencies, in `[−0.17, 0.17]`.
#[must_use]
pub fn displacement(n: V3) -> f64 {
    let [x, y, z] = n.to_array();
    0.09 * (5.0 * x).sin() * (5.0 * y).sin() * (5.0 * z).sin()
        + 0.05 * (11.0 * x + 2.0 * z).sin() * (9.0 * y - 3.0 * x).cos()
        + 0.03 * (23.0 * z + 7.0 * y).sin()
}

/// An icosphere with `subdivisions` 4-to-1 splits (20·4ⁿ triangles,
/// shared vertices), displaced along the normal by [`displacement`].
#[must_use]
pub fn displaced_icosphere(subdivisions: u32) -> IndexedMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pos: Vec<V3> = [
        V3::new(-1.0, g, 0.0),
        V3::new(1.0, g, 0.0),
        V3::new(-1.0, -g, 0.0),
        V3::new(1.0, -g, 0.0),
        V3::new(0.0, -1.0, g),
        V3::new(0.0, 1.0, g),
        V3::new(0.0, -1.0, -g),
        V3::new(0.0, 1.0, -g),
        V3::new(g, 0.0, -1.0),
        V3::new(g, 0.0, 1.0),
        V3::new(-g, 0.0, -1.0),
        V3::new(-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&p| p.normalize_or_zero())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, pos: &mut Vec<V3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                pos.push((pos[a as usize] + pos[b as usize]).normalize_or_zero());
                (pos.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let ab = midpoint(a, b, &mut pos);
            let bc = midpoint(b, c, &mut pos);
            let ca = midpoint(c, a, &mut pos);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    IndexedMesh {
        positions: pos
            .iter()
            .map(|&n| {
                let p = n * (1.0 + displacement(n));
                [p[0] as f32, p[1] as f32, p[2] as f32]
            })
            .collect(),
        indices: tris.into_iter().flatten().collect(),
    }
}

/// `levels` LODs of `mesh`: level 0 is the mesh itself, level `i` is
/// simplified by meshoptimizer from level 0 to a target of
/// `triangles/2ⁱ` (target error 1.0 relative to the mesh extent, so the
/// target count, not an error limit, stops it).
#[must_use]
pub fn lod_chain(mesh: &IndexedMesh, levels: usize) -> Vec<IndexedMesh> {
    let mut out = vec![mesh.clone()];
    for i in 1..levels {
        let target = (mesh.indices.len() >> i) / 3 * 3;
        let indices = meshopt::simplify_decoder(
            &mesh.indices,
            &mesh.positions,
            target,
            1.0,
            meshopt::SimplifyOptions::None,
            None,
        );
        out.push(IndexedMesh {
            positions: mesh.positions.clone(),
            indices,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_counts_and_closed() {
        let m = displaced_icosphere(2);
        assert_eq!(m.triangle_count(), 320);
        assert_eq!(m.positions.len(), 162); // 10·4ⁿ + 2
        // Closed 2-manifold: every edge used exactly twice.
        let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
        for t in m.indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        assert!(edges.values().all(|&n| n == 2));
        for p in &m.positions {
            let r = f64::from(p[0].hypot(p[1]).hypot(p[2]));
            assert!((0.8..=1.2).contains(&r), "{r}");
        }
    }

    #[test]
    fn lod_chain_halves() {
        let m = displaced_icosphere(4); // 5120 triangles
        let chain = lod_chain(&m, 5);
        for w in chain.windows(2) {
            let r = w[1].triangle_count() as f64 / w[0].triangle_count() as f64;
            assert!((0.4..=0.6).contains(&r), "ratio {r}");
        }
    }
}
