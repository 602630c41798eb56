//! Object-space triangles, zero-area test and the tessellation of the
//! analytic primitives (`s` spheres, `c` cones).
//!
//! Tessellation resolution (BART kitchen and robots contain neither; the
//! museum scene has cylinders):
//! * sphere: [`SPHERE_SLICES`] = 32 longitude steps × [`SPHERE_STACKS`] = 16
//!   latitude steps → 2·32 cap triangles + 2·32·14 = 960 triangles, vertex
//!   normals radial (exact sphere normals, so shading is smooth);
//! * cone / cylinder: [`CONE_SEGMENTS`] = 32 sides → 64 triangles, open (no
//!   caps, as the format says), vertex normals those of the true cone.
//!
//! At 32 segments the chord deviates from the circle by
//! `r·(1 − cos(π/32)) ≈ 0.0048 r`.

use super::anim::V3;

/// Longitude steps of a tessellated sphere.
pub const SPHERE_SLICES: usize = 32;
/// Latitude steps of a tessellated sphere.
pub const SPHERE_STACKS: usize = 16;
/// Sides of a tessellated cone or cylinder.
pub const CONE_SEGMENTS: usize = 32;

/// A triangle before the transform stack is applied.
#[derive(Clone, Debug)]
pub(crate) struct RawTri {
    pub p: [V3; 3],
    pub n: Option<[V3; 3]>,
    pub uv: Option<[[f64; 2]; 3]>,
    pub material: u32,
    pub texture: Option<u32>,
    /// Transform node (index into the parser's node list; 0 = identity).
    pub node: u32,
}

/// Exactly zero area in object space: `(p1 − p0) × (p2 − p0) = 0` in f64
/// (repeated vertices or exactly collinear ones). Decided before any
/// transform so the count does not depend on rounding in the world matrix
/// (a non-singular affine map keeps zero area zero).
pub(crate) fn zero_area(p: &[V3; 3]) -> bool {
    (p[1] - p[0]).cross(p[2] - p[0]) == V3::ZERO
}

/// Exactly zero UV area.
pub(crate) fn zero_uv_area(uv: &[[f64; 2]; 3]) -> bool {
    let (a, b) = (
        [uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]],
        [uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]],
    );
    a[0] * b[1] - a[1] * b[0] == 0.0
}

/// Orders a triangle so its geometric normal agrees with the mean of its
/// vertex normals (counter-clockwise seen from the side the normals face).
fn oriented(p: [V3; 3], n: [V3; 3]) -> ([V3; 3], [V3; 3]) {
    let g = (p[1] - p[0]).cross(p[2] - p[0]);
    if g.dot((n[0] + n[1]) + n[2]) < 0.0 {
        ([p[0], p[2], p[1]], [n[0], n[2], n[1]])
    } else {
        (p, n)
    }
}

/// Two unit vectors perpendicular to unit `a` and to each other.
fn basis(a: V3) -> (V3, V3) {
    let helper = if a[0].abs() < 0.9 {
        V3::new(1.0, 0.0, 0.0)
    } else {
        V3::new(0.0, 1.0, 0.0)
    };
    let u = a
        .cross(helper)
        .try_normalize()
        .unwrap_or(V3::new(0.0, 0.0, 1.0));
    (u, a.cross(u))
}

/// Sphere at `c` with radius `|r|`; `r < 0` → normals point inward (only
/// the inside is visible). Returns (positions, normals) per triangle.
pub(crate) fn sphere(c: V3, r: f64) -> Vec<([V3; 3], [V3; 3])> {
    let sign = if r < 0.0 { -1.0 } else { 1.0 };
    let rad = r.abs();
    let dir = |i: usize, j: usize| -> V3 {
        let th = std::f64::consts::PI * i as f64 / SPHERE_STACKS as f64;
        let ph = std::f64::consts::TAU * j as f64 / SPHERE_SLICES as f64;
        V3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin())
    };
    let mut out = Vec::with_capacity(2 * SPHERE_SLICES * (SPHERE_STACKS - 1));
    let mut push = |d: [V3; 3]| {
        let p = d.map(|v| c + (v * rad));
        out.push(oriented(p, d.map(|v| v * sign)));
    };
    for i in 0..SPHERE_STACKS {
        for j in 0..SPHERE_SLICES {
            let (a, b) = (dir(i, j), dir(i, j + 1));
            let (cc, d) = (dir(i + 1, j), dir(i + 1, j + 1));
            if i != 0 {
                push([a, b, d]);
            }
            if i + 1 != SPHERE_STACKS {
                push([a, d, cc]);
            }
        }
    }
    out
}

