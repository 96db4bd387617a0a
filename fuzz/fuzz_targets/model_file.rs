//! Fuzz target: the model-file path of `railfem check` — TOML or JSON text (JSON when the
//! first non-blank byte is `{`), parsed, read into a builder (every section, the rail
//! toolkit's `[track]` and `[[vehicle]]` included), built into a model through the element
//! registry and handed to the driver's constructor (DOF numbering, sparsity, solver choice)
//! — no time stepping, so an input costs milliseconds.
//!
//! Asserts: no panic, and every refusal is one non-empty line (the CLI prints it as the
//! single line of stderr). Inputs that are valid but merely huge (a 100 km track meshed at
//! 1 mm, a thousand carriages) and inputs naming files on this machine (profiles, plugins)
//! are skipped by [`too_big_or_external`]: they test the disk and the memory, not the code.

#![no_main]

use libfuzzer_sys::fuzz_target;
use railfem::framework::modelfile;
use serde_json::Value;
use std::path::Path;

/// Largest rail mesh (stations per rail) and train the target builds.
const MAX_STATIONS: f64 = 20_000.0;
const MAX_CARRIAGES: f64 = 3.0;
/// Largest profile sampling and node count (each point costs a dense-table lookup).
const MAX_POINTS: f64 = 2_000.0;

fn num(v: Option<&Value>) -> Option<f64> {
    v.and_then(Value::as_f64)
}

/// Whether `v` asks for more work than a fuzz input should (see the module doc) or names
/// a file: plugin paths are loaded as shared libraries and profile paths are read.
fn too_big_or_external(v: &Value) -> bool {
    fn walk(v: &Value) -> bool {
        match v {
            Value::String(s) => s.contains('/') || s.contains('\\') || s.ends_with(".csv"),
            Value::Array(a) => a.iter().any(walk),
            Value::Object(m) => {
                for key in ["wheel_points", "rail_nodes", "carriages"] {
                    if let Some(x) = num(m.get(key)) {
                        let limit = if key == "carriages" {
                            MAX_CARRIAGES
                        } else {
                            MAX_POINTS
                        };
                        if x > limit {
                            return true;
                        }
                    }
                }
                m.values().any(walk)
            }
            _ => false,
        }
    }
    let Value::Object(root) = v else { return false };
    if root.contains_key("plugins") {
        return true;
    }
    if let Some(Value::Object(t)) = root.get("track") {
        let length: f64 = match t.get("segments") {
            Some(Value::Array(segs)) => segs
                .iter()
                .map(|s| num(s.get("length")).unwrap_or(0.0).abs())
                .sum(),
            _ => 0.0,
        };
        let h = num(t.get("element_length")).unwrap_or(0.6).abs();
        let window = match t.get("window") {
            Some(Value::Array(w)) if w.len() == 2 => num(w.get(1))
                .unwrap_or(0.0)
                .abs()
                .max(num(w.first()).unwrap_or(0.0).abs()),
            _ => 0.0,
        };
        let span = if window > 0.0 {
            length.min(2.0 * window)
        } else {
            length
        };
        if !(span / h.max(1e-300) <= MAX_STATIONS) {
            return true;
        }
    }
    walk(v)
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let is_json = text.trim_start().starts_with('{');
    let (name, parsed) = if is_json {
        ("fuzz.json", modelfile::parse_json(text, "fuzz.json"))
    } else {
        ("fuzz.toml", modelfile::parse_toml(text, "fuzz.toml"))
    };
    let result = parsed.and_then(|value| {
        if too_big_or_external(&value) {
            return Ok(());
        }
        let model = modelfile::from_value(&value, name, Path::new("/nonexistent"))?.build()?;
        railfem::solvers::Driver::new(model).map(|_| ())
    });
    if let Err(e) = result {
        let line = e.to_string();
        assert!(!line.trim().is_empty(), "empty error message");
        assert!(!line.contains('\n'), "multi-line error: {line:?}");
    }
});
