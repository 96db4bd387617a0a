//! Trains as moving axle loads: the universal dynamic trains HSLM-A1…A10 and HSLM-B of
//! EN 1991-2 §6.4.6.1.1 and Annex E, and a user's train from a TOML or CSV table.
//!
//! A [`Train`] is a list of [`Axle`]s, each a distance behind the first axle (m, ≥ 0,
//! ascending) and a static vertical load (N, downward positive). The crossing starts with
//! the first axle on the bridge's first support.
//!
//! # HSLM-A (EN 1991-2 Fig. 6.12 and Table E.4)
//!
//! Two power cars, two end coaches and `N` intermediate coaches of length `D` (the distance
//! between the centres of the articulated bogies the coaches share), bogie axle spacing
//! `d`, every axle load `P`. The fixed dimensions of the figure: each power car has two
//! bogies of axle spacing 3 m whose inner axles are 11 m apart; the axles of a power car
//! and of the end coach beside it are 3.525 m apart; the end coach (from the coupling,
//! midway between those two axles, to the centre of the first shared bogie) is `D` long.
//! Measured from the first axle:
//!
//! ```text
//! power car        0, 3, 14, 17
//! coupling         c = 17 + 3.525/2
//! end coach        c + 3.525/2,  c + 3.525/2 + d
//! shared bogies    c + D·(k + 1) ± d/2,  k = 0..=N
//! rear end coach   c' − 3.525/2 − d,  c' − 3.525/2     (c' = c + D·(N + 2))
//! rear power car   c' + 3.525/2 + (0, 3, 14, 17)
//! ```
//!
//! so a train has `2N + 14` axles and is `2·(17 + 3.525/2) + D·(N + 2)` m long from first to
//! last axle. The regular spacing that excites resonance is `D` (EN 1991-2 Eq. 6.9,
//! `v = n₀·λ`, `λ = D/i`).
//!
//! # HSLM-B (EN 1991-2 Fig. 6.13 and Fig. E.7)
//!
//! `N` point forces of 170 kN at a uniform spacing `d`, both read from the figure as
//! functions of the span `L` (1 m ≤ L < 7 m, simply supported spans only): `d` rises
//! linearly from 2.5 m at `L = 1 m` to 3.5 m at `L = 7 m`, `N` falls linearly from 20 to 10
//! (rounded to the nearest whole force).

use crate::framework::FemError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One axle of a train.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axle {
    /// Distance behind the first axle (m).
    pub position: f64,
    /// Static vertical load (N, downward positive).
    pub load: f64,
}

/// A train of axle loads.
#[derive(Debug, Clone, PartialEq)]
pub struct Train {
    /// Name (`HSLM-A1`, or the user's).
    pub name: String,
    /// Axles, first at position 0, ascending.
    pub axles: Vec<Axle>,
    /// The regular spacing that excites resonance (m): `D` of HSLM-A, `d` of HSLM-B, or the
    /// user's (`None`: no resonance speeds are marked).
    pub regular_spacing: Option<f64>,
}

impl Train {
    /// Length from first to last axle (m).
    pub fn length(&self) -> f64 {
        self.axles.last().map_or(0.0, |a| a.position)
    }

    /// Total static load (N).
    pub fn total_load(&self) -> f64 {
        self.axles.iter().map(|a| a.load).sum()
    }

    /// Largest axle load (N).
    pub fn max_load(&self) -> f64 {
        self.axles.iter().fold(0.0, |m, a| m.max(a.load))
    }
}

/// One row of EN 1991-2 Table E.4: the parameters of an HSLM-A train.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HslmA {
    /// Number of intermediate coaches `N`.
    pub coaches: usize,
    /// Coach length `D` (m).
    pub coach_length: f64,
    /// Bogie axle spacing `d` (m).
    pub bogie_spacing: f64,
    /// Point force `P` (N).
    pub load: f64,
}

