//! Ride comfort from acceleration histories: Sperling's ride index `Wz` with its vertical
//! and lateral frequency weightings, and the EN 12299 simplified mean comfort index
//! `N_MV` with the `W_b` / `W_d` weightings, both from records first resampled onto a
//! uniform time grid.
//!
//! The `comfort` recorder kind that collects the histories during a run and writes these
//! indices when it finishes is in [`recorder`]. What does not live here: EN 12299's other
//! indices (complete method, standing and seated continuous comfort, discrete events).
//!
//! # Sperling's ride index
//!
//! For a harmonic acceleration of amplitude `a` (cm/s²) at frequency `f` (Hz) Sperling
//! (Sperling & Betzhold 1956, as tabulated by Garg & Dukkipati, *Dynamics of Railway
//! Vehicle Systems*, 1984, ch. 12) rates the ride by
//!
//! `Wz = 0.896·(a³·F(f)/f)^(1/10)`,
//!
//! with the frequency weighting `F(f)` of the direction:
//!
//! | direction | `F(f)` |
//! |---|---|
//! | vertical | `0.325·f²` for `f < 5.9 Hz`, `400/f²` for `5.9 ≤ f < 20 Hz`, `1` for `f ≥ 20 Hz` |
//! | lateral  | `0.8·f²` for `f < 5.4 Hz`, `650/f²` for `5.4 ≤ f < 26 Hz`, `1` for `f ≥ 26 Hz` |
//!
//! A record holding many frequencies is split into harmonics by its discrete Fourier
//! transform and the harmonics are combined by Sperling's rule
//! `Wz = (Σ_i Wz_i¹⁰)^(1/10)`, i.e.
//!
//! `Wz = 0.896·(Σ_i a_i³·F(f_i)/f_i)^(1/10)`,
//!
//! over the bins `f_i = i/T` inside the band [`BAND_HZ`] (0.5–30 Hz, the range the
//! weightings were defined for; capped by the Nyquist frequency of the record), `a_i` the
//! single-sided amplitude `2·|X_i|/N` converted from m/s² to cm/s².
//!
//! **Resampling.** A run's recorded steps need not be uniform (a last short step, step
//! cuts). The record over `[t₀, t₀ + T]` is interpolated linearly onto `N` points
//! `t₀ + j·T/N`, `j = 0…N−1`, `N` the power of two at or above the number of recorded
//! intervals (no coarser than the record). The transform then sees the record as periodic
//! with period `T`: a harmonic with a whole number of periods in `T` falls on one bin and
//! gives Sperling's single-frequency value exactly; any other spreads over neighbouring
//! bins (leakage), which the cube of the amplitudes does not conserve — run long enough
//! (many periods of the lowest frequency of interest) for a stable index.

use nalgebra::Complex;
use railfem_framework::fft::fft;
use thiserror::Error;

pub mod recorder;

/// The frequency band (Hz) over which Sperling's weightings are applied.
pub const BAND_HZ: (f64, f64) = (0.5, 30.0);

/// The ride-comfort index a `comfort` recorder writes (`method` in a model file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ComfortMethod {
    /// Sperling's ride index Wz per node and DOF (`"sperling"`).
    #[default]
    Sperling,
    /// EN 12299's simplified mean comfort N_MV per node (`"en12299"`).
    En12299,
}

/// Which of Sperling's weightings applies to a direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Vertical (car-body bounce and pitch motion at the floor).
    Vertical,
    /// Lateral (sway, roll motion at the floor).
    Lateral,
    /// Longitudinal (EN 12299's X; Sperling has no weighting for it).
    Longitudinal,
}

impl Direction {
    /// `"vertical"` or `"lateral"`.
    pub fn name(self) -> &'static str {
        match self {
            Direction::Vertical => "vertical",
            Direction::Lateral => "lateral",
            Direction::Longitudinal => "longitudinal",
        }
    }
}

