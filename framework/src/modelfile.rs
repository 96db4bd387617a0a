//! Model files: TOML or JSON (the same structure), read into a [`ModelBuilder`].
//!
//! Top-level keys: `[analysis]`, `[[node]]`, `[[element]]`, `[[link]]`, `[[load]]`,
//! `[[recorder]]`, `plugins`, `[limits]` (the size guards' budgets, [`crate::limits`]),
//! and any section registered by a [`ModelSection`] (the rail
//! toolkit adds `[track]` and `[[vehicle]]`). Every key is documented in
//! `docs/model-format.md`. Errors are one line naming the file, the place (line and column
//! for syntax errors, the table and index otherwise) and the fix.

use crate::builder::ModelBuilder;
use crate::dof::DofSet;
use crate::error::{nearest, FemError};
use crate::limits::{fmt_num, fmt_vec, LimitSpec};
use crate::loads::LoadSpec;
use crate::model::AnalysisSpec;
use crate::recorder::RecorderSpec;
use crate::registry::ElementSpec;
use serde::Deserialize;
use serde_json::{Map, Value};
use std::collections::HashMap;
use std::path::Path;

/// A top-level model-file section handled outside the framework (e.g. `[track]`).
pub struct ModelSection {
    /// The key (`"track"`).
    pub key: &'static str,
    /// One-line description for the documentation.
    pub description: &'static str,
    /// Order in which sections are applied (lower first; nodes and elements are at 0).
    pub order: i32,
    /// Applies the section's value to the builder. `origin` is `"file.toml: [key]"`.
    pub apply: fn(&Value, &str, &mut ModelBuilder) -> Result<(), FemError>,
    /// What the section will build, estimated from its value alone (`base`: the model
    /// file's folder, for the files it names) before any section is applied: the part of
    /// the whole model's size guard ([`check_model_size`]). `None`: nothing in it grows
    /// with its input. A value the section will refuse estimates as nothing.
    pub estimate: Option<fn(&Value, &Path) -> Vec<SizePart>>,
}

/// One part of a model's size estimate: what grows (`"[track]: 5e4 rail stations"`)
/// and the bytes it will take.
#[derive(Debug, Clone, PartialEq)]
pub struct SizePart {
    /// The input and what it implies, for the message.
    pub what: String,
    /// Estimated bytes.
    pub bytes: f64,
}

/// The whole model's size guard, checked once before any section is applied: the sum of
/// every section's [`ModelSection::estimate`] against the memory budget. Each section also
/// checks its own part when it builds it, with a message naming its key; so a part that
/// alone exceeds the budget is left to that message, and this check refuses the models
/// whose parts fit one by one but not together (a long slab track and a long train).
pub fn check_model_size(parts: &[SizePart]) -> Result<(), String> {
    let limit = crate::limits::max_memory() as f64;
    if parts.iter().any(|p| p.bytes.is_nan() || p.bytes > limit) {
        return Ok(());
    }
    let total: f64 = parts.iter().map(|p| p.bytes).sum();
    if total <= limit {
        return Ok(());
    }
    let list: Vec<String> = parts
        .iter()
        .map(|p| format!("{}: {}", p.what, crate::limits::fmt_bytes(p.bytes)))
        .collect();
    Err(format!(
        "the model as written needs about {} ({}), more than the memory limit {}; make one of them smaller, or raise the limit with `[limits] max_memory` or `--max-memory`",
        crate::limits::fmt_bytes(total),
        list.join("; "),
        crate::limits::fmt_bytes(limit)
    ))
}

inventory::collect!(ModelSection);

const CORE_KEYS: [&str; 8] = [
    "analysis", "node", "element", "link", "load", "recorder", "plugins", "limits",
];

/// Largest node coordinate magnitude a model file may give (m). Beyond it, lengths cubed
/// (beam stiffness ∝ 1/L³) leave the range of a double and nothing physical remains to
/// model: 1e8 m is eight times the Earth's diameter.
pub const MAX_COORDINATE: f64 = 1e8;

/// Reads a model file (`.toml` or `.json`, by extension) into a builder. Plugins named in
/// the file are loaded (see [`crate::plugin`]) before elements are built.
pub fn read(path: &Path) -> Result<ModelBuilder, FemError> {
    let name = path.display().to_string();
    crate::limits::check_file(path, "the model file").map_err(|m| FemError::input(&name, m))?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| FemError::input(&name, format!("cannot read the model file: {e}")))?;
    // A byte-order mark is not part of the text (TOML's parser skips one; JSON's does not).
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let is_json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let value = if is_json {
        parse_json(text, &name)?
    } else {
        parse_toml(text, &name)?
    };
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    from_value(&value, &name, &base)
}

