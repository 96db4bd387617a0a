//! The study plan (`railfem study PLAN.toml`, docs/study.md): read the TOML file,
//! refuse every key, axis or value it does not know with one line naming the place and the
//! fix, and hand back a [`Plan`]: a base case, the options of that case and the axes whose
//! Cartesian product makes the cases ([`super::cases`]).
//!
//! A base is either a built-in case (`case = "train-bridge"` or `"curve"`, with its options
//! in `[options]`) or a model file (`base = "model.toml"`, relative to the plan's folder).
//! An axis is `[[axis]]` with a `name` and exactly one way to give its values: `values`
//! (a list), `start`/`stop` with `step` or `count` (a range, both ends included), or `dir`
//! (every `*.csv` ground-motion record of a folder, sorted by name).

use crate::framework::error::nearest;
use crate::framework::FemError;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Most cases a plan may expand to.
pub const MAX_CASES: usize = 1_000_000;

/// Keys of the plan's top level.
const TOP_KEYS: [&str; 5] = ["case", "base", "options", "histories", "axis"];
/// Keys of one `[[axis]]` table.
const AXIS_KEYS: [&str; 6] = ["name", "values", "start", "stop", "step", "count"];
/// Keys of the train–bridge case, as options and as axes.
pub const TRAIN_BRIDGE_KEYS: [&str; 28] = [
    "cars",
    "spans",
    "span",
    "element_length",
    "speed",
    "radius",
    "ct",
    "duration",
    "dt",
    "pier_height",
    "mu",
    "penalty",
    "quake",
    "quake_scale",
    "seed",
    "pga",
    "quake_duration",
    "midspans",
    "first_active_set",
    "solver",
    "window",
    "window_ahead",
    "window_tolerance",
    "window_layer",
    "window_layer_damping",
    "far_field",
    "far_field_cutoff",
    "far_field_reach",
];
/// Keys of the curve case, as options and as axes.
pub const CURVE_KEYS: [&str; 12] = [
    "radius",
    "ct",
    "speed",
    "mu",
    "dt",
    "penalty",
    "duration",
    "lengths",
    "anti_roll",
    "tangential",
    "geometry",
    "first_active_set",
];

/// The built-in cases a plan's `case` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BuiltInCase {
    /// `case = "train-bridge"`.
    TrainBridge,
    /// `case = "curve"`.
    Curve,
}

/// Which case the plan varies.
#[derive(Debug, Clone, PartialEq)]
pub enum Base {
    /// `railfem train-bridge` ([`crate::train_bridge`]).
    TrainBridge,
    /// `railfem curve` ([`crate::curve`]).
    Curve,
    /// A model file, parsed into its JSON form.
    Model {
        /// The file.
        path: PathBuf,
        /// Its contents as a JSON value (TOML and JSON files alike).
        value: Value,
    },
}

impl Base {
    /// The name in the table and the sidecar.
    pub fn name(&self) -> String {
        match self {
            Base::TrainBridge => "train-bridge".into(),
            Base::Curve => "curve".into(),
            Base::Model { path, .. } => path.display().to_string(),
        }
    }
}

/// One value of an axis.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisValue {
    /// A number.
    Num(f64),
    /// A word (`tangential = "polach"`) or a path given as text.
    Text(String),
    /// A ground-motion record found in an axis's `dir`.
    Record(PathBuf),
}

impl AxisValue {
    /// The value as the table prints it: numbers in shortest round-trip form, records by
    /// file name.
    pub fn label(&self) -> String {
        match self {
            AxisValue::Num(v) => format!("{v}"),
            AxisValue::Text(t) => t.clone(),
            AxisValue::Record(p) => p
                .file_name()
                .map_or_else(|| p.display().to_string(), |f| f.to_string_lossy().into()),
        }
    }

    /// The value as JSON (what a model-file key path receives).
    pub fn json(&self) -> Value {
        match self {
            AxisValue::Num(v) => {
                serde_json::Number::from_f64(*v).map_or(Value::Null, Value::Number)
            }
            AxisValue::Text(t) => Value::String(t.clone()),
            AxisValue::Record(p) => Value::String(p.display().to_string()),
        }
    }
}

/// One parameter axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The key it sets (a case key, or a dotted key path of a model file).
    pub name: String,
    /// Its values, in order.
    pub values: Vec<AxisValue>,
}

/// A parsed plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The plan file.
    pub file: PathBuf,
    /// The base case.
    pub base: Base,
    /// Options of a built-in base (key, value), paths resolved against the plan's folder.
    pub options: Vec<(String, AxisValue)>,
    /// Write each case's history CSVs into `DIR/cases/<id>/`.
    pub histories: bool,
    /// The axes, first = slowest in the case numbering.
    pub axes: Vec<Axis>,
    /// The plan as JSON (for the sidecar).
    pub json: Value,
}