/// Why an index could not be computed.
#[derive(Debug, Error, PartialEq)]
pub enum ComfortError {
    /// Too few samples or a record of no duration.
    #[error("the record has {samples} sample(s) over {duration} s; Wz needs at least 8 samples over a positive duration (record more steps, or lower `record_every`)")]
    TooShort {
        /// Number of samples.
        samples: usize,
        /// Duration (s).
        duration: f64,
    },
    /// Times not increasing or a value not finite.
    #[error("sample {index} has time {time} s or value {value}: times must increase and values be finite")]
    BadSample {
        /// Index of the sample.
        index: usize,
        /// Its time (s).
        time: f64,
        /// Its value.
        value: f64,
    },
}

/// Sperling's frequency weighting `F(f)` of `dir` at `f` Hz (table in the module doc).
pub fn sperling_weighting(f: f64, dir: Direction) -> f64 {
    let (knee, low, high_num, flat) = match dir {
        Direction::Vertical => (5.9, 0.325, 400.0, 20.0),
        // The recorder refuses a longitudinal Sperling index; the lateral curve is the
        // horizontal one.
        Direction::Lateral | Direction::Longitudinal => (5.4, 0.8, 650.0, 26.0),
    };
    if f < knee {
        low * f * f
    } else if f < flat {
        high_num / (f * f)
    } else {
        1.0
    }
}

/// Sperling's index of one harmonic of amplitude `amplitude` (m/s²) at `f` Hz.
pub fn sperling_single(amplitude: f64, f: f64, dir: Direction) -> f64 {
    let a = 100.0 * amplitude; // cm/s²
    0.896 * (a.powi(3) * sperling_weighting(f, dir) / f).powf(0.1)
}

/// `(h, x)`: the record `(t, a)` linearly interpolated onto `N` uniform points
/// `t₀ + j·h`, `h = T/N`, `N` the power of two at or above the number of intervals.
pub fn resample_uniform(t: &[f64], a: &[f64]) -> Result<(f64, Vec<f64>), ComfortError> {
    let n = t.len().min(a.len());
    let duration = if n > 0 { t[n - 1] - t[0] } else { 0.0 };
    if n < 8 || duration.is_nan() || duration <= 0.0 {
        return Err(ComfortError::TooShort {
            samples: n,
            duration,
        });
    }
    for i in 0..n {
        if !a[i].is_finite() || !t[i].is_finite() || (i > 0 && t[i] <= t[i - 1]) {
            return Err(ComfortError::BadSample {
                index: i,
                time: t[i],
                value: a[i],
            });
        }
    }
    let m = (n - 1).next_power_of_two();
    let h = duration / m as f64;
    let mut x = Vec::with_capacity(m);
    let mut k = 0;
    for j in 0..m {
        let tj = t[0] + j as f64 * h;
        while k + 2 < n && t[k + 1] <= tj {
            k += 1;
        }
        let w = ((tj - t[k]) / (t[k + 1] - t[k])).clamp(0.0, 1.0);
        x.push(a[k] + w * (a[k + 1] - a[k]));
    }
    Ok((h, x))
}

/// Single-sided amplitude spectrum `(f_i, a_i)` (Hz, units of `x`) of a uniform record of
/// step `h`, bins `1 ≤ i < N/2`, mean removed.
pub fn amplitude_spectrum(h: f64, x: &[f64]) -> Vec<(f64, f64)> {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let mut re: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let mut im = vec![0.0; n];
    fft(&mut re, &mut im, false);
    let period = h * n as f64;
    (1..n / 2)
        .map(|i| (i as f64 / period, 2.0 * re[i].hypot(im[i]) / n as f64))
        .collect()
}

/// Sperling's `Wz` of the acceleration record `(t, a)` (s, m/s²) in direction `dir`
/// (module doc: resampling, spectrum, band, combination of the harmonics).
pub fn sperling_wz(t: &[f64], a: &[f64], dir: Direction) -> Result<f64, ComfortError> {
    let (h, x) = resample_uniform(t, a)?;
    let sum: f64 = amplitude_spectrum(h, &x)
        .into_iter()
        .filter(|&(f, _)| f >= BAND_HZ.0 && f <= BAND_HZ.1)
        .map(|(f, amp)| (100.0 * amp).powi(3) * sperling_weighting(f, dir) / f)
        .sum();
    Ok(0.896 * sum.powf(0.1))
}

