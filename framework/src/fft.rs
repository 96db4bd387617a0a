//! The discrete Fourier transform used by railfem's signal processing (irregularity
//! generation and Welch estimates, ride-comfort spectra): an in-place radix-2 FFT and the
//! portable `sin_cos` its twiddles come from.
//!
//! Everything here uses only IEEE-754 `+ − × ÷` (correctly rounded), never the platform's
//! libm, so a transform gives the same bits on every machine: a generated track
//! irregularity is reproducible from its seed anywhere.

use std::f64::consts::PI;

/// `(sin x, cos x)` from a fixed polynomial: reduction by the nearest multiple `q·π/2`
/// (π/2 split in two parts), then the Taylor series of sin and cos on `|r| ≤ π/4` to
/// degree 17 and 18 (truncation below 3e-19). The rounding of `q·π/2` limits the accuracy
/// to about `|q|·2e-16`: within 1e-15 for `|x| ≤ 4π` (the generator's arguments lie in
/// `[0, 2π)`). The same bits on every IEEE-754 machine.
pub fn sin_cos(x: f64) -> (f64, f64) {
    const PIO2_HI: f64 = std::f64::consts::FRAC_PI_2;
    const PIO2_LO: f64 = 6.123_233_995_736_766e-17;
    let q = (x * (2.0 / PI)).round();
    let r = (x - q * PIO2_HI) - q * PIO2_LO;
    let r2 = r * r;
    // Horner, highest degree first: sin r = r·Σ_k (−1)^k r^{2k}/(2k+1)!, k ≤ 8;
    // cos r = Σ_k (−1)^k r^{2k}/(2k)!, k ≤ 9. The factorials are exact in f64 (18! < 2^53).
    let fact = |n: usize| (1..=n).fold(1.0f64, |a, i| a * i as f64);
    let sign = |k: usize| if k % 2 == 0 { 1.0 } else { -1.0 };
    let mut s = 0.0;
    for k in (0..=8).rev() {
        s = s * r2 + sign(k) / fact(2 * k + 1);
    }
    let mut c = 0.0;
    for k in (0..=9).rev() {
        c = c * r2 + sign(k) / fact(2 * k);
    }
    let sin_r = s * r;
    let cos_r = c;
    match (q as i64).rem_euclid(4) {
        0 => (sin_r, cos_r),
        1 => (cos_r, -sin_r),
        2 => (-sin_r, -cos_r),
        _ => (-cos_r, sin_r),
    }
}

/// In-place radix-2 FFT of `(re, im)` (length a power of two):
/// `X_k = Σ_j x_j·e^{∓2πi·jk/n}`, `−` forward, `+` with `inverse` (no 1/n factor).
pub fn fft(re: &mut [f64], im: &mut [f64], inverse: bool) {
    let tw = twiddles(re.len(), inverse);
    fft_with(re, im, &tw);
}

/// The twiddles `e^{∓2πi·m/n}`, `m < n/2`, of a transform of length `n` (`+` with
/// `inverse`), for [`fft_with`]: made once, they serve every transform of that length.
pub fn twiddles(n: usize, inverse: bool) -> Vec<(f64, f64)> {
    let sign = if inverse { 1.0 } else { -1.0 };
    (0..n / 2)
        .map(|m| {
            let (s, c) = sin_cos(2.0 * PI * m as f64 / n as f64);
            (c, sign * s)
        })
        .collect()
}

/// [`fft`] with the twiddles given ([`twiddles`] of the same length and direction).
pub fn fft_with(re: &mut [f64], im: &mut [f64], tw: &[(f64, f64)]) {
    let n = re.len();
    assert!(
        n.is_power_of_two() && im.len() == n && tw.len() == n / 2,
        "fft length"
    );
    if n < 2 {
        return;
    }
    // Bit-reversal permutation.
    let bits = n.trailing_zeros();
    for i in 0..n {
        let j = i.reverse_bits() >> (usize::BITS - bits);
        if j > i {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let half = len / 2;
        let stride = n / len;
        for start in (0..n).step_by(len) {
            for k in 0..half {
                let (wr, wi) = tw[k * stride];
                let (a, b) = (start + k, start + k + half);
                let tr = re[b] * wr - im[b] * wi;
                let ti = re[b] * wi + im[b] * wr;
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
            }
        }
        len *= 2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sin_cos_matches_libm() {
        let mut worst = 0.0f64;
        for i in -2000..=2000 {
            let x = i as f64 * 0.00628;
            let (s, c) = sin_cos(x);
            worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
        }
        assert!(worst < 1e-15, "worst {worst}");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
    }

    /// The FFT against the direct DFT sum, and inverse(forward(x)) = n·x.
    #[test]
    fn fft_matches_dft() {
        let n = 64;
        let x: Vec<f64> = (0..n).map(|j| ((j * 7 % 13) as f64 - 6.0) * 0.1).collect();
        let (mut re, mut im) = (x.clone(), vec![0.0; n]);
        fft(&mut re, &mut im, false);
        for k in 0..n {
            let (mut sr, mut si) = (0.0, 0.0);
            for (j, v) in x.iter().enumerate() {
                let a = -2.0 * PI * (j * k) as f64 / n as f64;
                sr += v * a.cos();
                si += v * a.sin();
            }
            assert!((sr - re[k]).abs() < 1e-12 && (si - im[k]).abs() < 1e-12);
        }
        fft(&mut re, &mut im, true);
        for j in 0..n {
            assert!((re[j] / n as f64 - x[j]).abs() < 1e-14);
        }
    }
}
