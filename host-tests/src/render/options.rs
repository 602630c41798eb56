//! What to render: LOD method, arithmetic, size, bounces.

use serde::Serialize;

use super::RenderError;

/// Texture LOD method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Per-triangle Pb table and accumulated path length (Park et al.).
    Table,
    /// Ray cones (Akenine-Möller et al., RTG ch. 20), with the |n·d| term.
    Cone,
    /// Ray differentials (Igehy 1999): the firmware's fixed-point ones
    /// (`raymip::path::raydiff`) in fixed precision, f64 in float precision.
    Raydiff,
    /// Ray differentials whose first hit comes from a G-buffer (the talk's
    /// "RayDiffs GB"): a pass over the pixel centres stores each first hit
    /// (position, shading normal, distance); a path's first hit takes its
    /// position and normal differentials from the neighbouring pixels'
    /// (`raymip::path::raydiff::gbuffer`, the side with the smaller distance
    /// step), later hits transfer them as the raydiff method does.
    Gbuffer,
    /// No LOD: bilinear in level 0.
    Mip0,
    /// Ground truth: jittered supersampling, bilinear in level 0.
    Truth,
}

impl Method {
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Table => "table",
            Self::Cone => "cone",
            Self::Raydiff => "raydiff",
            Self::Gbuffer => "gbuffer",
            Self::Mip0 => "mip0",
            Self::Truth => "truth",
        }
    }
}

impl Method {
    /// Ray differentials: a footprint with two axes per hit (for
    /// anisotropic filtering), not only a lod.
    #[must_use]
    pub fn has_footprint(self) -> bool {
        matches!(self, Self::Raydiff | Self::Gbuffer)
    }
}

/// Arithmetic of the LOD and the texture unit of a render (not the
/// firmware's precision tier, `raymip::units::Precision`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Arithmetic {
    /// Firmware fixed point (table, ray stack, lod, sampler).
    Fixed,
    /// f64: the reference sampler (`raymip_reference::sampler`) and the
    /// f64 lods of this crate.
    Float,
}

impl Arithmetic {
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Fixed => "fixed",
            Self::Float => "float",
        }
    }
}

/// Render options.
#[derive(Clone, Debug)]
pub struct Options {
    /// LOD method.
    pub method: Method,
    /// Arithmetic.
    pub arithmetic: Arithmetic,
    /// Image size; `None` = the scene camera's.
    pub size: Option<(u32, u32)>,
    /// Maximum reflection/refraction depth (every value fits the ray
    /// stack: [`STACK_CAPACITY`](super::STACK_CAPACITY)).
    pub bounces: u8,
    /// Samples per pixel for [`Method::Truth`].
    pub spp: u32,
    /// Record the texel-block address of every fetch (firmware unit).
    pub record_blocks: bool,
    /// Show a progress bar.
    pub progress: bool,
    /// Anisotropic filtering with at most this many probes (1..=16) over
    /// the ray-differential footprint (pbrt-style axes; never a ray-cone
    /// ellipse): the firmware's fixed-point footprint in fixed precision,
    /// the f64 one in float precision. Only the ray-differential methods
    /// ([`Method::Raydiff`], [`Method::Gbuffer`]) have a footprint:
    /// [`Options::validate`] refuses it with any other method
    /// (the CLI reports that error); a library caller that sets it anyway
    /// gets isotropic filtering at the chosen method's lod (never a switch
    /// of method). `None` = isotropic (trilinear at the method's lod).
    pub aniso: Option<u8>,
}

impl Options {
    /// Checks that the options go together.
    ///
    /// # Errors
    /// Anisotropic filtering with a method other than the ray-differential
    /// ones ([`Method::Raydiff`], [`Method::Gbuffer`]): the table and cone
    /// methods give an isotropic lod and no footprint axes.
    pub fn validate(&self) -> Result<(), RenderError> {
        if self.aniso.is_some() && !self.method.has_footprint() {
            return Err(RenderError::AnisoNeedsRaydiff {
                method: self.method,
            });
        }
        Ok(())
    }
}

impl Default for Options {
    fn default() -> Self {
        Self {
            method: Method::Table,
            arithmetic: Arithmetic::Fixed,
            size: None,
            bounces: 10,
            spp: 256,
            record_blocks: false,
            progress: false,
            aniso: None,
        }
    }
}