/// EN 1991-2:2003 Table E.4 (HSLM-A1 … HSLM-A10): `N`, `D` (m), `d` (m), `P` (kN).
pub const HSLM_A_TABLE: [(usize, f64, f64, f64); 10] = [
    (18, 18.0, 2.0, 170.0),
    (17, 19.0, 3.5, 200.0),
    (16, 20.0, 2.0, 180.0),
    (15, 21.0, 3.0, 190.0),
    (14, 22.0, 2.0, 170.0),
    (13, 23.0, 2.0, 180.0),
    (13, 24.0, 2.0, 190.0),
    (12, 25.0, 2.5, 190.0),
    (11, 26.0, 2.0, 210.0),
    (11, 27.0, 2.0, 210.0),
];

/// Power-car axles behind its first axle (m), EN 1991-2 Fig. 6.12.
const POWER_CAR: [f64; 4] = [0.0, 3.0, 14.0, 17.0];
/// Axle distance between a power car and its end coach (m), EN 1991-2 Fig. 6.12.
const POWER_TO_COACH: f64 = 3.525;

/// The parameters of HSLM-A`i` (1 ≤ i ≤ 10), `None` otherwise.
pub fn hslm_a_parameters(i: usize) -> Option<HslmA> {
    let (coaches, coach_length, bogie_spacing, p) = *HSLM_A_TABLE.get(i.checked_sub(1)?)?;
    Some(HslmA {
        coaches,
        coach_length,
        bogie_spacing,
        load: p * 1e3,
    })
}

/// The axles of an HSLM-A train from its parameters (module documentation).
pub fn hslm_a_axles(p: &HslmA) -> Vec<Axle> {
    let (dd, d, half) = (p.coach_length, p.bogie_spacing, POWER_TO_COACH / 2.0);
    let mut x: Vec<f64> = POWER_CAR.to_vec();
    let c = POWER_CAR[3] + half;
    x.extend([c + half, c + half + d]);
    for k in 0..=p.coaches {
        let centre = c + dd * (k + 1) as f64;
        x.extend([centre - d / 2.0, centre + d / 2.0]);
    }
    let c2 = c + dd * (p.coaches + 2) as f64;
    x.extend([c2 - half - d, c2 - half]);
    x.extend(POWER_CAR.iter().map(|a| c2 + half + a));
    x.into_iter()
        .map(|position| Axle {
            position,
            load: p.load,
        })
        .collect()
}

/// HSLM-A`i` (1 ≤ i ≤ 10).
pub fn hslm_a(i: usize) -> Option<Train> {
    let p = hslm_a_parameters(i)?;
    Some(Train {
        name: format!("HSLM-A{i}"),
        axles: hslm_a_axles(&p),
        regular_spacing: Some(p.coach_length),
    })
}

/// `(N, d)` of HSLM-B for a span `L` (m), EN 1991-2 Fig. E.7 read as straight lines
/// (module documentation); `None` outside 1 m ≤ L ≤ 7 m.
pub fn hslm_b_parameters(span: f64) -> Option<(usize, f64)> {
    if !(1.0..=7.0).contains(&span) {
        return None;
    }
    let s = (span - 1.0) / 6.0;
    Some(((20.0 - 10.0 * s).round() as usize, 2.5 + s))
}

/// HSLM-B for a span `L` (m): `N` forces of 170 kN at spacing `d`.
pub fn hslm_b(span: f64) -> Option<Train> {
    let (n, d) = hslm_b_parameters(span)?;
    Some(Train {
        name: "HSLM-B".into(),
        axles: (0..n)
            .map(|k| Axle {
                position: d * k as f64,
                load: 170e3,
            })
            .collect(),
        regular_spacing: Some(d),
    })
}

/// A built-in train by name: `HSLM-A1` … `HSLM-A10` (case-insensitive), `HSLM-B` (needs
/// the span, m).
pub fn builtin(name: &str, span: Option<f64>) -> Option<Train> {
    let up = name.to_ascii_uppercase();
    if up == "HSLM-B" {
        return hslm_b(span?);
    }
    let i: usize = up.strip_prefix("HSLM-A")?.parse().ok()?;
    hslm_a(i)
}

