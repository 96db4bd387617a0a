//! The standard track-irregularity spectra: US FRA classes 1–6 and the German high-speed
//! low- and high-disturbance spectra, as one-sided power spectral densities of the
//! spatial angular frequency Ω (rad/m), in m²/(rad/m).
//!
//! Units convention: `∫ S(Ω) dΩ` over Ω ≥ 0 is the variance (m²) of the irregularity. A
//! density per cycle/m, `G(f)` with `f = Ω/2π`, is `G = 2π·S`.
//!
//! **FRA** (the Federal Railroad Administration's six track classes, in the SI form of
//! Hamid & Yang and Garg & Dukkipati, *Dynamics of Railway Vehicle Systems*, 1984, as used
//! throughout the vehicle–track literature with `k = 0.25`):
//!
//! ```text
//! vertical profile  S_v(Ω) = k·A_v·Ω_c² / (Ω²·(Ω² + Ω_c²))
//! alignment         S_a(Ω) = k·A_a·Ω_c² / (Ω²·(Ω² + Ω_c²))
//! cross-level       S_c(Ω) = 4k·A_v·Ω_c² / ((Ω² + Ω_c²)·(Ω² + Ω_s²))
//! ```
//!
//! with `A_v`, `A_a` in cm²·rad/m (the densities come out in cm²/(rad/m); ×1e-4 for m²)
//! and `Ω_c`, `Ω_s` in rad/m ([`FRA`]). The cross-level is the height difference of the
//! two rails (m). FRA gives no gauge spectrum.
//!
//! **German** high-speed spectra, low and high disturbance (in the form quoted throughout
//! the vehicle–track literature, e.g. Zhai, *Vehicle–Track Coupled Dynamics*):
//!
//! ```text
//! vertical profile  S_v(Ω) = A_v·Ω_c² / ((Ω² + Ω_r²)·(Ω² + Ω_c²))
//! alignment         S_a(Ω) = A_a·Ω_c² / ((Ω² + Ω_r²)·(Ω² + Ω_c²))
//! cross-level       S_c(Ω) = (A_v/b²)·Ω_c²·Ω² / ((Ω² + Ω_r²)·(Ω² + Ω_c²)·(Ω² + Ω_s²))
//! gauge             S_g(Ω) = A_g·Ω_c²·Ω² / ((Ω² + Ω_r²)·(Ω² + Ω_c²)·(Ω² + Ω_s²))
//! ```
//!
//! with `A` in m²·rad/m, `Ω` in rad/m, `b = 0.75 m` half the distance between the rails'
//! rolling circles ([`GERMAN_LOW`], [`GERMAN_HIGH`]). `S_c` as printed is the density of
//! the cross-level *angle* (rad²/(rad/m)); railfem's cross-level is the height difference
//! `2b·angle`, so it uses `(2b)²·S_c = 4·A_v·Ω_c²·Ω²/(…)` m²/(rad/m).

/// The four standard components of a track irregularity (a model file's `components`
/// names them: `vertical`, `alignment`, `cross_level`, `gauge`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Component {
    /// Mean of the two rails' vertical deviations (m, up positive).
    Vertical,
    /// Mean of the two rails' lateral deviations (m, towards the left of travel positive).
    Alignment,
    /// Left minus right vertical deviation (m).
    CrossLevel,
    /// Left minus right lateral deviation (m, positive = wider).
    Gauge,
}

impl Component {
    /// All four, in the column order of the CSV files.
    pub const ALL: [Component; 4] = [
        Component::Vertical,
        Component::Alignment,
        Component::CrossLevel,
        Component::Gauge,
    ];

    /// The name used in model files and CSV headers.
    pub fn name(self) -> &'static str {
        match self {
            Component::Vertical => "vertical",
            Component::Alignment => "alignment",
            Component::CrossLevel => "cross_level",
            Component::Gauge => "gauge",
        }
    }

    /// Index in [`Component::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The component named `s` (`cross-level` is accepted for `cross_level`).
    pub fn parse(s: &str) -> Option<Self> {
        let t = s.trim().to_ascii_lowercase().replace('-', "_");
        Component::ALL.into_iter().find(|c| c.name() == t)
    }
}

/// `[A_v, A_a, Ω_s, Ω_c]` of FRA classes 1 to 6: A in cm²·rad/m, Ω in rad/m.
pub const FRA: [[f64; 4]; 6] = [
    [1.2107, 3.3634, 0.6046, 0.8245],
    [1.0181, 1.2107, 0.9308, 0.8245],
    [0.6816, 0.4128, 0.8520, 0.8245],
    [0.5376, 0.3027, 1.1312, 0.8245],
    [0.2095, 0.0762, 0.8209, 0.8245],
    [0.0339, 0.0339, 0.4380, 0.8245],
];

/// The FRA scale factor `k` of the SI form.
pub const FRA_K: f64 = 0.25;

