//! Hostile model files generated from good ones: the mutations of the property test
//! `tests/mutations.rs` and of the fuzz target `fuzz/fuzz_targets/mutations.rs` (which
//! includes this file), driven by a seeded generator so that every case can be replayed.
//!
//! A case starts from a shipped example model, read as a TOML value, and applies one to
//! three mutations: a number replaced by an extreme (0, −1, ±1e-300, 1e300, NaN, ±inf, the
//! largest integer, 2⁵³ + 1), a key deleted, a whole table deleted, an array entry deleted
//! or duplicated, a value replaced by one of another type. The result is written as TOML or
//! as JSON; in JSON a key may also be written twice in one object (TOML's writer cannot say
//! that). Non-finite numbers have no JSON spelling and are written as `1e999` (which a JSON
//! reader turns into infinity or refuses).

#![allow(dead_code)]

use toml::Value;

/// A small, fast, seedable generator (SplitMix64): no dependency, same stream everywhere.
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// The extreme values a number is replaced with.
pub fn extreme(rng: &mut Rng) -> Value {
    match rng.below(11) {
        0 => Value::Float(0.0),
        1 => Value::Float(-1.0),
        2 => Value::Float(1e-300),
        3 => Value::Float(-1e-300),
        4 => Value::Float(1e300),
        5 => Value::Float(f64::NAN),
        6 => Value::Float(f64::INFINITY),
        7 => Value::Float(f64::NEG_INFINITY),
        8 => Value::Integer(i64::MAX),
        9 => Value::Integer((1 << 53) + 1),
        _ => Value::Integer(0),
    }
}

/// Paths (keys and indices) of every value in `v`, depth first.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A key of a table.
    Key(String),
    /// An index of an array.
    Index(usize),
}

