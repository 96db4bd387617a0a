//! Random irregular profiles with a prescribed spectrum, the same on every machine.
//!
//! A profile is a sum of cosines with random phases and deterministic amplitudes,
//!
//! ```text
//! z(s_j) = Σ_k a_k·cos(Ω_k·s_j + φ_k),   a_k = √(2·S(Ω_k)·ΔΩ),   s_j = j·h,
//! ```
//!
//! over the harmonics `Ω_k = k·ΔΩ`, `ΔΩ = 2π/(M·h)`, that fall in the band
//! `[2π/λ_max, 2π/λ_min]`; `M` is the number of samples rounded up to a power of two, so
//! the sum is one inverse FFT. Its variance is `Σ a_k²/2 = Σ S(Ω_k)·ΔΩ`, the Riemann sum
//! of `∫ S dΩ` over the band (exact over the record, by orthogonality of the harmonics).
//! The phases `φ_k = 2π·u_k` come from a SplitMix64 stream seeded by the user's seed and
//! the component, drawn for every harmonic from 1 up, so a phase does not depend on the
//! band. Bitwise reproducibility across machines: only IEEE-754 `+ − × ÷ √` are used (all
//! correctly rounded); the sines and cosines of the phases and FFT twiddles come from
//! [`sin_cos`] (a fixed polynomial in `railfem_framework::fft`), not from the platform's
//! libm.

use super::psd::{Component, PsdClass};
pub use railfem_framework::fft::{fft, sin_cos};
use railfem_framework::limits::{self, fmt_num};
use std::f64::consts::PI;

/// SplitMix64 (Steele, Lea & Flood 2014): a 64-bit state advanced by a constant, then
/// mixed by two xor-shift-multiply rounds. Passes BigCrush; plenty for random phases.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A stream from `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`, 53 bits.
    pub fn next_unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// What a generated profile is asked to be.
#[derive(Debug, Clone, PartialEq)]
pub struct PsdRequest {
    /// The spectrum.
    pub class: PsdClass,
    /// Seed of the phases.
    pub seed: u64,
    /// `[λ_min, λ_max]` (m).
    pub wavelengths: [f64; 2],
    /// Sampling step `h` (m).
    pub step: f64,
    /// Length of the profile (m).
    pub length: f64,
}

/// Bytes a generated sample costs while it is made and interpolated (FFT pair, value and
/// the spline's five arrays), for the size guard.
pub const BYTES_PER_SAMPLE: f64 = 9.0 * 8.0;

impl PsdRequest {
    /// Number of samples `n = ⌈length/h⌉ + 1` and the FFT size `M` (power of two ≥ n).
    pub fn sizes(&self) -> (usize, usize) {
        let n = (self.length / self.step).ceil() as usize + 1;
        (n, n.next_power_of_two().max(8))
    }

    /// Bytes a profile of `length` sampled every `step` (m) costs while it is made: its
    /// samples, doubled for the transform's power of two, at [`BYTES_PER_SAMPLE`]. The
    /// guard of [`PsdRequest::validate`] and the model's size estimate
    /// ([`super::estimate`]) both count it so.
    pub fn estimated_bytes(length: f64, step: f64) -> f64 {
        2.0 * (length / step + 1.0) * BYTES_PER_SAMPLE
    }

