//! The frequency cut-off of the deck acceleration: which frequencies count (EN 1990
//! A2.4.4.2.1(4)P and EN 1991-2 §6.4.6.5(3): up to the greatest of 30 Hz, 1.5 times the
//! first bending frequency and the third mode's frequency), and the zero-phase low-pass
//! filter that removes the rest from a sampled history.
//!
//! The filter works in the frequency domain: the history is padded with zeros (so the
//! filter's response does not wrap around), transformed ([`crate::framework::fft`]),
//! multiplied by a real, even gain `H(f)` and transformed back. `H = 1` up to the cut-off
//! `f_c`, falls as `½·(1 + cos(π·(f − f_c)/(w·f_c)))` to 0 at `(1 + w)·f_c` (`w` =
//! [`TAPER`]), and is 0 above: everything up to the cut-off counts in full (the third mode
//! often *is* the cut-off), and the taper keeps the time-domain ringing of a brick wall
//! short. A real even gain applied to `x + i·y` filters the two real histories `x` and `y`
//! at once, so one transform pair serves two deck points.

use crate::framework::fft::{fft_with, twiddles};

/// Relative width of the taper above the cut-off.
pub const TAPER: f64 = 0.1;

/// The cut-off frequency (Hz): the greatest of 30 Hz, `1.5·n₀` and `n₃` (EN 1990
/// A2.4.4.2.1(4)P, EN 1991-2 §6.4.6.5(3)); `n3` may be absent (fewer than three modes).
pub fn cutoff(n0: f64, n3: Option<f64>) -> f64 {
    30f64.max(1.5 * n0).max(n3.unwrap_or(0.0))
}

/// The gain of the filter at `f` (Hz) for the cut-off `fc` (module documentation).
pub fn gain(f: f64, fc: f64) -> f64 {
    let f = f.abs();
    if f <= fc {
        1.0
    } else if f >= (1.0 + TAPER) * fc {
        0.0
    } else {
        0.5 * (1.0 + (std::f64::consts::PI * (f - fc) / (TAPER * fc)).cos())
    }
}

/// The gain and twiddles of one transform length, step and cut-off.
#[derive(Debug, Clone)]
struct Plan {
    key: (usize, u64, u64),
    h: Vec<f64>,
    forward: Vec<(f64, f64)>,
    inverse: Vec<(f64, f64)>,
}

/// Work buffers of the filter and its plans, kept between calls (no allocation per
/// history once a length has been seen).
#[derive(Debug, Default, Clone)]
pub struct LowPass {
    re: Vec<f64>,
    im: Vec<f64>,
    plans: Vec<Plan>,
}

impl LowPass {
    /// The transform length for `n` samples at step `dt` and cut-off `fc`: a power of two
    /// at least `n` plus ten periods of the cut-off's taper band (the filter's ringing).
    fn size(n: usize, dt: f64, fc: f64) -> usize {
        let ring = (10.0 / (TAPER * fc * dt)).ceil() as usize;
        (n + ring).next_power_of_two()
    }

    /// Filters the histories `x` and `y` (same length, sampled at `dt`) in place with
    /// cut-off `fc` (Hz). `y` may be empty (one history).
    pub fn apply_pair(&mut self, x: &mut [f64], y: &mut [f64], dt: f64, fc: f64) {
        let n = x.len();
        let m = Self::size(n, dt, fc);
        let key = (m, dt.to_bits(), fc.to_bits());
        let k = match self.plans.iter().position(|p| p.key == key) {
            Some(k) => k,
            None => {
                let h = (0..m)
                    .map(|k| {
                        let k = if k <= m / 2 {
                            k as f64
                        } else {
                            k as f64 - m as f64
                        };
                        // The inverse transform has no 1/m factor: it goes into the gain.
                        gain(k / (m as f64 * dt), fc) / m as f64
                    })
                    .collect();
                self.plans.push(Plan {
                    key,
                    h,
                    forward: twiddles(m, false),
                    inverse: twiddles(m, true),
                });
                self.plans.len() - 1
            }
        };
        let plan = &self.plans[k];
        self.re.resize(m, 0.0);
        self.im.resize(m, 0.0);
        self.re[..n].copy_from_slice(x);
        self.re[n..m].fill(0.0);
        if y.len() == n {
            self.im[..n].copy_from_slice(y);
        } else {
            self.im[..n].fill(0.0);
        }
        self.im[n..m].fill(0.0);
        let (re, im) = (&mut self.re[..m], &mut self.im[..m]);
        fft_with(re, im, &plan.forward);
        for k in 0..m {
            re[k] *= plan.h[k];
            im[k] *= plan.h[k];
        }
        fft_with(re, im, &plan.inverse);
        x.copy_from_slice(&re[..n]);
        if y.len() == n {
            y.copy_from_slice(&im[..n]);
        }
    }

    /// Filters one history in place.
    pub fn apply(&mut self, x: &mut [f64], dt: f64, fc: f64) {
        self.apply_pair(x, &mut [], dt, fc);
    }
}
