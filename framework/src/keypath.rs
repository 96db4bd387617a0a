//! Typed values out of a parsed input, with the key path of whatever is refused.
//!
//! Every model file, vehicle file and section is first parsed into a JSON
//! [`serde_json::Value`] (TOML and JSON alike, [`crate::modelfile`]) and then deserialized
//! into its typed structs. serde's own error says what was wrong ("invalid length 3,
//! expected an array of length 2") but not where; [`from_value`] tracks the path with
//! `serde_path_to_error`, so the message names the key, down to the array index:
//! `vehicle[0].speed_table[2]`, `track.irregularity[0].seed`.

use crate::error::FemError;
use serde::de::DeserializeOwned;
use serde_json::Value;

/// Deserializes `v`, the value at key path `at` of the input (`"vehicle[0]"`, `""` for the
/// top of a file), into `T`. A refusal is [`FemError::input`] at `origin` whose message
/// names the full key path of the offending value, serde's reason and the fix.
pub fn from_value<T: DeserializeOwned>(v: &Value, origin: &str, at: &str) -> Result<T, FemError> {
    serde_path_to_error::deserialize(v).map_err(|e| {
        let reason = e.inner().to_string();
        let mut rel = e.path().to_string();
        if let Some(key) = map_key(e.path(), &reason) {
            // A map keyed by an enum: serde_path_to_error writes the refused key as `?`.
            rel = format!("{}{key}", &rel[..rel.len() - 1]);
        } else if let Some(key) = variant_key(v, e.path(), &reason) {
            rel = join(if rel == "." { "" } else { &rel }, &key);
        }
        let path = join(at, &rel);
        FemError::input(origin, message(&path, &reason))
    })
}

/// The refused key of a map whose keys are an enum (a suspension's `bump_stop.w`): the
/// path ends in an unknown segment (`?`) and the reason names the variant.
fn map_key(path: &serde_path_to_error::Path, reason: &str) -> Option<String> {
    use serde_path_to_error::Segment;
    if !matches!(path.iter().next_back(), Some(Segment::Unknown)) {
        return None;
    }
    let bad = reason
        .strip_prefix("unknown variant `")?
        .split('`')
        .next()?;
    Some(bad.to_string())
}

/// The key below `path` that holds the unknown variant `reason` names, where the path
/// stops short of it. Inside an internally tagged enum (`[[load]]`, `[[recorder]]`: the
/// `type` key picks the variant) serde reads the table into a buffer first, and the path
/// ends at the table (`recorder[3]`); the key is then the one whose string is the refused
/// value (`method`), searched in the table's own keys and their arrays (`dofs[1]`).
fn variant_key(v: &Value, path: &serde_path_to_error::Path, reason: &str) -> Option<String> {
    use serde_path_to_error::Segment;
    let bad = reason
        .strip_prefix("unknown variant `")?
        .split('`')
        .next()?;
    let mut here = v;
    for seg in path {
        here = match seg {
            Segment::Seq { index } => here.get(*index)?,
            Segment::Map { key } => here.get(key)?,
            _ => return None,
        };
    }
    if here.as_str() == Some(bad) {
        return None;
    }
    let obj = here.as_object()?;
    obj.iter().find_map(|(k, x)| match x {
        Value::String(s) if s == bad => Some(k.clone()),
        Value::Array(a) => a
            .iter()
            .position(|y| y.as_str() == Some(bad))
            .map(|i| format!("{k}[{i}]")),
        _ => None,
    })
}

/// `at` and a path relative to it (serde_path_to_error prints `.` for the empty path).
pub fn join(at: &str, rel: &str) -> String {
    let rel = if rel == "." { "" } else { rel };
    match (at.is_empty(), rel.is_empty()) {
        (_, true) => at.to_string(),
        (true, false) => rel.to_string(),
        (false, false) if rel.starts_with('[') => format!("{at}{rel}"),
        (false, false) => format!("{at}.{rel}"),
    }
}

/// The one-line message for a value refused at `path` because of `reason`: the key, what
/// serde expected, and how to fix it.
fn message(path: &str, reason: &str) -> String {
    let reason = reason.replace('\n', " ");
    let fix = if reason.starts_with("unknown field") {
        "remove or rename the key"
    } else if reason.starts_with("missing field") {
        "add the key"
    } else if reason.starts_with("unknown variant") || reason.contains("expected one of") {
        "give one of the values listed"
    } else {
        "give a value of the expected kind"
    };
    let key = if path.is_empty() {
        "the top level".to_string()
    } else {
        format!("`{path}`")
    };
    format!("{key}: {reason}; {fix} (docs/model-format.md lists every key, its type and unit)")
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Train {
        speed_table: Vec<[f64; 2]>,
        seed: Option<u64>,
    }

    #[test]
    fn the_message_names_the_key_down_to_the_index() {
        let v = serde_json::json!({"speed_table": [[0, 1], [1, 2], [2, 3, 4]]});
        let e = from_value::<Train>(&v, "m.toml", "vehicle[0]")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("m.toml: `vehicle[0].speed_table[2]`: invalid length 3"),
            "{e}"
        );
        let v = serde_json::json!({"speed_table": [], "seed": -1});
        let e = from_value::<Train>(&v, "m.toml", "track.irregularity[0]")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`track.irregularity[0].seed`: invalid value: integer `-1`"),
            "{e}"
        );
        let e = from_value::<Train>(&serde_json::json!({"spede_table": []}), "m.toml", "")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown field `spede_table`") && e.contains("remove or rename"),
            "{e}"
        );
        assert_eq!(join("a", "[1].b"), "a[1].b");
        // Inside an internally tagged enum the path stops at the table: the key holding
        // the refused value is named all the same.
        #[derive(Debug, Deserialize)]
        #[serde(tag = "type", rename_all = "snake_case")]
        #[allow(dead_code)]
        enum Tagged {
            Comfort { method: Method },
        }
        #[derive(Debug, Deserialize)]
        #[serde(rename_all = "snake_case")]
        enum Method {
            Sperling,
        }
        let v = serde_json::json!([{"type": "comfort", "method": "iso"}]);
        let e = from_value::<Vec<Tagged>>(&v, "m.toml", "recorder")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`recorder[0].method`: unknown variant `iso`, expected `sperling`"),
            "{e}"
        );
        assert_eq!(join("", "."), "");
        // A map keyed by an enum names the refused key itself.
        #[derive(Debug, Deserialize, PartialEq, Eq, PartialOrd, Ord)]
        #[serde(rename_all = "lowercase")]
        enum Axis {
            X,
        }
        let v = serde_json::json!({"stop": {"x": 1.0, "w": 2.0}});
        let e = from_value::<
            std::collections::BTreeMap<String, std::collections::BTreeMap<Axis, f64>>,
        >(&v, "m.toml", "s[0]")
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("`s[0].stop.w`: unknown variant `w`, expected `x`"),
            "{e}"
        );
    }
}