/// Open cone from `base` (radius `rb`) to `apex` (radius `ra`); `rb < 0`
/// negates both radii and turns the normals inward. Empty for a zero-length
/// axis.
pub(crate) fn cone(base: V3, rb: f64, apex: V3, ra: f64) -> Vec<([V3; 3], [V3; 3])> {
    let (rb, ra, sign) = if rb < 0.0 {
        (-rb, -ra, -1.0)
    } else {
        (rb, ra, 1.0)
    };
    let axis = apex - base;
    let len = axis.dot(axis).sqrt();
    let Some(a) = axis.try_normalize() else {
        return Vec::new();
    };
    let (u, v) = basis(a);
    let ring = |j: usize| -> V3 {
        let ph = std::f64::consts::TAU * j as f64 / CONE_SEGMENTS as f64;
        (u * ph.cos()) + (v * ph.sin())
    };
    // Normal of the cone surface along generator d: ⟂ to the slant
    // L·a + (ra − rb)·d, in the plane of a and d.
    let normal = |d: V3| -> V3 {
        let n = (d * len) - (a * (ra - rb));
        n.try_normalize().unwrap_or(d) * sign
    };
    let mut out = Vec::with_capacity(2 * CONE_SEGMENTS);
    for j in 0..CONE_SEGMENTS {
        let (d0, d1) = (ring(j), ring(j + 1));
        let (b0, b1) = (base + (d0 * rb), base + (d1 * rb));
        let (a0, a1) = (apex + (d0 * ra), apex + (d1 * ra));
        let (n0, n1) = (normal(d0), normal(d1));
        for (p, n) in [([b0, b1, a1], [n0, n1, n1]), ([b0, a1, a0], [n0, n1, n0])] {
            if !zero_area(&p) {
                out.push(oriented(p, n));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_tessellation_is_closed_and_outward() {
        let tris = sphere(V3::new(1.0, 2.0, 3.0), 2.0);
        assert_eq!(tris.len(), 2 * SPHERE_SLICES * (SPHERE_STACKS - 1));
        let mut area = 0.0;
        for (p, n) in &tris {
            for (pi, ni) in p.iter().zip(n) {
                assert!(((*pi - V3::new(1.0, 2.0, 3.0)).length() - 2.0).abs() < 1e-12);
                assert!(((*ni).length() - 1.0).abs() < 1e-12);
            }
            let g = (p[1] - p[0]).cross(p[2] - p[0]);
            // Outward: geometric normal points away from the centre.
            let centroid = ((p[0] + p[1]) + p[2]) * (1.0 / 3.0);
            assert!(g.dot(centroid - V3::new(1.0, 2.0, 3.0)) > 0.0);
            area += 0.5 * g.length();
        }
        // Surface of the inscribed polyhedron: a little below 4πr².
        let exact = 4.0 * std::f64::consts::PI * 4.0;
        assert!(area < exact && area > 0.98 * exact, "{area} vs {exact}");
        // Inside-visible sphere: normals and winding point inward.
        for (p, n) in sphere(V3::ZERO, -1.0) {
            let g = (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(g.dot(p[0]) < 0.0 && n[0].dot(p[0]) < 0.0);
        }
    }

    #[test]
    fn cylinder_and_cone_normals() {
        let tris = cone(V3::ZERO, 1.0, V3::new(0.0, 2.0, 0.0), 1.0);
        assert_eq!(tris.len(), 2 * CONE_SEGMENTS);
        for (p, n) in &tris {
            for (pi, ni) in p.iter().zip(n) {
                // Cylinder: normal is the radial direction.
                assert!((ni[1]).abs() < 1e-12);
                assert!(((*ni).dot(V3::new(pi[0], 0.0, pi[2])) - 1.0).abs() < 1e-12);
            }
        }
        // Cone with radius 1 at base, 0 at apex (height 1): normals tilt
        // up by 45°.
        for (_, n) in cone(V3::ZERO, 1.0, V3::new(0.0, 1.0, 0.0), 0.0) {
            for ni in n {
                assert!((ni[1] - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
            }
        }
        assert!(cone(V3::ONE, 1.0, V3::ONE, 1.0).is_empty());
    }

    #[test]
    fn zero_area_cases() {
        assert!(zero_area(&[V3::ZERO, V3::ZERO, V3::new(1.0, 0.0, 0.0)]));
        assert!(zero_area(&[
            V3::ZERO,
            V3::new(1.0, 1.0, 1.0),
            V3::new(2.0, 2.0, 2.0)
        ]));
        assert!(!zero_area(&[
            V3::ZERO,
            V3::new(1.0, 0.0, 0.0),
            V3::new(0.0, 1e-30, 0.0)
        ]));
        assert!(zero_uv_area(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]));
        assert!(!zero_uv_area(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]));
    }
}