    /// Checks the numbers; the message says what to fix.
    pub fn validate(&self) -> Result<(), String> {
        let [lo, hi] = self.wavelengths;
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
            return Err(format!(
                "`wavelengths` = [{lo}, {hi}] m: give [λmin, λmax] with 0 < λmin < λmax"
            ));
        }
        let h = self.step;
        if !(h.is_finite() && h > 0.0 && h <= lo / 4.0) {
            return Err(format!(
                "`step` = {h} m: give a sampling step > 0 and ≤ λmin/4 = {} m (four samples on the shortest wave; the cubic spline between them is then within 2 % of the wave)",
                lo / 4.0
            ));
        }
        let l = self.length;
        if !(l.is_finite() && l >= hi) {
            return Err(format!(
                "`length` = {l} m: give a profile at least λmax = {hi} m long (one longest wave)"
            ));
        }
        // The size guard (memory) is the caller's; this only keeps the sample count an
        // integer that cannot overflow (2^40 samples is far beyond any memory budget).
        let samples = l / h + 1.0;
        limits::check_memory(
            &format!("`length` = {} m at `step` = {} m", fmt_num(l), fmt_num(h)),
            PsdRequest::estimated_bytes(l, h) / BYTES_PER_SAMPLE,
            "irregularity samples (rounded up to a power of two)",
            BYTES_PER_SAMPLE,
            "give a larger `step` or a shorter `length`",
        )?;
        if samples > (1u64 << 40) as f64 {
            return Err(format!(
                "`length` = {} m at `step` = {} m is {} samples; give a larger `step` or a shorter `length`",
                fmt_num(l),
                fmt_num(h),
                fmt_num(samples)
            ));
        }
        Ok(())
    }

    /// `(ΔΩ, k_first, k_last)`: the harmonics in the band for an FFT of size `m`.
    pub fn harmonics(&self, m: usize) -> (f64, usize, usize) {
        let d = 2.0 * PI / (m as f64 * self.step);
        let [lo, hi] = self.wavelengths;
        let k0 = ((2.0 * PI / hi) / d).ceil().max(1.0) as usize;
        let k1 = (((2.0 * PI / lo) / d).floor() as usize).min(m / 2 - 1);
        (d, k0, k1)
    }

    /// The profile of component `c` at `s_j = j·step`, `j < n` (m). `None` if the class
    /// does not define `c`. Call [`PsdRequest::validate`] (and the size guard) first.
    pub fn generate(&self, c: Component) -> Option<Vec<f64>> {
        self.class.density(c, 1.0)?;
        let (n, m) = self.sizes();
        let (d, k0, k1) = self.harmonics(m);
        let mut re = vec![0.0; m];
        let mut im = vec![0.0; m];
        // One stream per (seed, component): the seed mixed with the component's index.
        let mut rng =
            SplitMix64::new(self.seed ^ (c.index() as u64 + 1).wrapping_mul(0xD1B5_4A32_D192_ED03));
        for k in 1..=k1 {
            let phi = 2.0 * PI * rng.next_unit();
            if k < k0 {
                continue;
            }
            let s = self.class.density(c, k as f64 * d).unwrap_or(0.0);
            let a = (2.0 * s * d).sqrt();
            let (sp, cp) = sin_cos(phi);
            re[k] = a * cp;
            im[k] = a * sp;
        }
        // Re Σ_k a_k e^{i(Ω_k s_j + φ_k)} = Σ_k a_k cos(Ω_k s_j + φ_k).
        fft(&mut re, &mut im, true);
        re.truncate(n);
        Some(re)
    }

    /// The variance the generated profile has over its whole FFT record: `Σ S(Ω_k)·ΔΩ`.
    pub fn discrete_variance(&self, c: Component) -> f64 {
        let (_, m) = self.sizes();
        let (d, k0, k1) = self.harmonics(m);
        (k0..=k1)
            .map(|k| self.class.density(c, k as f64 * d).unwrap_or(0.0) * d)
            .sum()
    }
}

/// One-sided Welch estimate of the PSD of `x` sampled every `h` m: Hann windows of `seg`
/// samples (a power of two), 50 % overlap, each segment's mean removed. Returns
/// `(Ω_k, S_k)` for `k = 1 … seg/2 − 1`, Ω in rad/m, S in m²/(rad/m):
/// `S_k = 2·h·|Σ_j w_j x_j e^{−2πi·jk/seg}|² / (2π·Σ_j w_j²)`, averaged over segments.
/// `None` if `x` is shorter than one segment.
pub fn welch(x: &[f64], h: f64, seg: usize) -> Option<(Vec<f64>, Vec<f64>)> {
    if !seg.is_power_of_two() || seg < 8 || x.len() < seg {
        return None;
    }
    let w: Vec<f64> = (0..seg)
        .map(|j| 0.5 * (1.0 - (2.0 * PI * j as f64 / seg as f64).cos()))
        .collect();
    let w2: f64 = w.iter().map(|v| v * v).sum();
    let hop = seg / 2;
    let mut acc = vec![0.0; seg / 2];
    let mut count = 0usize;
    let mut start = 0;
    while start + seg <= x.len() {
        let part = &x[start..start + seg];
        let mean = part.iter().sum::<f64>() / seg as f64;
        let mut re: Vec<f64> = part.iter().zip(&w).map(|(v, wj)| (v - mean) * wj).collect();
        let mut im = vec![0.0; seg];
        fft(&mut re, &mut im, false);
        for k in 1..seg / 2 {
            acc[k] += re[k] * re[k] + im[k] * im[k];
        }
        count += 1;
        start += hop;
    }
    let scale = 2.0 * h / (2.0 * PI * w2 * count as f64);
    let omega = (1..seg / 2)
        .map(|k| 2.0 * PI * k as f64 / (seg as f64 * h))
        .collect();
    let psd = (1..seg / 2).map(|k| acc[k] * scale).collect();
    Some((omega, psd))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pure sinusoid a·cos(Ω₀ s) on a Welch bin: the estimate integrates to its variance
    /// a²/2 (Parseval with the Hann window's power normalisation).
    #[test]
    fn welch_integrates_to_variance() {
        let (h, seg) = (0.25, 256);
        let omega0 = 2.0 * PI * 20.0 / (seg as f64 * h);
        let x: Vec<f64> = (0..4096)
            .map(|j| 0.003 * (omega0 * j as f64 * h).cos())
            .collect();
        let (om, s) = welch(&x, h, seg).unwrap();
        let d = om[1] - om[0];
        let var: f64 = s.iter().sum::<f64>() * d;
        assert!((var / (0.003f64.powi(2) / 2.0) - 1.0).abs() < 1e-6, "{var}");
    }

    /// The SplitMix64 reference outputs for seed 1234567 (from the published algorithm).
    #[test]
    fn splitmix_reference() {
        let mut r = SplitMix64::new(1234567);
        let v: Vec<u64> = (0..3).map(|_| r.next_u64()).collect();
        assert_eq!(
            v,
            [
                6457827717110365317,
                3203168211198807973,
                9817491932198370423
            ]
        );
    }
}
