//! Differences of two RGB8 images: PSNR, the largest channel difference,
//! heat maps.

/// PSNR in dB of two RGB8 images (peak 255); infinite if identical.
#[must_use]
pub fn psnr(a: &[[u8; 3]], b: &[[u8; 3]]) -> f64 {
    let n = a.len().min(b.len()) * 3;
    if n == 0 {
        return f64::INFINITY;
    }
    let se: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| (f64::from(x[k]) - f64::from(y[k])).powi(2)))
        .sum();
    let mse = se / n as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

/// Largest per-channel absolute difference.
#[must_use]
pub fn max_diff(a: &[[u8; 3]], b: &[[u8; 3]]) -> u8 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| x[k].abs_diff(y[k])))
        .max()
        .unwrap_or(0)
}

/// Heat-map of the per-pixel max channel difference: black (0) → red →
/// yellow → white (≥ `full` levels).
#[must_use]
pub fn heat_map(a: &[[u8; 3]], b: &[[u8; 3]], full: u8) -> Vec<[u8; 3]> {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (0..3).map(|k| x[k].abs_diff(y[k])).max().unwrap_or(0);
            let t = (f32::from(d) / f32::from(full.max(1))).min(1.0) * 3.0;
            let c = |s: f32| (s.clamp(0.0, 1.0) * 255.0).round() as u8;
            [c(t), c(t - 1.0), c(t - 2.0)]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn psnr_of_known_error() {
        // Every channel off by 1: MSE 1 → 20·log10(255) dB.
        let a = vec![[10u8, 20, 30]; 50];
        let b = vec![[11u8, 19, 31]; 50];
        assert!((psnr(&a, &b) - 20.0 * 255f64.log10()).abs() < 1e-9);
        assert!(psnr(&a, &a).is_infinite());
        assert_eq!(max_diff(&a, &b), 1);
        // Off by 16 in one channel of every pixel: MSE 256/3.
        let c = vec![[26u8, 20, 30]; 50];
        let want = 10.0 * (255.0f64 * 255.0 / (256.0 / 3.0)).log10();
        assert!((psnr(&a, &c) - want).abs() < 1e-9);
    }

    #[test]
    fn heat_map_saturates() {
        let a = [[0u8; 3], [0; 3]];
        let b = [[0u8; 3], [200; 3]];
        assert_eq!(heat_map(&a, &b, 16), vec![[0, 0, 0], [255, 255, 255]]);
    }
}