fn paths(v: &Value, at: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(at.clone());
    match v {
        Value::Table(t) => {
            for (k, x) in t {
                at.push(Step::Key(k.clone()));
                paths(x, at, out);
                at.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                at.push(Step::Index(i));
                paths(x, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    let mut cur = v;
    for s in path {
        cur = match (cur, s) {
            (Value::Table(t), Step::Key(k)) => t.get_mut(k)?,
            (Value::Array(a), Step::Index(i)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

/// One mutation of `v`; returns what it did (for the failure message) and, for the JSON
/// writer, a key to write twice (`path of the table`, `key`).
pub fn mutate(v: &mut Value, rng: &mut Rng) -> (String, Option<(Vec<Step>, String)>) {
    let mut all = Vec::new();
    paths(v, &mut Vec::new(), &mut all);
    let numbers: Vec<&Vec<Step>> = all
        .iter()
        .filter(|p| {
            let mut probe = v.clone();
            matches!(
                get_mut(&mut probe, p),
                Some(Value::Integer(_) | Value::Float(_))
            )
        })
        .collect();
    let kind = rng.below(10);
    // Numbers are the richest target: half of all mutations.
    if kind < 5 && !numbers.is_empty() {
        let p = numbers[rng.below(numbers.len())].clone();
        let x = extreme(rng);
        let what = format!("{p:?} = {x}");
        if let Some(slot) = get_mut(v, &p) {
            *slot = x;
        }
        return (what, None);
    }
    let p = all[rng.below(all.len())].clone();
    let Some((last, parent)) = p.split_last() else {
        return ("nothing".into(), None);
    };
    let parent = parent.to_vec();
    let Some(container) = get_mut(v, &parent) else {
        return ("nothing".into(), None);
    };
    match (container, last, kind) {
        (Value::Table(t), Step::Key(k), 5 | 6) => {
            t.remove(k);
            (format!("deleted {p:?}"), None)
        }
        (Value::Table(_), Step::Key(k), 7) => {
            (format!("key {p:?} twice"), Some((parent, k.clone())))
        }
        (Value::Array(a), Step::Index(i), 5 | 6) => {
            a.remove(*i);
            (format!("deleted entry {p:?}"), None)
        }
        (Value::Array(a), Step::Index(i), 7) => {
            let x = a[*i].clone();
            a.insert(*i, x);
            (format!("duplicated entry {p:?}"), None)
        }
        (c, _, _) => {
            // A value of another type in its place.
            let replacement = match rng.below(4) {
                0 => Value::String("x".into()),
                1 => Value::Array(Vec::new()),
                2 => Value::Table(Default::default()),
                _ => Value::Boolean(true),
            };
            if let Some(slot) = match (c, last) {
                (Value::Table(t), Step::Key(k)) => t.get_mut(k),
                (Value::Array(a), Step::Index(i)) => a.get_mut(*i),
                _ => None,
            } {
                *slot = replacement.clone();
            }
            (format!("{p:?} = {replacement}"), None)
        }
    }
}

fn json_number(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else if x > 0.0 {
        "1e999".into()
    } else {
        "-1e999".into()
    }
}

/// `v` as JSON text, with `twice` (a table path and one of its keys) written twice.
pub fn to_json(v: &Value, twice: Option<&(Vec<Step>, String)>) -> String {
    fn w(v: &Value, at: &mut Vec<Step>, twice: Option<&(Vec<Step>, String)>, out: &mut String) {
        match v {
            Value::String(s) => out.push_str(&serde_json::to_string(s).unwrap_or_default()),
            Value::Integer(i) => out.push_str(&i.to_string()),
            Value::Float(f) => out.push_str(&json_number(*f)),
            Value::Boolean(b) => out.push_str(if *b { "true" } else { "false" }),
            Value::Datetime(d) => out.push_str(&format!("\"{d}\"")),
            Value::Array(a) => {
                out.push('[');
                for (i, x) in a.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    at.push(Step::Index(i));
                    w(x, at, twice, out);
                    at.pop();
                }
                out.push(']');
            }
            Value::Table(t) => {
                out.push('{');
                let mut first = true;
                for (k, x) in t {
                    let n = match twice {
                        Some((p, key)) if p == at && key == k => 2,
                        _ => 1,
                    };
                    for _ in 0..n {
                        if !first {
                            out.push_str(", ");
                        }
                        first = false;
                        out.push_str(&serde_json::to_string(k).unwrap_or_default());
                        out.push_str(": ");
                        at.push(Step::Key(k.clone()));
                        w(x, at, twice, out);
                        at.pop();
                    }
                }
                out.push('}');
            }
        }
    }
    let mut out = String::new();
    w(v, &mut Vec::new(), twice, &mut out);
    out
}

/// A hostile case: the model text and its extension (`"toml"` or `"json"`), and what was
/// done to it.
pub struct Case {
    /// File text.
    pub text: String,
    /// `"toml"` or `"json"`.
    pub ext: &'static str,
    /// The mutations, for the failure message.
    pub what: Vec<String>,
}

/// One to three mutations of `base` (a parsed example model), written as TOML or JSON.
pub fn case(base: &Value, rng: &mut Rng) -> Case {
    let mut v = base.clone();
    let mut what = Vec::new();
    let mut twice = None;
    for _ in 0..1 + rng.below(3) {
        let (w, t) = mutate(&mut v, rng);
        what.push(w);
        if t.is_some() {
            twice = t;
        }
    }
    if twice.is_some() || rng.below(3) == 0 {
        Case {
            text: to_json(&v, twice.as_ref()),
            ext: "json",
            what,
        }
    } else {
        Case {
            text: toml::to_string(&v).unwrap_or_else(|_| to_json(&v, None)),
            ext: if toml::to_string(&v).is_ok() {
                "toml"
            } else {
                "json"
            },
            what,
        }
    }
}

/// Caps the work a mutated model asks for, so that a case runs in seconds: at most
/// `steps` time or load steps and 10 modes. Other sizes (meshes, trains) are left
/// alone: the size guards must refuse them.
pub fn cap_work(v: &mut Value, steps: i64) {
    let Some(Value::Table(a)) = v.get_mut("analysis") else {
        return;
    };
    let num = |x: Option<&Value>| match x {
        Some(Value::Float(f)) => Some(*f),
        Some(Value::Integer(i)) => Some(*i as f64),
        _ => None,
    };
    let dt = num(a.get("dt")).unwrap_or(0.01);
    let duration = num(a.get("duration")).unwrap_or(1.0);
    if dt.is_finite() && dt > 0.0 && duration.is_finite() && duration / dt > steps as f64 {
        a.insert("duration".into(), Value::Float(dt * steps as f64));
    }
    for (key, most) in [("steps", steps), ("modes", 10)] {
        if let Some(Value::Integer(s)) = a.get(key) {
            if *s > most {
                a.insert(key.into(), Value::Integer(most));
            }
        }
    }
}

/// A mutated model whose track mesh has more than a million stations, whose alignment is
/// longer than 1000 km or bends tighter than a 1 m radius (its sampling grows with both),
/// or whose train has
/// more than 100 carriages: a build without the generators' size guard cannot refuse
/// these in seconds, so its callers skip them then.
pub fn too_big(v: &Value) -> bool {
    let num = |x: Option<&Value>| match x {
        Some(Value::Float(f)) => Some(*f),
        Some(Value::Integer(i)) => Some(*i as f64),
        _ => None,
    };
    if let Some(t) = v.get("track") {
        let length: f64 = match t.get("segments") {
            Some(Value::Array(a)) => a
                .iter()
                .map(|s| num(s.get("length")).unwrap_or(0.0).abs())
                .sum(),
            _ => 0.0,
        };
        let tight = match t.get("segments") {
            Some(Value::Array(a)) => a.iter().any(|s| {
                num(s.get("radius")).is_some_and(|r| r.abs() < 1.0)
                    || ["from_curvature", "to_curvature"]
                        .iter()
                        .any(|k| num(s.get(*k)).is_some_and(|c| c.is_nan() || c.abs() > 1.0))
            }),
            _ => false,
        };
        if tight {
            return true;
        }
        let h = num(t.get("element_length")).unwrap_or(0.6).abs();
        // NaN (a NaN length) counts as too big.
        if (length / h).is_nan() || length / h > 1e6 || length > 1e6 {
            return true;
        }
    }
    match v.get("vehicle") {
        Some(Value::Array(a)) => a
            .iter()
            .any(|x| num(x.get("carriages")).is_some_and(|c| c > 100.0)),
        _ => false,
    }
}

/// What a field of a CSV input is replaced with: extremes, non-numbers, nothing.
const CSV_FIELDS: [&str; 10] = [
    "1e300",
    "-1e300",
    "NaN",
    "inf",
    "-1",
    "0",
    "1e-300",
    "",
    "x",
    "18446744073709551616",
];

/// One to three line-level mutations of a CSV input (an irregularity table, a study
/// checkpoint): a field replaced by an extreme or a non-number, a field dropped or added,
/// a line deleted, duplicated or swapped with the next, a comment line inserted, a
/// byte-order mark put first, a unit of the header changed, the text cut mid-line.
/// Returns the text and what was done.
pub fn mutate_csv(text: &str, rng: &mut Rng) -> (String, Vec<String>) {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut what = Vec::new();
    let mut bom = false;
    let mut cut = None;
    for _ in 0..1 + rng.below(3) {
        if lines.is_empty() {
            lines.push(String::new());
        }
        let i = rng.below(lines.len());
        match rng.below(10) {
            0..=2 => {
                let mut f: Vec<String> = lines[i].split(',').map(str::to_string).collect();
                let j = rng.below(f.len());
                let x = CSV_FIELDS[rng.below(CSV_FIELDS.len())];
                what.push(format!("line {} field {j} = {x:?}", i + 1));
                f[j] = x.to_string();
                lines[i] = f.join(",");
            }
            3 => {
                what.push(format!("deleted line {}", i + 1));
                lines.remove(i);
            }
            4 => {
                what.push(format!("duplicated line {}", i + 1));
                let l = lines[i].clone();
                lines.insert(i, l);
            }
            5 => {
                let mut f: Vec<&str> = lines[i].split(',').collect();
                if rng.below(2) == 0 && f.len() > 1 {
                    f.pop();
                    what.push(format!("line {} lost a field", i + 1));
                } else {
                    f.push("1");
                    what.push(format!("line {} gained a field", i + 1));
                }
                lines[i] = f.join(",");
            }
            6 => {
                what.push(format!("comment before line {}", i + 1));
                lines.insert(i, "# a comment".into());
            }
            7 => {
                what.push("byte-order mark".into());
                bom = true;
            }
            8 => {
                let units = [("_mm", "_m"), ("_m", "_mm"), ("[mm]", "[in]"), ("_mm", "")];
                let (a, b) = units[rng.below(units.len())];
                what.push(format!("header unit {a:?} -> {b:?}"));
                if let Some(h) = lines.iter_mut().find(|l| !l.starts_with('#')) {
                    *h = h.replacen(a, b, 1);
                }
            }
            _ => {
                if i + 1 < lines.len() {
                    what.push(format!("swapped lines {} and {}", i + 1, i + 2));
                    lines.swap(i, i + 1);
                } else {
                    cut = Some(rng.below(lines[i].len() + 1));
                    what.push(format!("cut line {} at byte {cut:?}", i + 1));
                }
            }
        }
    }
    let mut out = if bom {
        "\u{feff}".to_string()
    } else {
        String::new()
    };
    out.push_str(&lines.join("\n"));
    match cut {
        Some(c) => {
            // Cut the last line short (on a character boundary), without a line end.
            let last = out.rfind('\n').map_or(0, |p| p + 1);
            let mut at = (last + c).min(out.len());
            while !out.is_char_boundary(at) {
                at -= 1;
            }
            out.truncate(at);
        }
        None => out.push('\n'),
    }
    (out, what)
}

/// One to three mutations of a TOML input that only TOML may spell (a vehicle file, a
/// study plan): [`mutate`], written back as TOML (as JSON if TOML cannot write it, which
/// the reader must refuse).
pub fn toml_case(base: &Value, rng: &mut Rng) -> Case {
    let mut v = base.clone();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(3) {
        what.push(mutate(&mut v, rng).0);
    }
    Case {
        text: toml::to_string(&v).unwrap_or_else(|_| to_json(&v, None)),
        ext: "toml",
        what,
    }
}
