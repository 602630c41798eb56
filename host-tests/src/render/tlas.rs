//! Two-level BVH: a top level over instances (each a rigid transform, a
//! bottom-level mesh and an 8-bit instance mask) and one bottom-level
//! [`Bvh`] per mesh (per LOD). The instance mask is tested against the
//! ray's mask at the top-level leaf, before the ray enters the instance
//! (as DXR does), with the firmware's [`raymip::geomlod::visible`]. Both
//! levels are the binned-SAH [`Hierarchy`] of [`super::bvh`].

use raymip::geomlod::visible;

use super::bvh::{Aabb, Bvh, Hierarchy, Hit, TraversalStats};
use crate::scene::V3;
use crate::scene::instances::Mat3;

/// One instance: `world = rotation · object + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Orthonormal rotation, object → world.
    pub rotation: Mat3,
    /// World position of the object origin.
    pub translation: V3,
    /// Index of the bottom-level mesh.
    pub mesh: u32,
    /// 8-bit instance mask.
    pub mask: u8,
    /// The caller's id (e.g. the grid cell), reported with hits.
    pub id: u32,
}

impl Instance {
    /// World point of object point `p`.
    #[must_use]
    pub fn to_world(&self, p: V3) -> V3 {
        mul(&self.rotation, p) + self.translation
    }

    /// World vector of object vector `d`.
    #[must_use]
    pub fn dir_to_world(&self, d: V3) -> V3 {
        mul(&self.rotation, d)
    }

    /// Object vector of world vector `d` (transpose of the rotation).
    #[must_use]
    pub fn dir_to_object(&self, d: V3) -> V3 {
        let r = &self.rotation;
        V3::new(
            r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2],
            r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2],
            r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2],
        )
    }
}

fn mul(m: &Mat3, p: V3) -> V3 {
    V3::new(m[0].dot(p), m[1].dot(p), m[2].dot(p))
}

/// A hit in the two-level structure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceHit {
    /// Index into [`TwoLevel::instances`].
    pub instance: u32,
    /// The triangle hit in the instance's mesh (object space).
    pub hit: Hit,
}

/// Work counters of two-level traversals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TwoLevelStats {
    /// Top level: nodes entered, instances tested.
    pub top: TraversalStats,
    /// Bottom level: nodes entered, triangles tested.
    pub bottom: TraversalStats,
    /// Instances skipped because `instance_mask & ray_mask == 0`.
    pub masked: u64,
}

impl TwoLevelStats {
    /// Sums counters.
    pub fn add(&mut self, o: &Self) {
        add_fields!(self, o; top.nodes, top.prims, bottom.nodes, bottom.prims, masked);
    }
}

/// The two-level BVH over borrowed bottom levels.
#[derive(Clone, Debug)]
pub struct TwoLevel<'a> {
    meshes: &'a [Bvh],
    instances: Vec<Instance>,
    top: Hierarchy,
}

impl<'a> TwoLevel<'a> {
    /// Builds the top level over `instances` of `meshes`.
    ///
    /// # Panics
    /// If an instance names a mesh outside `meshes`.
    #[must_use]
    pub fn build(meshes: &'a [Bvh], instances: Vec<Instance>) -> Self {
        let boxes: Vec<Aabb> = instances
            .iter()
            .map(|inst| {
                let b = meshes[inst.mesh as usize].bounds();
                let mut w = Aabb::EMPTY;
                for k in 0..8 {
                    let c = V3::new(
                        if k & 1 == 0 { b.lo[0] } else { b.hi[0] },
                        if k & 2 == 0 { b.lo[1] } else { b.hi[1] },
                        if k & 4 == 0 { b.lo[2] } else { b.hi[2] },
                    );
                    w.grow_p(inst.to_world(c));
                }
                w
            })
            .collect();
        Self {
            meshes,
            top: Hierarchy::build(&boxes),
            instances,
        }
    }

    /// The instances (index = [`InstanceHit::instance`]).
    #[must_use]
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Bytes of the top level (nodes, index, instance records).
    #[must_use]
    pub fn top_bytes(&self) -> usize {
        self.top.bytes() + self.instances.len() * std::mem::size_of::<Instance>()
    }

