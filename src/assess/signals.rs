//! The signal processing of a running-safety assessment: the zero-phase low-pass filter,
//! the sliding mean over a distance window, and percentiles. Pure functions on slices;
//! what the quantities are and which limits apply lives in [`super::limits`].

/// A zero-phase low-pass filter: a second-order Butterworth section (bilinear transform
/// with the cut-off prewarped, e.g. R. G. Lyons, *Understanding Digital Signal
/// Processing*, §6.5) run forwards and then backwards over the signal, as EN 14363
/// evaluations filter Y and Q without shifting them in time. The amplitude response of the
/// pair is `|H(f)|² = 1/(1 + (tan(πf/fs)/tan(πfc/fs))⁴)` (exactly, away from the ends):
/// −6 dB at the cut-off `fc`, no phase shift. The ends start from the first (last) value
/// held constant, so a constant signal passes unchanged. `fc ≥ fs/2` returns the signal
/// as it is (nothing to remove below the Nyquist frequency).
pub fn low_pass(x: &[f64], fs: f64, fc: f64) -> Vec<f64> {
    if x.len() < 3 || fc.is_nan() || fc <= 0.0 || fc >= 0.5 * fs {
        return x.to_vec();
    }
    // Bilinear transform of 1/(s² + √2·s + 1) at the prewarped cut-off.
    let k = (std::f64::consts::PI * fc / fs).tan();
    let (k2, r2) = (k * k, std::f64::consts::SQRT_2 * k);
    let norm = 1.0 / (1.0 + r2 + k2);
    let b = [k2 * norm, 2.0 * k2 * norm, k2 * norm];
    let a = [2.0 * (k2 - 1.0) * norm, (1.0 - r2 + k2) * norm];
    let pass = |input: &mut Vec<f64>| {
        // Steady state of a constant input x0: output x0, the delay line at x0.
        let x0 = input[0];
        let (mut x1, mut x2, mut y1, mut y2) = (x0, x0, x0, x0);
        for v in input.iter_mut() {
            let y = b[0] * *v + b[1] * x1 + b[2] * x2 - a[0] * y1 - a[1] * y2;
            (x2, x1) = (x1, *v);
            (y2, y1) = (y1, y);
            *v = y;
        }
    };
    let mut y = x.to_vec();
    pass(&mut y);
    y.reverse();
    pass(&mut y);
    y.reverse();
    y
}

/// The sliding mean of `x` over the distance window `window` (m) ending at each sample:
/// `(1/L)·∫_{s−L}^{s} x ds'` by the trapezoidal rule over the samples' stations `s`
/// (increasing, not necessarily evenly spaced), the window's start interpolated linearly.
/// Samples less than a window from the first station get `NaN` (no full window yet).
pub fn sliding_mean(s: &[f64], x: &[f64], window: f64) -> Vec<f64> {
    let n = s.len().min(x.len());
    // Cumulative trapezoidal integral.
    let mut cum = vec![0.0; n];
    for i in 1..n {
        cum[i] = cum[i - 1] + 0.5 * (x[i] + x[i - 1]) * (s[i] - s[i - 1]);
    }
    // The integral up to station `t` (inside the samples), interpolating the integrand.
    let integral_to = |t: f64, hint: usize| -> (f64, usize) {
        let mut k = hint;
        while k + 1 < n && s[k + 1] <= t {
            k += 1;
        }
        let h = t - s[k];
        if k + 1 >= n || h <= 0.0 {
            return (cum[k], k);
        }
        let slope = (x[k + 1] - x[k]) / (s[k + 1] - s[k]);
        (cum[k] + h * (x[k] + 0.5 * slope * h), k)
    };
    let mut out = vec![f64::NAN; n];
    let mut k = 0;
    for i in 0..n {
        let start = s[i] - window;
        if start < s[0] - 1e-12 * window.abs().max(1.0) {
            continue;
        }
        let (c, kk) = integral_to(start.max(s[0]), k);
        k = kk;
        out[i] = (cum[i] - c) / window;
    }
    out
}

