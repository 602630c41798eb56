//! The scene of `builtin:instances` (stochastic geometric LOD, after
//! NVIDIA's "Implementing Stochastic Levels of Detail with DirectX
//! Raytracing", 2020): a 64 × 60 grid of randomly rotated instances of one
//! dense mesh ([`super::lodmesh`]: displaced icosphere, 81 920 triangles,
//! 8 LODs halving each time) on a ground plane, the four camera views and
//! the LOD colours. The renderer builds its bottom-level BVHs from these
//! meshes (`render::instances::InstanceScene`).

use raymip::rng::Rng;
use serde::Serialize;

use super::{Camera, V3};

/// Instances along x and z.
pub const GRID: (u32, u32) = (64, 60);
/// Distance between neighbouring instances (scene units; the mesh radius
/// is about 1).
pub const SPACING: f64 = 3.0;
/// Number of LODs.
pub const LEVELS: u8 = 8;
/// Icosphere subdivisions of LOD 0 (20·4⁶ = 81 920 triangles).
pub const SUBDIVISIONS: u32 = 6;
/// Camera-space depth of LOD 0 (scene units).
pub const Z_NEAR: f64 = 4.0;
/// Camera-space depth where the LOD parameter reaches `L` = 8.
pub const Z_FAR: f64 = 300.0;
/// Default image size.
pub const DEFAULT_SIZE: (u32, u32) = (800, 480);
/// Index of the ground mesh among the meshes (after the LODs).
pub const GROUND: u32 = LEVELS as u32;
/// Height of the instance centres above the ground.
const CENTRE_Y: f64 = 1.25;
/// Camera views of the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum View {
    /// Straight down from 250 units: every instance far (coarse LODs).
    Top,
    /// Oblique from 30 units up: near rows fine, far rows coarse.
    High,
    /// Grazing, 3 units above the ground across the whole grid.
    Low,
    /// A few units from one instance of the front row.
    Close,
}

impl View {
    /// Every view.
    pub const ALL: [Self; 4] = [Self::Top, Self::High, Self::Low, Self::Close];

    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Top => "top",
            Self::High => "high",
            Self::Low => "low",
            Self::Close => "close",
        }
    }

    /// The camera at `width`×`height`.
    #[must_use]
    pub fn camera(self, width: u32, height: u32) -> Camera {
        let front = (f64::from(GRID.1) - 1.0) / 2.0 * SPACING; // z of the front row
        let (from, at, fov) = match self {
            Self::Top => (V3::new(0.0, 250.0, 0.01), V3::new(0.0, 0.0, 0.0), 45.0),
            Self::High => (
                V3::new(0.0, 30.0, front + 25.0),
                V3::new(0.0, 0.0, front - 50.0),
                50.0,
            ),
            Self::Low => (
                V3::new(0.0, 3.0, front + 6.0),
                V3::new(0.0, 1.5, front - 60.0),
                50.0,
            ),
            Self::Close => (
                V3::new(4.3, 2.6, front + 4.4),
                V3::new(1.5, 1.1, front),
                40.0,
            ),
        };
        Camera::looking_at(from, at, fov, (width, height))
    }
}

/// A rotation matrix (rows), object → world.
pub type Mat3 = [V3; 3];

/// A rotation from a unit quaternion `(w, x, y, z)` (normalised here).
#[must_use]
pub fn rotation_from_quaternion(q: [f64; 4]) -> Mat3 {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let [w, x, y, z] = q.map(|c| c / n);
    [
        V3::new(
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ),
        V3::new(
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ),
        V3::new(
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ),
    ]
}

/// One grid cell: where the instance stands and how it looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Object → world rotation.
    pub rotation: Mat3,
    /// Centre.
    pub translation: V3,
    /// Diffuse colour.
    pub albedo: V3,
}

/// The ground quad under the grid (two triangles, 40 units past the grid
/// on every side).
#[must_use]
pub fn ground() -> Vec<[V3; 3]> {
    let (hx, hz) = (
        f64::from(GRID.0) * SPACING * 0.5 + 40.0,
        f64::from(GRID.1) * SPACING * 0.5 + 40.0,
    );
    let g = |x: f64, z: f64| V3::new(x, 0.0, z);
    vec![
        [g(-hx, -hz), g(-hx, hz), g(hx, hz)],
        [g(-hx, -hz), g(hx, hz), g(hx, -hz)],
    ]
}

/// The grid cells (id = index), row by row: each instance uniformly
/// randomly rotated and coloured by the firmware generator seeded
/// `0x5EED_0001`.
#[must_use]
pub fn placements() -> Vec<Placement> {
    let mut rng = Rng::new(0x5EED_0001);
    let mut uni = move || f64::from(rng.next_u32()) / 4_294_967_296.0;
    let mut placements = Vec::with_capacity((GRID.0 * GRID.1) as usize);
    for j in 0..GRID.1 {
        for i in 0..GRID.0 {
            // Uniform random rotation (Shoemake's quaternion from three uniforms).
            let (u1, u2, u3) = (uni(), uni(), uni());
            let tau = std::f64::consts::TAU;
            let q = [
                (1.0 - u1).sqrt() * (tau * u2).sin(),
                (1.0 - u1).sqrt() * (tau * u2).cos(),
                u1.sqrt() * (tau * u3).sin(),
                u1.sqrt() * (tau * u3).cos(),
            ];
            let hue = uni();
            placements.push(Placement {
                rotation: rotation_from_quaternion(q),
                translation: V3::new(
                    (f64::from(i) - (f64::from(GRID.0) - 1.0) / 2.0) * SPACING,
                    CENTRE_Y,
                    (f64::from(j) - (f64::from(GRID.1) - 1.0) / 2.0) * SPACING,
                ),
                albedo: (V3::splat(0.25) + (hue_color(hue * 300.0) * 0.5)),
            });
        }
    }
    placements
}

/// HSV hue (degrees, full saturation, value 0.9) to linear RGB.
fn hue_color(h: f64) -> V3 {
    let h = h.rem_euclid(360.0) / 60.0;
    let x = 1.0 - (h % 2.0 - 1.0).abs();
    let c = match h as u32 {
        0 => V3::new(1.0, x, 0.0),
        1 => V3::new(x, 1.0, 0.0),
        2 => V3::new(0.0, 1.0, x),
        3 => V3::new(0.0, x, 1.0),
        4 => V3::new(x, 0.0, 1.0),
        _ => V3::new(1.0, 0.0, x),
    };
    c * 0.9
}

/// Colour of LOD `l`: LOD 0 red, then through yellow, green and cyan to
/// LOD 7 blue (hue 0° … 240°).
#[must_use]
pub fn lod_color(l: u8) -> V3 {
    hue_color(240.0 * f64::from(l.min(LEVELS - 1)) / f64::from(LEVELS - 1))
}