fn refuse(file: &Path, place: &str, msg: impl std::fmt::Display) -> FemError {
    FemError::input(format!("{}: {place}", file.display()), msg.to_string())
}

/// `key` unknown among `valid`: the message with the nearest valid key.
fn unknown(file: &Path, place: &str, what: &str, key: &str, valid: &[&str]) -> FemError {
    let hint = nearest(key, valid)
        .map(|n| format!("did you mean `{n}`? "))
        .unwrap_or_default();
    refuse(
        file,
        place,
        format!(
            "unknown {what} `{key}`; {hint}use one of {}",
            valid.join(", ")
        ),
    )
}

fn toml_to_value(file: &Path, place: &str, v: &toml::Value) -> Result<AxisValue, FemError> {
    match v {
        toml::Value::Integer(i) => Ok(AxisValue::Num(*i as f64)),
        toml::Value::Float(f) if f.is_finite() => Ok(AxisValue::Num(*f)),
        toml::Value::String(s) => Ok(AxisValue::Text(s.clone())),
        other => Err(refuse(
            file,
            place,
            format!("`{other}` is not a finite number or a text; give one"),
        )),
    }
}

/// Reads and checks a plan file.
pub fn read(file: &Path) -> Result<Plan, FemError> {
    crate::framework::limits::check_file(file, "the plan")
        .map_err(|m| FemError::input(file.display().to_string(), m))?;
    let text = std::fs::read_to_string(file).map_err(|e| {
        FemError::input(
            file.display().to_string(),
            format!("cannot read the plan ({e}); give a TOML study plan (docs/study.md)"),
        )
    })?;
    let table: toml::Table = toml::from_str(&text).map_err(|e| {
        let msg = e.message().replace('\n', " ");
        let line = e
            .span()
            .map(|s| text[..s.start.min(text.len())].lines().count().max(1));
        FemError::input(
            match line {
                Some(l) => format!("{}:{l}", file.display()),
                None => file.display().to_string(),
            },
            format!("{msg}; give valid TOML (docs/study.md)"),
        )
    })?;
    parse(file, &table)
}