/// Parses TOML text into a JSON value, refusing NaN and infinity with their key path.
pub fn parse_toml(text: &str, name: &str) -> Result<Value, FemError> {
    let t: toml::Table = toml::from_str(text).map_err(|e| {
        let (line, col) = e.span().map(|s| line_col(text, s.start)).unwrap_or((0, 0));
        FemError::input(
            format!("{name}:{line}:{col}"),
            format!(
                "TOML syntax error: {}",
                e.message().trim().replace('\n', " ")
            ),
        )
    })?;
    let tv = toml::Value::Table(t);
    if let Some(p) = non_finite_toml(&tv, "") {
        return Err(FemError::input(
            name,
            format!("`{p}` is not a finite number; give a finite value in SI units"),
        ));
    }
    serde_json::to_value(&tv).map_err(|e| FemError::input(name, format!("unsupported value: {e}")))
}

/// Parses JSON text, reporting line and column of syntax errors. A key given twice in one
/// object is refused ([`crate::strict_json`]): serde_json would keep the last silently,
/// where TOML refuses it.
pub fn parse_json(text: &str, name: &str) -> Result<Value, FemError> {
    crate::strict_json::from_str(text).map_err(|e| {
        FemError::input(
            format!("{name}:{}:{}", e.line(), e.column()),
            format!("JSON syntax error: {e}"),
        )
    })
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

fn non_finite_toml(v: &toml::Value, path: &str) -> Option<String> {
    match v {
        toml::Value::Float(f) if !f.is_finite() => Some(path.to_string()),
        toml::Value::Table(t) => t.iter().find_map(|(k, x)| {
            non_finite_toml(
                x,
                &if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                },
            )
        }),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, x)| non_finite_toml(x, &format!("{path}[{i}]"))),
        _ => None,
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NodeEntry {
    id: u64,
    xyz: [f64; 3],
    /// A [`DofSet`], read apart from the rest of the table ([`node_fix`]).
    #[serde(default)]
    fix: Option<Value>,
}

/// The node's `fix` (none if absent): read on its own, so that a word outside the DOF
/// names is one problem among the file's others and the node still exists for the
/// elements, loads and recorders that name it.
fn node_fix(fix: &Option<Value>, origin: &str, i: usize) -> Result<DofSet, FemError> {
    match fix {
        None => Ok(DofSet::NONE),
        Some(v) => de(v, origin, &format!("node[{i}].fix")),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LinkEntry {
    master: u64,
    slave: u64,
    #[serde(default)]
    dofs: Option<DofSet>,
    #[serde(default)]
    geometry: Option<crate::model::Geometry>,
}

fn entries<'a>(
    root: &'a Map<String, Value>,
    key: &str,
    name: &str,
) -> Result<Vec<&'a Value>, FemError> {
    match root.get(key) {
        None => Ok(Vec::new()),
        Some(Value::Array(a)) => Ok(a.iter().collect()),
        Some(v @ Value::Object(_)) => Ok(vec![v]),
        Some(_) => Err(FemError::input(
            name,
            format!("`{key}` must be an array of tables (`[[{key}]]`)"),
        )),
    }
}

/// The `[[load]]` entry `v` (number `i` of file `name`): a built-in kind through its typed
/// spec, a plugin's kind as its keys for the kind's factory ([`crate::load_kind`]); a
/// `type` no kind is registered under lists the registered ones.
fn load_spec(v: &Value, name: &str, i: usize) -> Result<LoadSpec, FemError> {
    use crate::load_kind::{LoadBuild, LoadEntry};
    let origin = format!("{name}: load[{i}]");
    if let Some(kind) = v.get("type").and_then(Value::as_str) {
        match crate::load_kind::find(kind).map(|k| k.build) {
            None => return Err(crate::load_kind::unknown(kind, &origin)),
            Some(LoadBuild::Factory(_)) => {
                let mut params = v.as_object().cloned().unwrap_or_default();
                params.remove("type");
                return Ok(LoadSpec::Registered(LoadEntry {
                    kind: kind.to_string(),
                    params,
                }));
            }
            Some(LoadBuild::BuiltIn) => {}
        }
    }
    de::<LoadSpec>(v, &origin, &format!("load[{i}]"))
}

