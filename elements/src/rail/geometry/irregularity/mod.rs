//! Track irregularities: the deviation of each rail head from its design position, as four
//! standard components along the station, read from a CSV table or generated from a
//! standard spectrum, summed over any number of sources.
//!
//! Components and signs (axis 1 lateral towards the left of travel, axis 2 up, the wheel
//! frame of `framework/src/moving.rs`; rail 0 left, rail 1 right):
//!
//! ```text
//! vertical profile  v = (z_L + z_R)/2        cross-level  c = z_L − z_R
//! alignment         a = (y_L + y_R)/2        gauge        g = y_L − y_R  (positive = wider)
//! ⇒ z_L = v + c/2,  z_R = v − c/2,   y_L = a + g/2,  y_R = a − g/2
//! ```
//!
//! (the left rail is at +axis 1, so a positive gauge deviation moves it further left and
//! the right rail further right). Each component is interpolated in station by a C²
//! not-a-knot cubic spline ([`CubicSpline`]): a wheel rolling on the profile feels its
//! curvature as an inertia force, `m·v²·z''(s)`, so a piecewise-linear (C⁰) table would
//! give force impulses at every knot and a C¹ Hermite scheme steps in force; the spline's
//! curvature is continuous. Outside a table's stations the end value is held (no jump).
//!
//! Submodules: [`psd`] (the standard spectra), [`generate`] (random profiles with a given
//! spectrum, the Welch estimator), [`csv`] (tables in files), [`estimate`] (their part of
//! the model's size estimate).

pub mod csv;
pub mod estimate;
pub mod generate;
pub mod psd;

use crate::rail::contact::profiles::CubicSpline;
use csv::IrregularityTable;
use generate::PsdRequest;
use psd::{Component, PsdClass};
use railfem_framework::error::FemError;
use railfem_framework::limits::{self, fmt_num};
use serde::Deserialize;
use serde_json::Value;
use std::path::Path;

/// One source of irregularity: a spline per component it defines.
#[derive(Debug, Clone)]
pub struct IrregularityPart {
    /// Where it came from (`irr.csv`, `fra4 seed 1`).
    pub label: String,
    /// Component splines, station (m) → deviation (m).
    pub splines: Vec<(Component, CubicSpline)>,
}

impl IrregularityPart {
    /// A part from a table (splines through every row).
    pub fn from_table(t: &IrregularityTable, label: &str) -> Result<Self, String> {
        let splines = t
            .columns
            .iter()
            .map(|(c, v)| {
                CubicSpline::new(&t.stations, v)
                    .map(|s| (*c, s))
                    .map_err(|e| e.to_string())
            })
            .collect::<Result<_, _>>()?;
        Ok(Self {
            label: label.into(),
            splines,
        })
    }

    /// The table this part interpolates (knots and values).
    pub fn table(&self) -> IrregularityTable {
        IrregularityTable {
            stations: self
                .splines
                .first()
                .map(|(_, s)| s.knots().to_vec())
                .unwrap_or_default(),
            columns: self
                .splines
                .iter()
                .map(|(c, s)| (*c, s.values().to_vec()))
                .collect(),
        }
    }
}

/// A track's irregularity: the sum of its parts.
#[derive(Debug, Clone, Default)]
pub struct Irregularity {
    /// The sources, summed.
    pub parts: Vec<IrregularityPart>,
}

impl Irregularity {
    /// `[value, slope, curvature]` of component `c` at station `s` (m, 1, 1/m); each part
    /// holds its end values outside its stations (slope and curvature zero there).
    pub fn component_all(&self, c: Component, s: f64) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (_, sp) in self
            .parts
            .iter()
            .flat_map(|p| &p.splines)
            .filter(|(d, _)| *d == c)
        {
            let (a, b) = sp.domain();
            let v = if s < a || s > b {
                [sp.value(s.clamp(a, b)), 0.0, 0.0]
            } else {
                sp.eval_all(s)
            };
            for k in 0..3 {
                out[k] += v[k];
            }
        }
        out
    }

    /// Component `c` at station `s` (m).
    pub fn component(&self, c: Component, s: f64) -> f64 {
        self.component_all(c, s)[0]
    }

    /// `[lateral (axis 1), vertical (axis 2)]` deviation of rail `rail` (0 left, 1 right)
    /// at station `s` (m), from the four components (module doc).
    pub fn rail_offset(&self, rail: usize, s: f64) -> [f64; 2] {
        let side = if rail == 0 { 0.5 } else { -0.5 };
        let v = self.component(Component::Vertical, s);
        let c = self.component(Component::CrossLevel, s);
        let a = self.component(Component::Alignment, s);
        let g = self.component(Component::Gauge, s);
        [a + side * g, v + side * c]
    }
}

