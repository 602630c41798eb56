//! Host time per call: the median over repeated warm runs of a loop over
//! the same inputs, inputs and results passed through
//! [`std::hint::black_box`] so that nothing is hoisted or dropped.

use std::hint::black_box;
use std::time::Instant;

/// Median of `xs` (NaN when empty).
#[must_use]
pub fn median(xs: &mut [f64]) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    if n % 2 == 1 {
        xs[n / 2]
    } else {
        0.5 * (xs[n / 2 - 1] + xs[n / 2])
    }
}

/// Nanoseconds per call of `f` over `inputs`: one warm-up pass, then the
/// median of `repeats` timed passes (each pass calls `f` once per input).
pub fn ns_per_call<T: Copy, O>(inputs: &[T], repeats: usize, mut f: impl FnMut(T) -> O) -> f64 {
    let mut pass = || {
        for &x in black_box(inputs) {
            black_box(f(black_box(x)));
        }
    };
    pass();
    let n = inputs.len().max(1) as f64;
    let mut t: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let t0 = Instant::now();
            pass();
            t0.elapsed().as_secs_f64() * 1e9 / n
        })
        .collect();
    median(&mut t)
}

/// `ns_per_call` and the results of one more pass mapped by `conv` (the
/// values the error is measured on).
pub fn measure<T: Copy, O, R>(
    inputs: &[T],
    repeats: usize,
    mut f: impl FnMut(T) -> O,
    conv: impl Fn(O) -> R,
) -> (f64, Vec<R>) {
    let ns = ns_per_call(inputs, repeats, &mut f);
    (ns, inputs.iter().map(|&x| conv(f(x))).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&mut []).is_nan());
    }

    #[test]
    fn measure_returns_every_result() {
        let (ns, out) = measure(&[1u32, 2, 3], 3, |x| x * 2, f64::from);
        assert!(ns >= 0.0 && ns.is_finite());
        assert_eq!(out, vec![2.0, 4.0, 6.0]);
    }
}