fn parse(file: &Path, table: &toml::Table) -> Result<Plan, FemError> {
    let folder = file.parent().unwrap_or(Path::new("")).to_path_buf();
    for k in table.keys() {
        if !TOP_KEYS.contains(&k.as_str()) {
            return Err(unknown(file, "top level", "key", k, &TOP_KEYS));
        }
    }
    let base = match (table.get("case"), table.get("base")) {
        (Some(_), Some(_)) => {
            return Err(refuse(
                file,
                "top level",
                "both `case` and `base` given; give one: a built-in case or a model file",
            ))
        }
        (None, None) => {
            return Err(refuse(
                file,
                "top level",
                "no base case; give `case = \"train-bridge\"` or `\"curve\"`, or `base = \"model.toml\"`",
            ))
        }
        (Some(toml::Value::String(c)), None) => {
            let origin = format!("{}: top level", file.display());
            match crate::choice::parse::<BuiltInCase>(&origin, "`case`", c)? {
                BuiltInCase::TrainBridge => Base::TrainBridge,
                BuiltInCase::Curve => Base::Curve,
            }
        }
        (None, Some(toml::Value::String(b))) => {
            let path = folder.join(b);
            if !path.is_file() {
                return Err(refuse(
                    file,
                    "`base`",
                    format!(
                        "model file {} does not exist; give a path relative to the plan's folder",
                        path.display()
                    ),
                ));
            }
            let value = model_value(&path).map_err(|e| refuse(file, "`base`", e))?;
            Base::Model { path, value }
        }
        _ => {
            return Err(refuse(
                file,
                "top level",
                "`case` and `base` take a text (a case name or a model file path)",
            ))
        }
    };
    let case_keys: &[&str] = match &base {
        Base::TrainBridge => &TRAIN_BRIDGE_KEYS,
        Base::Curve => &CURVE_KEYS,
        Base::Model { .. } => &[],
    };
    let mut options = Vec::new();
    if let Some(o) = table.get("options") {
        let toml::Value::Table(o) = o else {
            return Err(refuse(
                file,
                "`options`",
                "give a table `[options]` of case keys",
            ));
        };
        if matches!(base, Base::Model { .. }) {
            return Err(refuse(
                file,
                "`options`",
                "a model-file base takes no [options]; change the model file, or vary its keys with [[axis]] name = \"key.path\"",
            ));
        }
        for (k, v) in o {
            if !case_keys.contains(&k.as_str()) {
                return Err(unknown(
                    file,
                    "[options]",
                    &format!("key of the {} case", base.name()),
                    k,
                    case_keys,
                ));
            }
            let place = format!("[options] {k}");
            let value = match v {
                toml::Value::Array(a) => AxisValue::Text(
                    a.iter()
                        .map(|x| toml_to_value(file, &place, x).map(|v| v.label()))
                        .collect::<Result<Vec<_>, _>>()?
                        .join(","),
                ),
                v => toml_to_value(file, &place, v)?,
            };
            let value = match (k.as_str(), value) {
                ("quake", AxisValue::Text(t)) if t != "synthetic" => {
                    AxisValue::Record(folder.join(t))
                }
                (_, v) => v,
            };
            options.push((k.clone(), value));
        }
    }
    let histories = match table.get("histories") {
        None => false,
        Some(toml::Value::Boolean(b)) => *b,
        Some(_) => return Err(refuse(file, "`histories`", "give true or false")),
    };
    let mut axes: Vec<Axis> = Vec::new();
    let list = match table.get("axis") {
        None => &Vec::new(),
        Some(toml::Value::Array(a)) => a,
        Some(_) => {
            return Err(refuse(
                file,
                "`axis`",
                "give axes as [[axis]] tables (name = \"speed\", values = [...])",
            ))
        }
    };
    for (i, ax) in list.iter().enumerate() {
        let place = format!("[[axis]] {}", i + 1);
        let toml::Value::Table(ax) = ax else {
            return Err(refuse(
                file,
                &place,
                "give a table: [[axis]] name = \"speed\" ...",
            ));
        };
        for k in ax.keys() {
            if !AXIS_KEYS.contains(&k.as_str()) && k != "dir" {
                let mut valid = AXIS_KEYS.to_vec();
                valid.push("dir");
                return Err(unknown(file, &place, "axis key", k, &valid));
            }
        }
        let Some(toml::Value::String(name)) = ax.get("name") else {
            return Err(refuse(
                file,
                &place,
                "no `name`; give the key it varies, e.g. name = \"speed\"",
            ));
        };
        let place = format!("[[axis]] {} ({name})", i + 1);
        match &base {
            Base::Model { value, .. } => {
                key_path(value, name).map_err(|m| refuse(file, &place, m))?;
            }
            _ => {
                if !case_keys.contains(&name.as_str()) {
                    return Err(unknown(
                        file,
                        &place,
                        &format!("axis of the {} case", base.name()),
                        name,
                        case_keys,
                    ));
                }
            }
        }
        if axes.iter().any(|a| &a.name == name) {
            return Err(refuse(
                file,
                &place,
                format!("axis `{name}` given twice; merge its values into one axis"),
            ));
        }
        // The cases of the axes so far bound this one's length before its values exist.
        let so_far: usize = axes.iter().map(|a| a.values.len()).product();
        let values = axis_values(file, &place, &folder, ax, MAX_CASES / so_far.max(1))?;
        if values.is_empty() {
            return Err(refuse(
                file,
                &place,
                "the axis has no values; give at least one",
            ));
        }
        if name == "quake" {
            // Record paths given as text resolve against the plan's folder.
            let values = values
                .into_iter()
                .map(|v| match v {
                    AxisValue::Text(t) if t != "synthetic" => AxisValue::Record(folder.join(t)),
                    v => v,
                })
                .collect();
            axes.push(Axis {
                name: name.clone(),
                values,
            });
        } else {
            axes.push(Axis {
                name: name.clone(),
                values,
            });
        }
    }
    let count = axes
        .iter()
        .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
        .filter(|n| *n <= MAX_CASES);
    if count.is_none() {
        return Err(refuse(
            file,
            "[[axis]]",
            format!(
                "the axes make more than {MAX_CASES} cases; split the study into several plans"
            ),
        ));
    }
    let json = serde_json::to_value(table).unwrap_or(Value::Null);
    Ok(Plan {
        file: file.to_path_buf(),
        base,
        options,
        histories,
        axes,
        json,
    })
}

