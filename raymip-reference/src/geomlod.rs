//! f64 geometric-LOD parameter (NVIDIA 2020, "Implementing Stochastic
//! Levels of Detail with DirectX Raytracing"; the formula of the
//! firmware's `geomlod` module docs).

/// The continuous LOD of an instance at camera-space depth `z` between
/// `near` (LOD 0) and `far` (LOD `levels`), plus `bias`:
/// `clamp(levels · clamp((z − near)/(far − near), 0, 1) + bias, 0, levels − 1)`
/// for `far > near` and `levels ≥ 1`.
#[must_use]
pub fn lod_param(z: f64, near: f64, far: f64, levels: u8, bias: f64) -> f64 {
    let t = ((z - near) / (far - near)).clamp(0.0, 1.0);
    (f64::from(levels) * t + bias).clamp(0.0, f64::from(levels) - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_in_depth_then_clamped() {
        assert_eq!(lod_param(4.0, 4.0, 300.0, 8, 0.0), 0.0);
        assert_eq!(lod_param(152.0, 4.0, 300.0, 8, 0.0), 4.0);
        assert_eq!(lod_param(1e9, 4.0, 300.0, 8, 0.0), 7.0);
        assert_eq!(lod_param(152.0, 4.0, 300.0, 8, -5.0), 0.0);
        assert_eq!(lod_param(152.0, 4.0, 300.0, 8, 1.5), 5.5);
    }
}