/// One entry of `[track] irregularity` (docs/model-format.md).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IrregularitySpec {
    /// A CSV table, relative to the model file.
    #[serde(default)]
    pub file: Option<String>,
    /// A standard spectrum ([`PsdClass::NAMES`]).
    #[serde(default)]
    pub psd: Option<PsdClass>,
    /// Seed of the random phases.
    #[serde(default)]
    pub seed: Option<u64>,
    /// `[λmin, λmax]` (m).
    #[serde(default)]
    pub wavelengths: Option<[f64; 2]>,
    /// Sampling step (m); default λmin/8.
    #[serde(default)]
    pub step: Option<f64>,
    /// First station of the generated profile (m); default the start of the mesh.
    #[serde(default)]
    pub start: Option<f64>,
    /// Length of the generated profile (m); default to the end of the mesh.
    #[serde(default)]
    pub length: Option<f64>,
    /// Components to take (default all the source has).
    #[serde(default)]
    pub components: Option<Vec<Component>>,
}

fn pick_components(
    asked: &Option<Vec<Component>>,
    offered: &[Component],
    what: &str,
) -> Result<Vec<Component>, String> {
    let names: Vec<&str> = offered.iter().map(|c| c.name()).collect();
    let Some(list) = asked else {
        return Ok(offered.to_vec());
    };
    if list.is_empty() {
        return Err(format!(
            "`components` is empty; name some of {}",
            names.join(", ")
        ));
    }
    let mut out = Vec::new();
    for &c in list {
        let n = c.name();
        if !offered.contains(&c) {
            return Err(format!(
                "`components` names `{n}`, which {what} does not give; choose from {}",
                names.join(", ")
            ));
        }
        if out.contains(&c) {
            return Err(format!("`components` names `{n}` twice"));
        }
        out.push(c);
    }
    Ok(out)
}

/// A generated part: the profile of each component at `start + j·step`.
pub fn generate_part(
    req: &PsdRequest,
    start: f64,
    components: &[Component],
) -> Result<IrregularityPart, String> {
    req.validate()?;
    let (n, m) = req.sizes();
    // All components are held at once (the validation checked one).
    limits::check_memory(
        &format!(
            "`length` = {} m at `step` = {} m",
            fmt_num(req.length),
            fmt_num(req.step)
        ),
        m as f64,
        "irregularity samples",
        generate::BYTES_PER_SAMPLE * components.len().max(1) as f64,
        "give a larger `step` or a shorter `length`",
    )?;
    let stations: Vec<f64> = (0..n).map(|j| start + j as f64 * req.step).collect();
    let mut columns = Vec::new();
    for &c in components {
        let z = req
            .generate(c)
            .ok_or_else(|| format!("`{}` does not define `{}`", req.class.name(), c.name()))?;
        columns.push((c, z));
    }
    IrregularityPart::from_table(
        &IrregularityTable { stations, columns },
        &format!("{} seed {}", req.class.name(), req.seed),
    )
}