/// German spectrum constants: A in m²·rad/m, Ω in rad/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GermanConstants {
    /// Vertical profile roughness `A_v`.
    pub a_v: f64,
    /// Alignment roughness `A_a`.
    pub a_a: f64,
    /// Gauge roughness `A_g`.
    pub a_g: f64,
    /// Cut-off `Ω_c`.
    pub omega_c: f64,
    /// Cut-off `Ω_r`.
    pub omega_r: f64,
    /// Cut-off `Ω_s`.
    pub omega_s: f64,
}

/// The German low-disturbance spectrum.
pub const GERMAN_LOW: GermanConstants = GermanConstants {
    a_v: 4.032e-7,
    a_a: 2.119e-7,
    a_g: 0.532e-7,
    omega_c: 0.8246,
    omega_r: 0.0206,
    omega_s: 0.4380,
};

/// The German high-disturbance spectrum.
pub const GERMAN_HIGH: GermanConstants = GermanConstants {
    a_v: 10.80e-7,
    a_a: 6.125e-7,
    a_g: 1.032e-7,
    omega_c: 0.8246,
    omega_r: 0.0206,
    omega_s: 0.4380,
};

/// Half the distance between the rolling circles in the German cross-level spectrum (m).
pub const GERMAN_B: f64 = 0.75;

/// A standard spectrum. In a model file it is one of [`PsdClass::NAMES`] (`psd = "fra4"`);
/// any other name is refused with the list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(try_from = "String")]
pub enum PsdClass {
    /// FRA track class 1 (worst) to 6 (best).
    Fra(u8),
    /// German high-speed, low disturbance.
    GermanLow,
    /// German high-speed, high disturbance.
    GermanHigh,
}

impl TryFrom<String> for PsdClass {
    type Error = String;
    fn try_from(s: String) -> Result<Self, String> {
        PsdClass::parse(&s).ok_or_else(|| {
            format!(
                "unknown spectrum `{s}`, expected one of {}",
                PsdClass::NAMES.map(|n| format!("`{n}`")).join(", ")
            )
        })
    }
}

impl PsdClass {
    /// The names offered in model files and on the command line.
    pub const NAMES: [&'static str; 8] = [
        "fra1",
        "fra2",
        "fra3",
        "fra4",
        "fra5",
        "fra6",
        "german_low",
        "german_high",
    ];

    /// The class named `s` (case and `-`/`_` insensitive).
    pub fn parse(s: &str) -> Option<Self> {
        let t = s.trim().to_ascii_lowercase().replace('-', "_");
        match t.as_str() {
            "german_low" => Some(PsdClass::GermanLow),
            "german_high" => Some(PsdClass::GermanHigh),
            _ => t
                .strip_prefix("fra")
                .and_then(|n| n.parse::<u8>().ok())
                .filter(|n| (1..=6).contains(n))
                .map(PsdClass::Fra),
        }
    }

    /// The name in [`PsdClass::NAMES`].
    pub fn name(self) -> String {
        match self {
            PsdClass::Fra(n) => format!("fra{n}"),
            PsdClass::GermanLow => "german_low".into(),
            PsdClass::GermanHigh => "german_high".into(),
        }
    }

    /// The components this spectrum defines.
    pub fn components(self) -> &'static [Component] {
        match self {
            PsdClass::Fra(_) => &[
                Component::Vertical,
                Component::Alignment,
                Component::CrossLevel,
            ],
            _ => &Component::ALL,
        }
    }

    /// One-sided density `S(Ω)` of component `c` at `omega` (rad/m), m²/(rad/m); `None`
    /// if the class does not define `c`.
    pub fn density(self, c: Component, omega: f64) -> Option<f64> {
        let w2 = omega * omega;
        match self {
            PsdClass::Fra(n) => {
                let [a_v, a_a, o_s, o_c] = FRA[(n - 1) as usize];
                let oc2 = o_c * o_c;
                let cm2 = match c {
                    Component::Vertical => FRA_K * a_v * oc2 / (w2 * (w2 + oc2)),
                    Component::Alignment => FRA_K * a_a * oc2 / (w2 * (w2 + oc2)),
                    Component::CrossLevel => {
                        4.0 * FRA_K * a_v * oc2 / ((w2 + oc2) * (w2 + o_s * o_s))
                    }
                    Component::Gauge => return None,
                };
                Some(cm2 * 1e-4)
            }
            PsdClass::GermanLow | PsdClass::GermanHigh => {
                let g = if self == PsdClass::GermanLow {
                    GERMAN_LOW
                } else {
                    GERMAN_HIGH
                };
                let oc2 = g.omega_c * g.omega_c;
                let base = (w2 + g.omega_r * g.omega_r) * (w2 + oc2);
                let third = base * (w2 + g.omega_s * g.omega_s);
                Some(match c {
                    Component::Vertical => g.a_v * oc2 / base,
                    Component::Alignment => g.a_a * oc2 / base,
                    // (2b)²·(A_v/b²) = 4·A_v: the height difference, not the angle.
                    Component::CrossLevel => 4.0 * g.a_v * oc2 * w2 / third,
                    Component::Gauge => g.a_g * oc2 * w2 / third,
                })
            }
        }
    }
}