/// The `p`-th percentile (0–100) of the finite values of `x`, interpolating linearly
/// between order statistics (rank `(n − 1)·p/100`, the "type 7" definition of Hyndman &
/// Fan 1996, Am. Stat. 50(4)); `NaN` for no finite value.
pub fn percentile(x: &[f64], p: f64) -> f64 {
    let mut v: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let r = (v.len() - 1) as f64 * (p / 100.0).clamp(0.0, 1.0);
    let (lo, hi) = (r.floor() as usize, r.ceil() as usize);
    v[lo] + (v[hi] - v[lo]) * (r - lo as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A sine through the forward–backward Butterworth pair comes out scaled by the
    /// closed-form `|H|² = 1/(1 + (tan(πf/fs)/tan(πfc/fs))⁴)` and not shifted, at
    /// frequencies below, at and above the cut-off (checked mid-record, away from the
    /// start-up at the ends, to 2e-3 of the amplitude).
    #[test]
    fn low_pass_gain_is_the_butterworth_pair_and_phase_free() {
        let (fs, fc) = (1000.0, 20.0);
        for f in [2.0, 10.0, 20.0, 40.0, 80.0] {
            let n = 20_000;
            let x: Vec<f64> = (0..n)
                .map(|i| (2.0 * PI * f * i as f64 / fs).sin())
                .collect();
            let y = low_pass(&x, fs, fc);
            let r = ((PI * f / fs).tan() / (PI * fc / fs).tan()).powi(4);
            let gain = 1.0 / (1.0 + r);
            for i in (n / 4..3 * n / 4).step_by(37) {
                assert!(
                    (y[i] - gain * x[i]).abs() < 2e-3,
                    "f = {f}: {} vs {}",
                    y[i],
                    gain * x[i]
                );
            }
        }
        let c = vec![3.5; 100];
        assert!(low_pass(&c, fs, fc).iter().all(|v| (v - 3.5).abs() < 1e-12));
    }

    /// The sliding mean of `c + A·sin(2πs/λ)` over `L` is
    /// `c + A·λ/(2πL)·[cos(2π(s − L)/λ) − cos(2πs/λ)]` (integrated by hand), on uneven
    /// stations; NaN before the first full window.
    #[test]
    fn sliding_mean_of_a_sine_is_its_closed_form() {
        let (c, a, lam, l) = (0.4, 0.3, 3.3, 2.0);
        let s: Vec<f64> = (0..4000)
            .map(|i| {
                let t = i as f64 * 5e-3;
                t + 1e-3 * (7.0 * t).sin()
            })
            .collect();
        let x: Vec<f64> = s
            .iter()
            .map(|s| c + a * (2.0 * PI * s / lam).sin())
            .collect();
        let m = sliding_mean(&s, &x, l);
        for (i, &si) in s.iter().enumerate() {
            if si < l {
                assert!(m[i].is_nan());
                continue;
            }
            let exact = c + a * lam / (2.0 * PI * l)
                * ((2.0 * PI * (si - l) / lam).cos() - (2.0 * PI * si / lam).cos());
            assert!((m[i] - exact).abs() < 2e-5, "s = {si}: {} vs {exact}", m[i]);
        }
    }

    /// Percentiles of a shuffled ramp 0, 1, …, 100 are the percent itself (the type-7
    /// rank is exact there), and halfway values interpolate.
    #[test]
    fn percentiles_of_a_ramp() {
        let mut x: Vec<f64> = (0..=100).map(|i| ((i * 37) % 101) as f64).collect();
        x.push(f64::NAN);
        for p in [0.0, 15.0, 50.0, 99.0, 100.0] {
            assert!((percentile(&x, p) - p).abs() < 1e-12);
        }
        assert!((percentile(&x, 99.85) - 99.85).abs() < 1e-9);
        assert!((percentile(&[1.0, 2.0], 50.0) - 1.5).abs() < 1e-15);
        assert!(percentile(&[f64::NAN], 50.0).is_nan());
    }
}