/// The parameters of an ISO 8041 / ISO 2631 frequency weighting (frequencies in Hz):
/// band limiting (2nd-order Butterworth high pass `f1`, low pass `f2`), acceleration–
/// velocity transition (`f3`, `f4`, `q4`), upward step (`f5`, `q5`, `f6`, `q6`; `None`
/// for none) and gain `k`:
///
/// `H(s) = k · s²/(s² + ω₁s/Q₁ + ω₁²) · ω₂²/(s² + ω₂s/Q₂ + ω₂²)
///       · (1 + s/ω₃)/(1 + s/(Q₄ω₄) + s²/ω₄²) · (s² + ω₅s/Q₅ + ω₅²)/(s² + ω₆s/Q₆ + ω₆²)`,
///
/// `Q₁ = Q₂ = 1/√2`, `ω = 2πf`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsoWeighting {
    /// Name (`"Wb"`, `"Wd"`).
    pub name: &'static str,
    /// High-pass corner (Hz).
    pub f1: f64,
    /// Low-pass corner (Hz).
    pub f2: f64,
    /// Acceleration–velocity transition (Hz) and its quality factor.
    pub f3: f64,
    /// Second corner of the transition (Hz).
    pub f4: f64,
    /// Quality factor of the transition.
    pub q4: f64,
    /// Upward step `(f5, q5, f6, q6)`, if any.
    pub step: Option<(f64, f64, f64, f64)>,
    /// Gain.
    pub k: f64,
}

/// `W_b`, EN 12299's vertical weighting (ISO 2631-4; parameters as tabulated in
/// ISO 8041): f1 0.4, f2 100, f3 = f4 = 16 Hz, Q4 0.55, f5 2.5 Hz, Q5 0.9, f6 4 Hz,
/// Q6 0.95, K 1.024.
pub const W_B: IsoWeighting = IsoWeighting {
    name: "Wb",
    f1: 0.4,
    f2: 100.0,
    f3: 16.0,
    f4: 16.0,
    q4: 0.55,
    step: Some((2.5, 0.9, 4.0, 0.95)),
    k: 1.024,
};

/// `W_d`, EN 12299's horizontal weighting (ISO 2631-1): f1 0.4, f2 100, f3 = f4 = 2 Hz,
/// Q4 0.63, no upward step, K 1.
pub const W_D: IsoWeighting = IsoWeighting {
    name: "Wd",
    f1: 0.4,
    f2: 100.0,
    f3: 2.0,
    f4: 2.0,
    q4: 0.63,
    step: None,
    k: 1.0,
};

impl IsoWeighting {
    /// The complex response `H(i·2πf)` (see the type's documentation).
    pub fn response(&self, f: f64) -> Complex<f64> {
        let w = |x: f64| 2.0 * std::f64::consts::PI * x;
        let s = Complex::new(0.0, w(f));
        let q = std::f64::consts::FRAC_1_SQRT_2;
        let one = Complex::new(1.0, 0.0);
        let (w1, w2, w3, w4) = (w(self.f1), w(self.f2), w(self.f3), w(self.f4));
        let high = s * s / (s * s + s * (w1 / q) + w1 * w1);
        let low = Complex::new(w2 * w2, 0.0) / (s * s + s * (w2 / q) + w2 * w2);
        let transition = (one + s / w3) / (one + s / (self.q4 * w4) + s * s / (w4 * w4));
        let step = match self.step {
            Some((f5, q5, f6, q6)) => {
                let (w5, w6) = (w(f5), w(f6));
                (s * s + s * (w5 / q5) + w5 * w5) / (s * s + s * (w6 / q6) + w6 * w6)
            }
            None => one,
        };
        high * low * transition * step * self.k
    }
}

