//! The renderer's scene: triangles only (spheres are tessellated), with
//! per-vertex normals and UVs, materials, point lights and a pinhole camera.
//! [`aff_adapter`] converts a loaded AFF scene; [`load_scene`] loads
//! `builtin:NAME` or an AFF file.

pub mod aff;
#[cfg(feature = "app")]
pub mod builtin;
#[cfg(feature = "app")]
pub mod instances;
#[cfg(feature = "app")]
mod load;
#[cfg(feature = "app")]
pub mod lodmesh;
pub mod ppm;

#[cfg(feature = "app")]
pub use load::{SceneError, default_bart_dir, load_aff, load_scene, load_scene_dir, scene_label};

/// A 3-vector of scene units (or a linear RGB colour): `glam`'s f64
/// vector, the one home of the harness's vector math.
pub type V3 = glam::DVec3;

/// Pinhole camera (built-in scenes and the AFF loader alike).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (scene units).
    pub from: V3,
    /// Point looked at.
    pub at: V3,
    /// Up hint (not necessarily unit nor orthogonal to the view direction).
    pub up: V3,
    /// Full vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f64,
    /// Near distance (> 0, scene units): AFF `hither` (values below 1e-4
    /// read as 1), 1 for the built-in scenes; the renderer does not clip.
    pub hither: f64,
    /// Image width in pixels (≥ 1).
    pub width: u32,
    /// Image height in pixels (≥ 1).
    pub height: u32,
}

impl Camera {
    /// A camera at `from` looking at `at` with up +y, near distance 1 and a
    /// `width`×`height` image.
    #[must_use]
    pub fn looking_at(from: V3, at: V3, fov_y_deg: f64, (width, height): (u32, u32)) -> Self {
        Self {
            from,
            at,
            up: V3::new(0.0, 1.0, 0.0),
            fov_y_deg,
            hither: 1.0,
            width,
            height,
        }
    }
}

/// Whitted/NFF material (all colours linear, 0..1; AFF `fm`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Ambient reflectance.
    pub ambient: V3,
    /// Diffuse reflectance (multiplied by the texture colour when textured).
    pub diffuse: V3,
    /// Specular reflectance: highlight and mirror reflection weight.
    pub specular: V3,
    /// Phong exponent (0…255 in BART).
    pub shine: f64,
    /// Transmission weight (refraction; AFF gives one scalar, copied to the
    /// three channels).
    pub transmission: V3,
    /// Index of refraction of the inside (AFF values `<= 0` read as 1).
    pub ior: f64,
}

/// Point light.
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// One world-space triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Vertex positions.
    pub p: [V3; 3],
    /// Unit per-vertex normals (interpolated, Phong; AFF normals go through
    /// the inverse transpose); `None` = flat.
    pub n: Option<[V3; 3]>,
    /// Per-vertex UVs in texture repeats (AFF: as written, v = 0 the top
    /// row of the image); required for texturing.
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
    /// Colour of rays that hit nothing (without an environment map).
    pub background: V3,
    /// Latitude-longitude environment map of rays that hit nothing
    /// (`render::envmap`; `+y` up, `−z` at the centre), instead of the
    /// background colour.
    pub environment: Option<TextureImage>,
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

/// Converts a loaded AFF scene: the textures to RGBA8888 level 0, the rest
/// moves as it is (the loader produces these same types).
#[must_use]
pub fn aff_adapter(s: aff::Scene) -> Scene {
    Scene {
        camera: s.camera,
        background: s.background,
        environment: None,
        ambient: s.ambient,
        lights: s.lights,
        materials: s.materials,
        textures: s.textures.into_iter().map(TextureImage::from).collect(),
        triangles: s.triangles,
    }
}

impl From<aff::Texture> for TextureImage {
    fn from(t: aff::Texture) -> Self {
        Self {
            width: t.image.width,
            height: t.image.height,
            texels: t.image.to_rgba8888(),
            name: t.name,
        }
    }
}