/// The `[[recorder]]` entry `v` (number `i` of file `name`): a built-in kind through its
/// typed spec, a plugin's kind as its `file` and keys for the kind's factory
/// ([`crate::recorder_kind`]); a `type` no kind is registered under lists the registered
/// ones.
fn recorder_spec(v: &Value, name: &str, i: usize) -> Result<RecorderSpec, FemError> {
    use crate::recorder_kind::{RecorderBuild, RecorderEntry};
    let origin = format!("{name}: recorder[{i}]");
    if let Some(kind) = v.get("type").and_then(Value::as_str) {
        match crate::recorder_kind::find(kind).map(|k| k.build) {
            None => return Err(crate::recorder_kind::unknown(kind, &origin)),
            Some(RecorderBuild::Factory(_)) => {
                let mut params = v.as_object().cloned().unwrap_or_default();
                params.remove("type");
                let Some(Value::String(file)) = params.remove("file") else {
                    return Err(FemError::input(
                        &origin,
                        format!("recorder type `{kind}` needs `file` = \"NAME.csv\" (a string: the output file, relative to the output directory)"),
                    ));
                };
                return Ok(RecorderSpec::Registered(RecorderEntry {
                    kind: kind.to_string(),
                    file,
                    params,
                    at: format!("recorder[{i}]"),
                }));
            }
            Some(RecorderBuild::BuiltIn) => {}
        }
    }
    de::<RecorderSpec>(v, &origin, &format!("recorder[{i}]"))
}

/// `v`, the value at key path `at`, into `T`; a refusal names the key path
/// ([`crate::keypath::from_value`]).
fn de<T: serde::de::DeserializeOwned>(v: &Value, origin: &str, at: &str) -> Result<T, FemError> {
    crate::keypath::from_value(v, origin, at)
}

/// `[analysis] block_size` must be a whole number: serde alone would say "invalid value:
/// integer `-1`, expected usize" without naming the key. Zero is a whole number and is
/// refused with the other analysis values (`AnalysisSpec::validate`).
fn check_block_size(analysis: &Value, origin: &str) -> Result<(), FemError> {
    match analysis.get("block_size") {
        Some(v) if v.as_u64().is_none() => Err(FemError::input(
            origin,
            format!(
                "`block_size` = {v}: give a positive integer (interior equations per block of the partitioned solver; leave it out for 3000)"
            ),
        )),
        _ => Ok(()),
    }
}

