//! Pareto fronts: a configuration is on the front when no other one of
//! the same group ([`group`]) is at least as fast and at least as
//! accurate, and strictly better in one of the two.

use super::{Row, Stage};

/// The error a stage's chart and front use (smaller is better): max error
/// in levels for LOD, RMS error in LSB for filters, and PSNR vs ground
/// truth (negated) for frames.
#[must_use]
pub fn error_axis(r: &Row) -> f64 {
    match r.stage {
        Stage::Lod => r.error_max,
        Stage::Filter => r.error_rms,
        Stage::Frame => -r.psnr_truth_db.unwrap_or(f64::NEG_INFINITY),
    }
}

/// Indices of the non-dominated points of `(time, error)` (NaN times are
/// never on the front).
#[must_use]
pub fn front(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let (t, e) = points[i];
            !t.is_nan()
                && !points
                    .iter()
                    .any(|&(u, f)| u <= t && f <= e && (u < t || f < e))
        })
        .collect()
}

/// The group a row's front is computed in: per LOD method (the methods
/// compute different quantities), one for the filters, per scene for
/// frames.
#[must_use]
pub fn group(r: &Row) -> (Stage, String) {
    match r.stage {
        Stage::Lod => (r.stage, r.method.clone()),
        Stage::Filter => (r.stage, String::new()),
        Stage::Frame => (r.stage, r.scene.clone().unwrap_or_default()),
    }
}

/// Marks `pareto` on every row within its [`group`] (host time against
/// error), and `pareto_cost` on the frame rows with a firmware cost (M4
/// instructions per frame against PSNR).
pub fn mark(rows: &mut [Row]) {
    let mut groups: Vec<(Stage, String)> = Vec::new();
    for r in rows.iter() {
        let g = group(r);
        if !groups.contains(&g) {
            groups.push(g);
        }
    }
    for g in groups {
        let idx: Vec<usize> = (0..rows.len()).filter(|&i| group(&rows[i]) == g).collect();
        let pts: Vec<(f64, f64)> = idx
            .iter()
            .map(|&i| (rows[i].time(), error_axis(&rows[i])))
            .collect();
        for k in front(&pts) {
            rows[idx[k]].pareto = true;
        }
        if g.0 == Stage::Frame {
            // The firmware-cost front: M4 instructions per frame against
            // PSNR, among the rows that have a cost.
            let costed: Vec<usize> = idx
                .iter()
                .copied()
                .filter(|&i| rows[i].frame_m4.is_some())
                .collect();
            let pts: Vec<(f64, f64)> = costed
                .iter()
                .map(|&i| (rows[i].frame_m4.unwrap_or(f64::NAN), error_axis(&rows[i])))
                .collect();
            for k in front(&pts) {
                rows[costed[k]].pareto_cost = true;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_of_a_small_set() {
        // (1, 5) and (3, 1) are optimal; (2, 6) is dominated by (1, 5);
        // (3, 2) by (3, 1); a duplicate of an optimal point stays.
        let p = [
            (1.0, 5.0),
            (2.0, 6.0),
            (3.0, 1.0),
            (3.0, 2.0),
            (1.0, 5.0),
            (f64::NAN, 0.0),
        ];
        assert_eq!(front(&p), vec![0, 2, 4]);
    }
}