/// Length of EN 12299's rms windows (s).
pub const EN12299_WINDOW_S: f64 = 5.0;

/// The 95th percentile of the 5-s rms values of the record `(t, a)` (s, m/s²) weighted
/// by `w`: resampled as for Sperling's index, weighted in the frequency domain (each DFT
/// bin times `H(f)`, the record taken as periodic), cut into consecutive whole 5-s
/// windows (a last partial window is left out), the rms of each, and the percentile with
/// linear interpolation between order statistics (`p = 0.95·(n − 1)`). Returns the
/// percentile and the number of windows.
pub fn en12299_p95(t: &[f64], a: &[f64], w: &IsoWeighting) -> Result<(f64, usize), ComfortError> {
    let (h, x) = resample_uniform(t, a)?;
    let n = x.len();
    let duration = h * n as f64;
    let per_window = (EN12299_WINDOW_S / h).round() as usize;
    let windows = n.checked_div(per_window).unwrap_or(0);
    if windows == 0 {
        return Err(ComfortError::TooShort {
            samples: t.len(),
            duration,
        });
    }
    let mut re = x;
    let mut im = vec![0.0; n];
    fft(&mut re, &mut im, false);
    for k in 0..n {
        // Bin k is the frequency k/T (k ≤ N/2) or −(N − k)/T: H(−f) = conj H(f).
        let hk = if k == 0 {
            Complex::new(0.0, 0.0)
        } else if k <= n / 2 {
            w.response(k as f64 / duration)
        } else {
            w.response((n - k) as f64 / duration).conj()
        };
        let v = Complex::new(re[k], im[k]) * hk;
        // Inverse transform through the forward one: x = conj(FFT(conj X))/N.
        re[k] = v.re;
        im[k] = -v.im;
    }
    fft(&mut re, &mut im, false);
    let weighted: Vec<f64> = re.iter().map(|v| v / n as f64).collect();
    let mut rms: Vec<f64> = weighted
        .chunks_exact(per_window)
        .map(|c| (c.iter().map(|v| v * v).sum::<f64>() / c.len() as f64).sqrt())
        .collect();
    rms.sort_by(f64::total_cmp);
    let p = 0.95 * (rms.len() - 1) as f64;
    let (lo, frac) = (p.floor() as usize, p - p.floor());
    let hi = (lo + 1).min(rms.len() - 1);
    Ok((rms[lo] + frac * (rms[hi] - rms[lo]), windows))
}