/// Builds from an already-parsed value (`base` resolves relative file paths, e.g. plugins).
pub fn from_value(value: &Value, name: &str, base: &Path) -> Result<ModelBuilder, FemError> {
    let Value::Object(root) = value else {
        return Err(FemError::input(
            name,
            "the model file must be a table of sections",
        ));
    };
    let sections: Vec<&ModelSection> = inventory::iter::<ModelSection>.into_iter().collect();
    let mut valid: Vec<&str> = CORE_KEYS.to_vec();
    valid.extend(sections.iter().map(|s| s.key));
    let unknown: Vec<FemError> = root
        .keys()
        .filter(|k| !valid.contains(&k.as_str()))
        .map(|k| {
            let hint = nearest(k, &valid)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            FemError::input(
                name,
                format!(
                    "unknown top-level key `{k}`{hint}; valid keys: {}",
                    valid.join(", ")
                ),
            )
        })
        .collect();
    FemError::from_list(unknown)?;
    crate::limits::set_model_file(match root.get("limits") {
        Some(v) => parse_limits(v, &format!("{name}: [limits]"))?,
        None => LimitSpec::default(),
    });
    let parts: Vec<SizePart> = sections
        .iter()
        .filter_map(|s| Some((s.estimate?)(root.get(s.key)?, base)))
        .flatten()
        .collect();
    check_model_size(&parts).map_err(|m| FemError::input(name, m))?;
    let mut b = ModelBuilder::new(name);
    if let Some(p) = root.get("plugins") {
        let list: Vec<String> = de(p, &format!("{name}: plugins"), "plugins")?;
        for rel in list {
            let path = base.join(&rel);
            // The plugin's own error names the library; the model file and key say where
            // it was asked for.
            crate::plugin::load(&path)
                .map_err(|e| FemError::input(format!("{name}: plugins"), e.to_string()))?;
            b.plugin(&path.display().to_string());
        }
    }
    if let Some(a) = root.get("analysis") {
        let o = format!("{name}: [analysis]");
        match check_block_size(a, &o).and_then(|()| de::<AnalysisSpec>(a, &o, "analysis")) {
            Ok(spec) => {
                for e in ignored_analysis_keys(a, &spec, &o) {
                    b.error(e);
                }
                b.analysis(spec);
            }
            Err(e) => {
                b.error(e);
            }
        }
    }
    let mut node_ids: HashMap<u64, usize> = HashMap::new();
    for (i, v) in entries(root, "node", name)?.into_iter().enumerate() {
        let o = format!("{name}: node[{i}]");
        let n: NodeEntry = match de(v, &o, &format!("node[{i}]")) {
            Ok(n) => n,
            Err(e) => {
                b.error(e);
                continue;
            }
        };
        // Reported here, where the table index is known (the builder only knows the id).
        if let Some(j) = node_ids.insert(n.id, i) {
            b.error(FemError::input(
                o,
                format!(
                    "duplicate node id {} (also node[{j}]); give every node its own id",
                    n.id
                ),
            ));
            continue;
        }
        match n.xyz.iter().map(|x| x.abs()).reduce(f64::max) {
            Some(far) if far > MAX_COORDINATE => {
                b.error(FemError::input(
                    &o,
                    format!(
                        "`xyz` = {} lies {} m from the origin; give coordinates within {} m (the Earth's diameter is 1.3e7 m) — check the units (m)",
                        fmt_vec(&n.xyz),
                        fmt_num(far),
                        fmt_num(MAX_COORDINATE)
                    ),
                ));
            }
            _ => {
                let fixed = node_fix(&n.fix, &o, i).unwrap_or_else(|e| {
                    b.error(e);
                    DofSet::NONE
                });
                b.node_fixed(n.id, n.xyz, fixed);
            }
        }
    }
    let mut ordered: Vec<&&ModelSection> = sections.iter().collect();
    ordered.sort_by_key(|s| s.order);
    // A section that fails stops the reading (what comes after it may depend on it); the
    // problems found so far are reported with it.
    for s in ordered.iter().filter(|s| s.order < 0) {
        if let Some(v) = root.get(s.key) {
            if let Err(e) = (s.apply)(v, &format!("{name}: [{}]", s.key), &mut b) {
                b.error(e);
                return Ok(b);
            }
        }
    }
    for (i, v) in entries(root, "element", name)?.into_iter().enumerate() {
        if let Err(e) = element_entry(v, i, name, &mut b) {
            b.error(e);
        }
    }
    for (i, v) in entries(root, "link", name)?.into_iter().enumerate() {
        let o = format!("{name}: link[{i}]");
        match de::<LinkEntry>(v, &o, &format!("link[{i}]")) {
            Ok(l) => {
                let dofs = l.dofs.unwrap_or(DofSet::ALL);
                b.rigid_link_with(l.master, l.slave, dofs, l.geometry, o)
            }
            Err(e) => b.error(e),
        };
    }
    for s in ordered.iter().filter(|s| s.order >= 0) {
        if let Some(v) = root.get(s.key) {
            if let Err(e) = (s.apply)(v, &format!("{name}: [{}]", s.key), &mut b) {
                b.error(e);
                return Ok(b);
            }
        }
    }
    for (i, v) in entries(root, "load", name)?.into_iter().enumerate() {
        match load_spec(v, name, i) {
            Ok(l) => b.load(l),
            Err(e) => b.error(e),
        };
    }
    for (i, v) in entries(root, "recorder", name)?.into_iter().enumerate() {
        match recorder_spec(v, name, i) {
            Ok(r) => b.recorder(r),
            Err(e) => b.error(e),
        };
    }
    Ok(b)
}

