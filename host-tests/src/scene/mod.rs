//! The renderer's scene: triangles only (spheres are tessellated), with
//! per-vertex normals and UVs, materials, point lights and a pinhole camera.
//! [`aff_adapter`] converts a loaded AFF scene; [`load_scene`] loads
//! `builtin:NAME` or an AFF file.

pub mod aff;
pub mod builtin;
pub mod instances;
mod load;
pub mod lodmesh;
pub mod ppm;

pub use load::{default_bart_dir, load_aff, load_scene, load_scene_dir};

/// A 3-vector of scene units.
pub type V3 = [f64; 3];

/// Pinhole camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub from: V3,
    /// Point looked at.
    pub at: V3,
    /// Up hint.
    pub up: V3,
    /// Full vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// Whitted material (all colours linear, 0..1).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Ambient reflectance.
    pub ambient: V3,
    /// Diffuse reflectance (multiplied by the texture colour when textured).
    pub diffuse: V3,
    /// Specular reflectance: highlight and mirror reflection weight.
    pub specular: V3,
    /// Phong exponent.
    pub shine: f64,
    /// Transmission weight (refraction).
    pub transmission: V3,
    /// Index of refraction of the inside.
    pub ior: f64,
}

/// Point light.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Position.
    pub position: V3,
    /// Colour (intensity).
    pub color: V3,
}

/// A texture's level 0: RGBA8888 texels (`u32::from_le_bytes([r,g,b,a])`),
/// row-major, any size ≥ 1×1.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureImage {
    /// Name (file or procedural).
    pub name: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width·height` texels.
    pub texels: Vec<u32>,
}

/// One triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct Triangle {
    /// Vertex positions.
    pub p: [V3; 3],
    /// Per-vertex normals (interpolated, Phong); `None` = flat.
    pub n: Option<[V3; 3]>,
    /// Per-vertex UVs in texture repeats; required for texturing.
    pub uv: Option<[[f64; 2]; 3]>,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Index into [`Scene::textures`].
    pub texture: Option<u32>,
}

impl Triangle {
    /// True if the triangle is textured (texture and UVs present).
    #[must_use]
    pub fn is_textured(&self) -> bool {
        self.texture.is_some() && self.uv.is_some()
    }
}

/// A renderable scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Camera.
    pub camera: Camera,
    /// Colour of rays that hit nothing.
    pub background: V3,
    /// Global ambient light.
    pub ambient: V3,
    /// Point lights.
    pub lights: Vec<Light>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Textures (level 0).
    pub textures: Vec<TextureImage>,
    /// Triangles.
    pub triangles: Vec<Triangle>,
}

impl Scene {
    /// Number of textured triangles.
    #[must_use]
    pub fn textured_count(&self) -> usize {
        self.triangles.iter().filter(|t| t.is_textured()).count()
    }
}

/// Vector helpers.
pub mod v {
    use super::V3;
    /// a + b
    #[must_use]
    pub fn add(a: V3, b: V3) -> V3 {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }
    /// a − b
    #[must_use]
    pub fn sub(a: V3, b: V3) -> V3 {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    /// a·s
    #[must_use]
    pub fn scale(a: V3, s: f64) -> V3 {
        [a[0] * s, a[1] * s, a[2] * s]
    }
    /// a ∘ b (component-wise)
    #[must_use]
    pub fn mul(a: V3, b: V3) -> V3 {
        [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
    }
    /// a·b
    #[must_use]
    pub fn dot(a: V3, b: V3) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }
    /// a×b
    #[must_use]
    pub fn cross(a: V3, b: V3) -> V3 {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    /// |a|
    #[must_use]
    pub fn len(a: V3) -> f64 {
        dot(a, a).sqrt()
    }
    /// a/|a| (zero stays zero)
    #[must_use]
    pub fn norm(a: V3) -> V3 {
        let l = len(a);
        if l > 0.0 { scale(a, 1.0 / l) } else { a }
    }
    /// a + b·s
    #[must_use]
    pub fn madd(a: V3, b: V3, s: f64) -> V3 {
        [a[0] + b[0] * s, a[1] + b[1] * s, a[2] + b[2] * s]
    }
    /// max component
    #[must_use]
    pub fn max_c(a: V3) -> f64 {
        a[0].max(a[1]).max(a[2])
    }
}

/// Converts a loaded AFF scene (textures to RGBA8888 level 0).
#[must_use]
pub fn aff_adapter(s: aff::Scene) -> Scene {
    let c = s.camera;
    Scene {
        camera: Camera {
            from: c.from,
            at: c.at,
            up: c.up,
            fov_y_deg: c.fov_y_deg,
            width: c.width,
            height: c.height,
        },
        background: s.background,
        ambient: s.ambient,
        lights: s
            .lights
            .into_iter()
            .map(|l| Light {
                position: l.position,
                color: l.color,
            })
            .collect(),
        materials: s
            .materials
            .into_iter()
            .map(|m| Material {
                ambient: m.ambient,
                diffuse: m.diffuse,
                specular: m.specular,
                shine: m.shine,
                transmission: m.transmission,
                ior: m.ior,
            })
            .collect(),
        textures: s
            .textures
            .into_iter()
            .map(|t| TextureImage {
                name: t.name,
                width: t.image.width,
                height: t.image.height,
                texels: t.image.to_rgba8888(),
            })
            .collect(),
        triangles: s
            .triangles
            .into_iter()
            .map(|t| Triangle {
                p: t.p,
                n: t.n,
                uv: t.uv,
                material: t.material,
                texture: t.texture,
            })
            .collect(),
    }
}