/// The values of one axis table: `values`, a range or `dir`.
fn axis_values(
    file: &Path,
    place: &str,
    folder: &Path,
    ax: &toml::Table,
    cap: usize,
) -> Result<Vec<AxisValue>, FemError> {
    let too_many = || {
        refuse(
            file,
            place,
            format!(
                "with the axes before it, this axis makes more than {MAX_CASES} cases; give fewer values (a larger `step`, a smaller `count`) or split the study into several plans"
            ),
        )
    };
    let has = |k: &str| ax.contains_key(k);
    let ways = [has("values"), has("start") || has("stop"), has("dir")];
    if ways.iter().filter(|w| **w).count() != 1 {
        return Err(refuse(
            file,
            place,
            "give exactly one of `values = [...]`, `start`/`stop` with `step` or `count`, or `dir = \"records\"`",
        ));
    }
    if let Some(v) = ax.get("values") {
        let toml::Value::Array(a) = v else {
            return Err(refuse(
                file,
                place,
                "`values`: give a list, e.g. values = [60, 80]",
            ));
        };
        return a.iter().map(|x| toml_to_value(file, place, x)).collect();
    }
    if let Some(d) = ax.get("dir") {
        let toml::Value::String(d) = d else {
            return Err(refuse(file, place, "`dir`: give a folder as text"));
        };
        let dir = folder.join(d);
        let entries = std::fs::read_dir(&dir).map_err(|e| {
            refuse(
                file,
                place,
                format!("cannot read the record folder {} ({e}); give a folder of CSV records relative to the plan", dir.display()),
            )
        })?;
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "csv"))
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(refuse(
                file,
                place,
                format!(
                    "the folder {} has no *.csv record; put ground-motion records there (examples/records/README.md)",
                    dir.display()
                ),
            ));
        }
        return Ok(files.into_iter().map(AxisValue::Record).collect());
    }
    let num = |k: &str| -> Result<Option<f64>, FemError> {
        match ax.get(k) {
            None => Ok(None),
            Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
            Some(toml::Value::Float(f)) if f.is_finite() => Ok(Some(*f)),
            Some(_) => Err(refuse(file, place, format!("`{k}`: give a finite number"))),
        }
    };
    let (Some(start), Some(stop)) = (num("start")?, num("stop")?) else {
        return Err(refuse(file, place, "a range needs both `start` and `stop`"));
    };
    let n = match (num("step")?, num("count")?) {
        (Some(step), None) => {
            if step <= 0.0 || stop < start {
                return Err(refuse(file, place, "give `step` > 0 and `stop` ≥ `start`"));
            }
            // Both ends included; a stop that the steps miss by rounding only is reached.
            let n = ((stop - start) / step * (1.0 + 1e-12)).floor() + 1.0;
            if n > MAX_CASES as f64 {
                return Err(refuse(
                    file,
                    place,
                    format!("the range has more than {MAX_CASES} values; give a larger `step`"),
                ));
            }
            if n > cap as f64 {
                return Err(too_many());
            }
            return Ok((0..n as usize)
                .map(|i| AxisValue::Num(start + i as f64 * step))
                .collect());
        }
        (None, Some(c)) if c >= 1.0 && c.fract() == 0.0 && c <= MAX_CASES as f64 => {
            if c > cap as f64 {
                return Err(too_many());
            }
            c as usize
        }
        (None, Some(_)) => {
            return Err(refuse(file, place, "`count`: give a whole number ≥ 1"));
        }
        _ => {
            return Err(refuse(
                file,
                place,
                "a range needs exactly one of `step` or `count`",
            ));
        }
    };
    Ok((0..n)
        .map(|i| {
            if n == 1 {
                AxisValue::Num(start)
            } else {
                AxisValue::Num(start + (stop - start) * i as f64 / (n - 1) as f64)
            }
        })
        .collect())
}

/// A model file's contents as JSON (TOML or JSON by extension), as `railfem run` reads it.
fn model_value(path: &Path) -> Result<Value, FemError> {
    use crate::framework::modelfile::{parse_json, parse_toml};
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| FemError::input(&name, format!("cannot read the model file: {e}")))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        parse_json(text, &name)
    } else {
        parse_toml(text, &name)
    }
}

/// The value a dotted key path (`analysis.dt`, `elements.3.E`) names in a model file, or
/// why it names none.
pub fn key_path<'a>(value: &'a Value, path: &str) -> Result<&'a Value, String> {
    let mut v = value;
    for (depth, part) in path.split('.').enumerate() {
        let here = path
            .split('.')
            .take(depth + 1)
            .collect::<Vec<_>>()
            .join(".");
        v = match v {
            Value::Object(o) => o.get(part).ok_or_else(|| {
                let keys: Vec<&str> = o.keys().map(String::as_str).collect();
                let hint = crate::framework::error::nearest(part, &keys)
                    .map(|n| format!("did you mean `{n}`? "))
                    .unwrap_or_default();
                format!(
                    "the base model has no key `{here}`; {hint}give a key path that the model file sets (e.g. analysis.dt)"
                )
            })?,
            Value::Array(a) => part.parse::<usize>().ok().and_then(|i| a.get(i)).ok_or_else(|| {
                format!("`{here}`: give an index 0..{} into that list", a.len())
            })?,
            _ => {
                return Err(format!(
                    "`{here}`: the model's value there is not a table or a list; give a key path to a value"
                ))
            }
        };
    }
    if v.is_object() || v.is_array() {
        return Err(format!(
            "`{path}` is a table or a list in the base model; give the path down to one value"
        ));
    }
    Ok(v)
}