/// Keys of `[analysis]` that the chosen `kind` or `integrator` does not read (the
/// documentation says which): given anyway, they would be ignored without a word.
fn ignored_analysis_keys(raw: &Value, spec: &AnalysisSpec, o: &str) -> Vec<FemError> {
    use crate::model::{AnalysisKind as K, IntegratorKind as I};
    let Value::Object(map) = raw else {
        return Vec::new();
    };
    let transient = spec.kind == K::Transient;
    let mut out = Vec::new();
    for key in map.keys() {
        let reason = match key.as_str() {
            "dt" | "duration" | "integrator" | "initial_static" | "record_every"
                if !transient =>
            {
                Some("only a transient analysis reads it".to_string())
            }
            "beta" | "gamma" if !transient || spec.integrator != I::Newmark => Some(
                "only the Newmark integrator reads it (`hht` and `generalized_alpha` set β and γ from `alpha` / `rho_inf`)"
                    .to_string(),
            ),
            "alpha" if !transient || spec.integrator != I::Hht => {
                Some("only `integrator = \"hht\"` reads it".to_string())
            }
            "rho_inf" if !transient || spec.integrator != I::GeneralizedAlpha => {
                Some("only `integrator = \"generalized_alpha\"` reads it".to_string())
            }
            "steps" if spec.kind != K::Static => {
                Some("only a static analysis reads it".to_string())
            }
            "modes" if spec.kind != K::Modal => Some("only a modal analysis reads it".to_string()),
            "block_size"
                if matches!(
                    spec.solver,
                    crate::model::SolverChoice::Direct | crate::model::SolverChoice::LowRank
                ) =>
            {
                Some(format!(
                    "only the partitioned solver reads it, and `solver` = \"{}\"",
                    spec.solver.name()
                ))
            }
            _ => None,
        };
        if let Some(r) = reason {
            out.push(FemError::input(
                o,
                format!("`{key}` would be ignored: {r}; remove it or change `kind`/`integrator`"),
            ));
        }
    }
    out
}

/// One `[[element]]` table into the builder.
fn element_entry(v: &Value, i: usize, name: &str, b: &mut ModelBuilder) -> Result<(), FemError> {
    let mut o = format!("{name}: element[{i}]");
    let Value::Object(map) = v else {
        return Err(FemError::input(o, "must be a table"));
    };
    let mut params = map.clone();
    let kind = match params.remove("type") {
        Some(Value::String(s)) => s,
        _ => {
            return Err(FemError::input(
                o,
                "missing `type` (the registered element name; `railfem elements` lists them)",
            ))
        }
    };
    let id = match params.remove("id") {
        Some(Value::Number(n)) if n.as_u64().is_some() => n.as_u64().unwrap_or(0),
        _ => {
            return Err(FemError::input(
                o,
                "missing or invalid `id` (a non-negative integer)",
            ))
        }
    };
    o = format!("{name}: element[{i}] (id {id}, {kind})");
    let nodes: Vec<u64> = match params.remove("nodes") {
        Some(v) => de(&v, &o, &format!("element[{i}].nodes"))?,
        None => return Err(FemError::input(o, "missing `nodes` (a list of node ids)")),
    };
    b.element_spec(ElementSpec {
        id,
        kind,
        nodes,
        params,
        origin: o,
    });
    Ok(())
}

/// The `[limits]` table: `max_memory` (bytes, a number or a string with a binary suffix,
/// `"8G"`) and `max_steps` (a whole number ≥ 1).
fn parse_limits(v: &Value, origin: &str) -> Result<LimitSpec, FemError> {
    let Value::Object(map) = v else {
        return Err(FemError::input(origin, "must be a table"));
    };
    let mut spec = LimitSpec::default();
    for (k, x) in map {
        let text = match x {
            Value::String(s) => s.clone(),
            Value::Number(n) => n.to_string(),
            _ => String::new(),
        };
        if crate::limits::LIMIT_KEYS.contains(&k.as_str()) {
            crate::limits::set_from_text(&mut spec, k, &text)
                .map_err(|m| FemError::input(origin, format!("`{k}` = {x}; {m}")))?;
        } else {
            let hint = nearest(k, &crate::limits::LIMIT_KEYS)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(FemError::input(
                origin,
                format!(
                    "unknown key `{k}`{hint}; valid keys: {}",
                    crate::limits::LIMIT_KEYS.join(", ")
                ),
            ));
        }
    }
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_syntax_error_has_line_and_column() {
        let e = parse_toml("a = 1\nb = = 2\n", "m.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("m.toml:2:"), "{e}");
        assert!(!e.contains('\n'));
    }

    #[test]
    fn nan_is_refused_with_its_key() {
        let e = parse_toml("[[node]]\nid = 1\nxyz = [0.0, nan, 0.0]\n", "m.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("node[0].xyz[1]"), "{e}");
    }

    #[test]
    fn json_syntax_error_has_line() {
        let e = parse_json("{\n \"node\": [\n}", "m.json")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("m.json:3:"), "{e}");
    }
}
