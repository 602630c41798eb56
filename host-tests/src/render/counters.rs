//! Counters of one render.

use serde::Serialize;

use super::HIST_LEVELS;

/// Counters of one render.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Counters {
    /// Camera paths started (pixels × spp).
    pub paths: u64,
    /// Ray segments traced (primary + secondary).
    pub rays: u64,
    /// Segments that hit a triangle.
    pub hits: u64,
    /// Hits on textured triangles (texture path taken).
    pub textured_hits: u64,
    /// Hits on untextured triangles (texture path skipped).
    pub untextured_skipped: u64,
    /// Textured hits per selected integer mip level 0..15 (clamped lod, floor).
    pub level_hist: [u64; HIST_LEVELS],
    /// Hits per path depth (index = bounces before the hit).
    pub depth_hist: Vec<u64>,
    /// Reflection/refraction continuations pushed on the ray stack.
    pub bounces: u64,
    /// Refracted continuations computed (pushed or dropped): with firmware
    /// ray differentials, one `RayDiff::refract` each.
    pub refractions: u64,
    /// Reflected continuations computed (pushed or dropped): with firmware
    /// ray differentials, one `RayDiff::reflect` each.
    pub reflections: u64,
    /// Continuations dropped because the ray stack was full.
    pub stack_full: u64,
    /// Most entries on one path's ray stack (at most
    /// [`stack_bound`](raymip::path::raystack::stack_bound)`(bounces, 2)`).
    pub stack_peak: u64,
    /// Hits whose path state saturated (lod is then a bound).
    pub saturations: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
    /// Texels fetched.
    pub fetched: u64,
    /// Texel fetches skipped by the filter.
    pub fetch_skipped: u64,
    /// Σ of the textured hits' lods as the LOD method chose them (the
    /// values of `level_hist`), in 1/256 level (`HitLod::q256`).
    pub lod_sum_256: i64,
    /// Isotropic samples the texture unit took.
    pub samples: u64,
    /// Σ of the lods the texture unit was given for those samples, in 1/256
    /// level: equal to `lod_sum_256` when every textured hit is sampled at
    /// the chosen method's lod (the renderer's tests check it per filter).
    pub sampled_lod_sum_256: i64,
    /// Anisotropic samples the texture unit took (footprint, no lod).
    pub aniso_samples: u64,
}

impl Counters {
    pub(crate) fn add(&mut self, o: &Counters) {
        add_fields!(self, o; paths, rays, hits, textured_hits, untextured_skipped, bounces,
            stack_full, refractions, reflections, saturations, shadow_rays, fetched, fetch_skipped, lod_sum_256, samples,
            sampled_lod_sum_256, aniso_samples);
        for (a, b) in self.level_hist.iter_mut().zip(o.level_hist.iter()) {
            *a += b;
        }
        if self.depth_hist.len() < o.depth_hist.len() {
            self.depth_hist.resize(o.depth_hist.len(), 0);
        }
        for (a, b) in self.depth_hist.iter_mut().zip(o.depth_hist.iter()) {
            *a += b;
        }
        self.stack_peak = self.stack_peak.max(o.stack_peak);
    }

    /// Deepest depth with a hit.
    #[must_use]
    pub fn max_depth(&self) -> usize {
        self.depth_hist.iter().rposition(|&n| n > 0).unwrap_or(0)
    }
}