/// `∫ S dΩ` of component `c` over `[omega_lo, omega_hi]` by composite Simpson's rule in
/// `ln Ω` (2000 panels: the densities are smooth rational functions, the error is far
/// below 1e-8 relative). The variance of a profile limited to that band (m²).
pub fn band_variance(class: PsdClass, c: Component, omega_lo: f64, omega_hi: f64) -> f64 {
    let n = 2000;
    let (a, b) = (omega_lo.ln(), omega_hi.ln());
    let h = (b - a) / n as f64;
    let f = |u: f64| {
        let w = u.exp();
        class.density(c, w).unwrap_or(0.0) * w
    };
    let mut sum = f(a) + f(b);
    for i in 1..n {
        sum += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The asymptotes of the formulas: FRA vertical ~ k·A_v/Ω² well below Ω_c and
    /// ~ k·A_v·Ω_c²/Ω⁴ well above; German vertical → A_v/Ω_r² as Ω → 0 (flat), and
    /// German gauge and cross-level vanish like Ω² at Ω → 0.
    #[test]
    fn asymptotes() {
        let [a_v, _, _, o_c] = FRA[3];
        let lo = PsdClass::Fra(4).density(Component::Vertical, 1e-4).unwrap();
        assert!((lo / (FRA_K * a_v * 1e-4 / 1e-8) - 1.0).abs() < 1e-6);
        let hi = PsdClass::Fra(4).density(Component::Vertical, 1e3).unwrap();
        assert!((hi / (FRA_K * a_v * 1e-4 * o_c * o_c / 1e12) - 1.0).abs() < 1e-5);
        let g0 = PsdClass::GermanLow
            .density(Component::Vertical, 1e-6)
            .unwrap();
        let r = GERMAN_LOW.omega_r;
        assert!((g0 / (GERMAN_LOW.a_v / (r * r)) - 1.0).abs() < 1e-6);
        let g1 = PsdClass::GermanHigh
            .density(Component::Gauge, 1e-5)
            .unwrap();
        let g2 = PsdClass::GermanHigh
            .density(Component::Gauge, 2e-5)
            .unwrap();
        assert!((g2 / g1 - 4.0).abs() < 1e-5);
        assert!(PsdClass::Fra(1).density(Component::Gauge, 1.0).is_none());
    }

    /// Worse classes are rougher: FRA class 1's vertical variance over 1–50 m exceeds
    /// class 6's, and the German high-disturbance exceeds the low one by A_v's ratio.
    #[test]
    fn ordering_of_classes() {
        let (lo, hi) = (
            2.0 * std::f64::consts::PI / 50.0,
            2.0 * std::f64::consts::PI,
        );
        let v = |c| band_variance(c, Component::Vertical, lo, hi);
        for n in 1..6u8 {
            assert!(v(PsdClass::Fra(n)) > v(PsdClass::Fra(n + 1)));
        }
        let ratio = v(PsdClass::GermanHigh) / v(PsdClass::GermanLow);
        assert!((ratio - GERMAN_HIGH.a_v / GERMAN_LOW.a_v).abs() < 1e-12);
    }

    /// Simpson in ln Ω against the closed form: Ω_c²/(Ω²(Ω²+Ω_c²)) = 1/Ω² − 1/(Ω²+Ω_c²),
    /// so ∫ k·A·Ω_c²/(Ω²(Ω²+Ω_c²)) dΩ = k·A·[−1/Ω − atan(Ω/Ω_c)/Ω_c].
    #[test]
    fn band_variance_against_closed_form() {
        let [a_v, _, _, o_c] = FRA[0];
        let f = |w: f64| -1.0 / w - (w / o_c).atan() / o_c;
        let (lo, hi) = (0.1, 6.0);
        let exact = FRA_K * a_v * 1e-4 * (f(hi) - f(lo));
        let num = band_variance(PsdClass::Fra(1), Component::Vertical, lo, hi);
        assert!((num / exact - 1.0).abs() < 1e-9, "{num} vs {exact}");
    }

    #[test]
    fn names_round_trip() {
        for n in PsdClass::NAMES {
            assert_eq!(PsdClass::parse(n).unwrap().name(), n);
        }
        assert_eq!(PsdClass::parse("German-Low"), Some(PsdClass::GermanLow));
        assert_eq!(PsdClass::parse("fra7"), None);
        for c in Component::ALL {
            assert_eq!(Component::parse(c.name()), Some(c));
        }
    }
}