/// Builds the irregularity of `[track] irregularity` (one table or a list of tables):
/// files relative to `base`, generated profiles by default over the meshed `[from, to]`.
pub fn from_value(
    v: &Value,
    base: &Path,
    [from, to]: [f64; 2],
    origin: &str,
) -> Result<Irregularity, FemError> {
    let list: Vec<&Value> = match v {
        Value::Array(a) => a.iter().collect(),
        o @ Value::Object(_) => vec![o],
        _ => {
            return Err(FemError::input(
                origin,
                "`irregularity` must be a table ({file = \"irr.csv\"} or {psd = \"fra4\", seed = 1, wavelengths = [1, 50]}) or a list of them",
            ))
        }
    };
    let mut out = Irregularity::default();
    for (i, item) in list.into_iter().enumerate() {
        let o = format!("{origin} irregularity[{i}]");
        let e = |m: String| FemError::input(&o, m);
        let spec: IrregularitySpec = railfem_framework::keypath::from_value(
            item,
            origin,
            &format!("track.irregularity[{i}]"),
        )?;
        match (&spec.file, &spec.psd) {
            (Some(f), None) => {
                for (key, given) in [
                    ("seed", spec.seed.is_some()),
                    ("wavelengths", spec.wavelengths.is_some()),
                    ("step", spec.step.is_some()),
                    ("start", spec.start.is_some()),
                    ("length", spec.length.is_some()),
                ] {
                    if given {
                        return Err(e(format!(
                            "`{key}` belongs to a generated profile (`psd`), not to a `file`; remove it"
                        )));
                    }
                }
                let path = base.join(f);
                let t = csv::read_table_file(&path).map_err(|x| e(x.to_string()))?;
                let offered: Vec<Component> = t.columns.iter().map(|(c, _)| *c).collect();
                let keep =
                    pick_components(&spec.components, &offered, &format!("`{f}`")).map_err(e)?;
                let t = IrregularityTable {
                    stations: t.stations,
                    columns: t
                        .columns
                        .into_iter()
                        .filter(|(c, _)| keep.contains(c))
                        .collect(),
                };
                let part = IrregularityPart::from_table(&t, f).map_err(e)?;
                out.parts.push(part);
            }
            (None, Some(class)) => {
                let class = *class;
                let seed = spec
                    .seed
                    .ok_or_else(|| e("a generated profile needs `seed` (an integer ≥ 0)".into()))?;
                let wavelengths = spec.wavelengths.ok_or_else(|| {
                    e(
                        "a generated profile needs `wavelengths` = [λmin, λmax] (m), e.g. [1, 50]"
                            .into(),
                    )
                })?;
                let start = spec.start.unwrap_or(from);
                let length = spec.length.unwrap_or(to - start);
                let req = PsdRequest {
                    class,
                    seed,
                    wavelengths,
                    step: spec.step.unwrap_or(wavelengths[0] / 8.0),
                    length,
                };
                if !start.is_finite() {
                    return Err(e(format!("`start` = {start}: give a station in m")));
                }
                let comps = pick_components(
                    &spec.components,
                    class.components(),
                    &format!("`{}`", class.name()),
                )
                .map_err(e)?;
                out.parts
                    .push(generate_part(&req, start, &comps).map_err(e)?);
            }
            (Some(_), Some(_)) => {
                return Err(e(
                    "give either `file` or `psd` in one entry, not both (use a list for both)"
                        .into(),
                ))
            }
            (None, None) => {
                return Err(e(
                    "give `file = \"irr.csv\"` (a table) or `psd = \"…\"` (a generated profile)"
                        .into(),
                ))
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(c: Component, f: impl Fn(f64) -> f64) -> IrregularityPart {
        let st: Vec<f64> = (0..41).map(|i| i as f64 * 0.5).collect();
        let v = st.iter().map(|&s| f(s)).collect();
        IrregularityPart::from_table(
            &IrregularityTable {
                stations: st,
                columns: vec![(c, v)],
            },
            "t",
        )
        .unwrap()
    }

    /// The rail offsets recombine to the definitions: mean and difference of the rails.
    #[test]
    fn rail_offsets_follow_the_definitions() {
        let irr = Irregularity {
            parts: vec![
                part(Component::Vertical, |s| 1e-3 * (0.3 * s).sin()),
                part(Component::CrossLevel, |s| 2e-3 * (0.2 * s).cos()),
                part(Component::Alignment, |s| 1e-3 * (0.1 * s).cos()),
                part(Component::Gauge, |s| 5e-4 * (0.4 * s).sin()),
            ],
        };
        for s in [0.0, 3.3, 7.75, 19.9] {
            let [yl, zl] = irr.rail_offset(0, s);
            let [yr, zr] = irr.rail_offset(1, s);
            let c = |k| irr.component(k, s);
            assert!(((zl + zr) / 2.0 - c(Component::Vertical)).abs() < 1e-18);
            assert!((zl - zr - c(Component::CrossLevel)).abs() < 1e-18);
            assert!(((yl + yr) / 2.0 - c(Component::Alignment)).abs() < 1e-18);
            assert!((yl - yr - c(Component::Gauge)).abs() < 1e-18);
        }
        // Positive gauge widens: the left rail (at +axis 1) moves to +axis 1.
        let g = Irregularity {
            parts: vec![part(Component::Gauge, |_| 1e-3)],
        };
        assert!(g.rail_offset(0, 5.0)[0] > 0.0 && g.rail_offset(1, 5.0)[0] < 0.0);
    }

    /// Interpolation is C¹ (indeed C²): at every interior knot the one-sided slopes and
    /// curvatures agree to rounding, and between knots the spline of a smooth profile
    /// sampled 16 times per wave stays within (hΩ)⁴/384·amplitude·5 of it.
    #[test]
    fn interpolation_is_smooth() {
        let w = 2.0 * std::f64::consts::PI / 8.0;
        let p = part(Component::Vertical, |s| 1e-3 * (w * s).sin());
        let sp = &p.splines[0].1;
        let eps = 1e-9;
        for &k in &sp.knots()[1..sp.knots().len() - 1] {
            let l = sp.eval_all(k - eps);
            let r = sp.eval_all(k + eps);
            assert!((l[1] - r[1]).abs() < 1e-9, "slope jump at {k}");
            assert!((l[2] - r[2]).abs() < 1e-7, "curvature jump at {k}");
        }
        let bound = (0.5 * w).powi(4) / 384.0 * 1e-3 * 5.0;
        for i in 0..400 {
            let s = 2.0 + i as f64 * 0.04;
            assert!((sp.value(s) - 1e-3 * (w * s).sin()).abs() < bound);
        }
    }

    #[test]
    fn held_outside_the_table() {
        let p = part(Component::Vertical, |s| 1e-4 * s);
        let irr = Irregularity { parts: vec![p] };
        assert_eq!(irr.component(Component::Vertical, -5.0), 0.0);
        assert!((irr.component(Component::Vertical, 100.0) - 2e-3).abs() < 1e-15);
    }

    #[test]
    fn refuses_bad_entries() {
        let bad = |v: Value, expect: &str| {
            let e = from_value(&v, Path::new("."), [0.0, 100.0], "m.toml: [track]")
                .unwrap_err()
                .to_string();
            assert!(e.contains(expect), "{e}");
        };
        bad(
            serde_json::json!({"psd": "fra9", "seed": 1, "wavelengths": [1, 50]}),
            "`track.irregularity[0].psd`: unknown spectrum `fra9`, expected one of `fra1`, `fra2`, `fra3`, `fra4`, `fra5`, `fra6`, `german_low`, `german_high`",
        );
        bad(
            serde_json::json!({"psd": "fra4", "seed": 1, "wavelengths": [50, 1]}),
            "0 < λmin < λmax",
        );
        bad(
            serde_json::json!({"psd": "fra4", "seed": 1, "wavelengths": [1, 50], "components": ["gauge"]}),
            "`gauge`, which `fra4` does not give",
        );
        bad(
            serde_json::json!({"psd": "fra4", "seed": 1, "wavelengths": [1, 50], "components": ["vertical", "heave"]}),
            "`track.irregularity[0].components[1]`: unknown variant `heave`, expected one of `vertical`, `alignment`, `cross_level`, `gauge`",
        );
        bad(serde_json::json!({"file": "nope.csv"}), "cannot read");
        bad(serde_json::json!({"seed": 1}), "give `file");
    }
}