/// EN 12299's simplified mean comfort index from the three 95th percentiles (m/s²):
/// `N_MV = 6·√(a_XP95² + a_YP95² + a_ZP95²)` (X, Y weighted `W_d`, Z weighted `W_b`).
pub fn n_mv(ax: f64, ay: f64, az: f64) -> f64 {
    6.0 * (ax * ax + ay * ay + az * az).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The weightings against values published independently of their formula: |W_b|
    /// = 0.8126 and |W_d| = 0.1261 at 100 rad/s (15.915 Hz), the reference values of a
    /// vibration meter's specification (ZETLAB, after ISO 8041), 4 digits; and the
    /// asymptotes: W_d → 1 between the band-limiting corners below its 2 Hz transition
    /// (|W_d(1 Hz)| within 2 % of 1), both vanish at 0 Hz.
    #[test]
    fn iso_weightings_match_published_values() {
        let f = 100.0 / (2.0 * PI);
        assert!((W_B.response(f).norm() - 0.8126).abs() < 5e-5);
        assert!((W_D.response(f).norm() - 0.1261).abs() < 5e-5);
        assert!((W_D.response(1.0).norm() - 1.0).abs() < 0.02);
        assert!(W_B.response(1e-6).norm() < 1e-9 && W_D.response(1e-6).norm() < 1e-9);
    }

    /// A sine with whole periods in each 5-s window: every window's weighted rms is
    /// `a·|W(f)|/√2` (the periodic weighting is exact for a bin frequency), so the 95th
    /// percentile is that value; N_MV follows by its formula, and scales linearly with a.
    #[test]
    fn en12299_sine_gives_the_weighted_rms() {
        for (w, f) in [(W_B, 1.6), (W_B, 6.4), (W_D, 0.8), (W_D, 3.2)] {
            let a = 0.4;
            let (t, x) = sine(a, f, 20.0, 1 << 13);
            let (p95, windows) = en12299_p95(&t, &x, &w).unwrap();
            let want = a * w.response(f).norm() / 2f64.sqrt();
            assert_eq!(windows, 4);
            assert!(
                (p95 - want).abs() <= 1e-9 * want,
                "{} {f}: {p95} vs {want}",
                w.name
            );
            let x2: Vec<f64> = x.iter().map(|v| 3.0 * v).collect();
            let (p2, _) = en12299_p95(&t, &x2, &w).unwrap();
            assert!((p2 - 3.0 * p95).abs() <= 1e-9 * p95);
        }
        assert!((n_mv(0.03, 0.04, 0.12) - 6.0 * 0.13).abs() < 1e-12);
    }

    /// The percentile picks the loud window: a record quiet for 15 s and loud for 5 s
    /// (four windows) gives p = 0.95·3 = 2.85 between the third (quiet) and fourth (loud)
    /// sorted values: 0.15·quiet + 0.85·loud.
    #[test]
    fn en12299_percentile_interpolates_order_statistics() {
        let f = 3.2;
        let (t, x) = sine(1.0, f, 20.0, 1 << 13);
        let x: Vec<f64> = t
            .iter()
            .zip(&x)
            .map(|(&t, &v)| if t < 15.0 { 0.1 * v } else { v })
            .collect();
        let (p95, _) = en12299_p95(&t, &x, &W_D).unwrap();
        let r = W_D.response(f).norm() / 2f64.sqrt();
        // The switch at 15 s leaks slightly across windows through the weighting: 2 %.
        let want = 0.15 * 0.1 * r + 0.85 * r;
        assert!((p95 - want).abs() <= 0.02 * want, "{p95} vs {want}");
    }

    fn sine(a: f64, f: f64, t_end: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..=n).map(|i| t_end * i as f64 / n as f64).collect();
        let x = t
            .iter()
            .map(|&t| a * (2.0 * PI * f * t + 0.3).sin())
            .collect();
        (t, x)
    }

    /// The weightings at chosen frequencies against the table, computed by hand.
    #[test]
    fn weightings_at_chosen_frequencies() {
        use Direction::*;
        for (f, dir, want) in [
            (1.0, Vertical, 0.325),
            (4.0, Vertical, 5.2),
            (10.0, Vertical, 4.0),
            (25.0, Vertical, 1.0),
            (2.0, Lateral, 3.2),
            (5.0, Lateral, 20.0),
            (13.0, Lateral, 650.0 / 169.0),
            (28.0, Lateral, 1.0),
        ] {
            let w = sperling_weighting(f, dir);
            assert!(
                (w - want).abs() <= 1e-12 * want,
                "{f} {dir:?}: {w} vs {want}"
            );
        }
    }

    /// A pure sine of amplitude a with a whole number of periods gives Sperling's
    /// single-harmonic value `0.896·(a³·F(f)/f)^(1/10)` (a in cm/s²) at several
    /// frequencies in both directions. The record is sampled at 2¹³ intervals over 8 s,
    /// so the resampling is exact and only rounding remains (1e-9).
    #[test]
    fn pure_sine_gives_the_closed_form() {
        for dir in [Direction::Vertical, Direction::Lateral] {
            for f in [0.75, 1.5, 3.0, 5.0, 8.0, 12.5, 22.0, 27.5] {
                let a = 0.35;
                let (t, x) = sine(a, f, 8.0, 1 << 13);
                let wz = sperling_wz(&t, &x, dir).unwrap();
                let closed =
                    0.896 * ((100.0 * a).powi(3) * sperling_weighting(f, dir) / f).powf(0.1);
                assert!(
                    (wz - closed).abs() <= 1e-9 * closed,
                    "{dir:?} {f}: {wz} vs {closed}"
                );
                assert!((sperling_single(a, f, dir) - closed).abs() <= 1e-12 * closed);
            }
        }
    }

    /// Scaling laws: Wz ∝ a^0.3 (amplitude ×10 multiplies Wz by 10^0.3), and a sine
    /// outside the band (0.25 Hz, 40 Hz) contributes nothing: adding one leaves Wz.
    #[test]
    fn scaling_and_band() {
        let dir = Direction::Vertical;
        let (t, x1) = sine(0.1, 2.0, 8.0, 1 << 12);
        let (_, x10) = sine(1.0, 2.0, 8.0, 1 << 12);
        let w1 = sperling_wz(&t, &x1, dir).unwrap();
        let w10 = sperling_wz(&t, &x10, dir).unwrap();
        assert!((w10 / w1 - 10f64.powf(0.3)).abs() <= 1e-9);
        let mixed: Vec<f64> = t
            .iter()
            .zip(&x1)
            .map(|(&t, &x)| {
                x + 0.5 * (2.0 * PI * 0.25 * t).sin() + 0.5 * (2.0 * PI * 40.0 * t).cos()
            })
            .collect();
        let wm = sperling_wz(&t, &mixed, dir).unwrap();
        assert!((wm - w1).abs() <= 1e-9 * w1, "{wm} vs {w1}");
    }

    /// Two harmonics combine as (Wz₁¹⁰ + Wz₂¹⁰)^(1/10).
    #[test]
    fn harmonics_combine_by_the_tenth_power() {
        let dir = Direction::Lateral;
        let (t, x1) = sine(0.2, 1.0, 8.0, 1 << 12);
        let (_, x2) = sine(0.5, 7.0, 8.0, 1 << 12);
        let sum: Vec<f64> = x1.iter().zip(&x2).map(|(a, b)| a + b).collect();
        let w = sperling_wz(&t, &sum, dir).unwrap();
        let want = (sperling_single(0.2, 1.0, dir).powi(10)
            + sperling_single(0.5, 7.0, dir).powi(10))
        .powf(0.1);
        assert!((w - want).abs() <= 1e-9 * want, "{w} vs {want}");
    }

    /// Uneven steps (a cut region at a quarter of the step, a short last step) are
    /// resampled: a 3 Hz sine sampled at 2 ms with 0.5 ms steps between 2 s and 2.1 s
    /// gives the closed form within the linear-interpolation error, amplitude
    /// `(ωh)²/8 ≈ 7e-4` relative at h ≈ 2 ms, i.e. 2e-4 in Wz (a^0.3); 1e-3 asserted.
    #[test]
    fn uneven_steps_are_resampled() {
        let (a, f) = (0.2, 3.0);
        let mut t = Vec::new();
        let mut s = 0.0;
        while s < 8.0 - 1e-12 {
            t.push(s);
            s += if (2.0..2.1).contains(&s) { 5e-4 } else { 2e-3 };
        }
        t.push(8.0);
        let x: Vec<f64> = t.iter().map(|&t| a * (2.0 * PI * f * t).sin()).collect();
        let wz = sperling_wz(&t, &x, Direction::Vertical).unwrap();
        let closed = sperling_single(a, f, Direction::Vertical);
        assert!((wz - closed).abs() <= 1e-3 * closed, "{wz} vs {closed}");
    }

    #[test]
    fn bad_records_are_refused() {
        let e = sperling_wz(&[0.0, 1.0], &[0.0, 1.0], Direction::Vertical).unwrap_err();
        assert!(matches!(e, ComfortError::TooShort { samples: 2, .. }));
        let t: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let mut x = vec![0.0; 10];
        x[4] = f64::NAN;
        let e = sperling_wz(&t, &x, Direction::Vertical).unwrap_err();
        assert!(matches!(e, ComfortError::BadSample { index: 4, .. }));
    }
}