    /// Closest (or with `any`, any) hit with `t ∈ (tmin, tmax)` among the
    /// instances visible to `ray_mask`.
    pub fn query(
        &self,
        o: V3,
        d: V3,
        (tmin, tmax): (f64, f64),
        ray_mask: u8,
        any: bool,
        stats: &mut TwoLevelStats,
    ) -> Option<InstanceHit> {
        let inv = V3::new(1.0 / d[0], 1.0 / d[1], 1.0 / d[2]);
        let mut best = None;
        let (top, rest) = (&mut stats.top, (&mut stats.bottom, &mut stats.masked));
        let (bottom, masked) = rest;
        self.top.traverse(o, inv, tmax, any, top, |i, tbest| {
            let inst = &self.instances[i as usize];
            if !visible(inst.mask, ray_mask) {
                *masked += 1;
                return None;
            }
            let oo = inst.dir_to_object(o - inst.translation);
            let od = inst.dir_to_object(d);
            let h = self.meshes[inst.mesh as usize].query(oo, od, tmin, tbest, any, bottom)?;
            best = Some(InstanceHit {
                instance: i,
                hit: h,
            });
            Some(h.t)
        });
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::bvh::intersect;
    use crate::scene::instances::rotation_from_quaternion;

    fn lcg(s: &mut raymip::rng::Rng) -> f64 {
        f64::from(s.next_u32()) / 4_294_967_296.0
    }

    /// Against brute force over all world-space triangles of the visible
    /// instances, for random masks.
    #[test]
    fn matches_brute_force_with_masks() {
        let mut s = raymip::rng::Rng::new(3);
        let meshes: Vec<Bvh> = (0..3)
            .map(|_| {
                Bvh::build(
                    (0..40)
                        .map(|_| {
                            let c = V3::new(
                                lcg(&mut s) * 2.0 - 1.0,
                                lcg(&mut s) * 2.0 - 1.0,
                                lcg(&mut s) * 2.0 - 1.0,
                            );
                            [0, 1, 2].map(|_| {
                                c + V3::new(
                                    lcg(&mut s) * 0.6 - 0.3,
                                    lcg(&mut s) * 0.6 - 0.3,
                                    lcg(&mut s) * 0.6 - 0.3,
                                )
                            })
                        })
                        .collect(),
                )
            })
            .collect();
        let instances: Vec<Instance> = (0..30)
            .map(|i| Instance {
                rotation: rotation_from_quaternion([
                    lcg(&mut s) - 0.5,
                    lcg(&mut s) - 0.5,
                    lcg(&mut s) - 0.5,
                    lcg(&mut s) - 0.5,
                ]),
                translation: V3::new(lcg(&mut s) * 10.0, lcg(&mut s) * 10.0, lcg(&mut s) * 3.0),
                mesh: i % 3,
                mask: (lcg(&mut s) * 256.0) as u8,
                id: i,
            })
            .collect();
        let tl = TwoLevel::build(&meshes, instances.clone());
        let mut hits = 0;
        for _ in 0..1500 {
            let o = V3::new(lcg(&mut s) * 10.0, lcg(&mut s) * 10.0, -5.0);
            let d = V3::new(lcg(&mut s) - 0.5, lcg(&mut s) - 0.5, 1.0).normalize_or_zero();
            let rm = 1u8 << (lcg(&mut s) * 8.0) as u32;
            let mut want: Option<(f64, u32)> = None;
            for (ii, inst) in instances.iter().enumerate() {
                if inst.mask & rm == 0 {
                    continue;
                }
                let m = &meshes[inst.mesh as usize];
                for ti in 0..m.triangle_count() as u32 {
                    let w = m.triangle(ti).map(|p| inst.to_world(p));
                    if let Some((t, _, _)) = intersect(&w, o, d)
                        && t > 1e-9
                        && want.is_none_or(|w| t < w.0)
                    {
                        want = Some((t, ii as u32));
                    }
                }
            }
            let mut st = TwoLevelStats::default();
            let got = tl.query(o, d, (1e-9, f64::INFINITY), rm, false, &mut st);
            assert_eq!(got.map(|h| h.instance), want.map(|w| w.1));
            if let (Some(g), Some(w)) = (got, want) {
                assert!((g.hit.t - w.0).abs() < 1e-9);
            }
            let any = tl.query(o, d, (1e-9, f64::INFINITY), rm, true, &mut st);
            assert_eq!(any.is_some(), want.is_some());
            hits += usize::from(want.is_some());
        }
        assert!(hits > 100, "{hits}");
    }

    #[test]
    fn quaternion_rotation_is_orthonormal() {
        let r = rotation_from_quaternion([0.3, -0.2, 0.9, 0.1]);
        for i in 0..3 {
            for j in 0..3 {
                let d = r[i].dot(r[j]);
                assert!((d - f64::from(u8::from(i == j))).abs() < 1e-12);
            }
        }
    }
}