/// A user's axle table as a file: TOML `[[axle]]` tables with `position` (m) and `load`
/// (N), or CSV with a header row and the columns `position [m]` and `load [N]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxleFile {
    axle: Vec<Axle>,
}

/// Reads a user's train from `path` (TOML or CSV by extension), checks it and names it.
/// Errors name the file, the row or key and the fix.
pub fn read_user_train(path: &Path, name: &str) -> Result<Train, FemError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        FemError::input(
            &file,
            format!("cannot read the train file ({e}); fix the path"),
        )
    })?;
    let axles = if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
    {
        parse_csv(&text, &file)?
    } else {
        let f: AxleFile = toml::from_str(&text).map_err(|e| {
            FemError::input(
                &file,
                format!(
                    "{}; give [[axle]] tables with position (m) and load (N)",
                    e.message()
                ),
            )
        })?;
        f.axle
    };
    user_train(name, axles, &file)
}

/// Parses `position [m],load [N]` rows after a header.
fn parse_csv(text: &str, file: &str) -> Result<Vec<Axle>, FemError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let v: Vec<Option<f64>> = line.split(',').map(|x| x.trim().parse().ok()).collect();
        match v.as_slice() {
            [Some(position), Some(load)] => out.push(Axle {
                position: *position,
                load: *load,
            }),
            _ => {
                return Err(FemError::input(
                    format!("{file}: line {}", i + 1),
                    "give two numbers, `position [m],load [N]`",
                ))
            }
        }
    }
    Ok(out)
}

/// A checked user train: at least one axle, finite positions ascending from any origin
/// (shifted so the first axle is at 0), finite loads > 0.
pub fn user_train(name: &str, mut axles: Vec<Axle>, origin: &str) -> Result<Train, FemError> {
    if axles.is_empty() {
        return Err(FemError::input(
            origin,
            "the train has no axles; give at least one",
        ));
    }
    for (i, a) in axles.iter().enumerate() {
        if !(a.position.is_finite() && a.load.is_finite() && a.load > 0.0) {
            return Err(FemError::input(
                format!("{origin}: axle {}", i + 1),
                "give a finite position (m) and a load > 0 (N)",
            ));
        }
        if i > 0 && a.position < axles[i - 1].position {
            return Err(FemError::input(
                format!("{origin}: axle {}", i + 1),
                "positions must not decrease; list the axles from the front",
            ));
        }
    }
    let x0 = axles[0].position;
    for a in &mut axles {
        a.position -= x0;
    }
    Ok(Train {
        name: name.to_string(),
        axles,
        regular_spacing: None,
    })
}

/// The listing of `railfem trains`: every built-in train with its parameters, axle count,
/// length and loads.
pub fn listing() -> String {
    use std::fmt::Write as _;
    let mut s = String::from(
        "EN 1991-2 §6.4.6.1.1, Annex E (Table E.4): universal dynamic trains\n\
         train      N   D [m]  d [m]  P [kN]  axles  length [m]  total [kN]\n",
    );
    for i in 1..=10 {
        let p = hslm_a_parameters(i).expect("1..=10");
        let t = hslm_a(i).expect("1..=10");
        let _ = writeln!(
            s,
            "{:<9} {:>3} {:>6.1} {:>6.1} {:>7.0} {:>6} {:>11.3} {:>11.0}",
            t.name,
            p.coaches,
            p.coach_length,
            p.bogie_spacing,
            p.load / 1e3,
            t.axles.len(),
            t.length(),
            t.total_load() / 1e3
        );
    }
    s.push_str(
        "HSLM-B     N point forces of 170 kN at spacing d, from the span L (1-7 m, Fig. E.7):\n",
    );
    for l in [1.0, 3.0, 5.0, 7.0] {
        let (n, d) = hslm_b_parameters(l).expect("in range");
        let _ = writeln!(s, "           L = {l:.0} m: N = {n}, d = {d:.3} m");
    }
    s.push_str("User trains: [[train]] with `file` (TOML [[axle]] position, load; or CSV `position [m],load [N]`) in a bridge-check plan.\n");
    s
}
