//! The irregularity's part of the whole model's size estimate
//! ([`railfem_framework::modelfile::check_model_size`]), from `[track] irregularity` as
//! written, before any profile is generated or table read: a generated profile costs what
//! its own guard counts ([`PsdRequest::estimated_bytes`]: `length / step` samples, doubled
//! for the power-of-two transform); a table costs its rows times its columns (the guard of
//! [`super::csv::read_table`]), the rows and columns counted in the file's text.

use super::csv::BYTES_PER_VALUE;
use super::generate::PsdRequest;
use super::IrregularitySpec;
use railfem_framework::limits::{self, fmt_num};
use railfem_framework::modelfile::SizePart;
use serde_json::Value;
use std::path::Path;

/// One part per entry of `v` (a table or a list), files relative to `base`, a generated
/// profile by default over the meshed `[from, to]`. An entry the section will refuse
/// estimates as nothing (its own message is the useful one).
pub fn estimate(v: &Value, base: &Path, [from, to]: [f64; 2]) -> Vec<SizePart> {
    let list: Vec<&Value> = match v {
        Value::Array(a) => a.iter().collect(),
        o @ Value::Object(_) => vec![o],
        _ => return Vec::new(),
    };
    let mut parts = Vec::new();
    for (i, item) in list.into_iter().enumerate() {
        let Ok(spec) = railfem_framework::keypath::from_value::<IrregularitySpec>(item, "", "")
        else {
            continue;
        };
        let key = format!("[track] irregularity[{i}]");
        match (&spec.file, &spec.psd, spec.wavelengths) {
            (None, Some(_), Some([lo, _])) => {
                let step = spec.step.unwrap_or(lo / 8.0);
                let start = spec.start.unwrap_or(from);
                let length = spec.length.unwrap_or(to - start);
                let samples = length / step + 1.0;
                if samples.is_finite() && samples > 0.0 {
                    parts.push(SizePart {
                        what: format!("{key}: {} samples", fmt_num(samples.ceil())),
                        bytes: PsdRequest::estimated_bytes(length, step),
                    });
                }
            }
            (Some(f), None, _) => {
                let path = base.join(f);
                if limits::check_file(&path, "the irregularity file").is_err() {
                    continue;
                }
                let Ok(text) = std::fs::read_to_string(&path) else {
                    continue;
                };
                let rows = text.lines().count() as f64;
                let columns = text
                    .trim_start_matches('\u{feff}')
                    .lines()
                    .find(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
                    .map_or(1, |h| h.split(',').count()) as f64;
                parts.push(SizePart {
                    what: format!("{key}: `{f}`, {} rows", fmt_num(rows)),
                    bytes: rows * columns * BYTES_PER_VALUE,
                });
            }
            _ => {}
        }
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_generated_profile_counts_its_samples_and_a_table_its_values() {
        // 1000 m at 0.25 m: 4001 samples, doubled, 72 bytes each.
        let v = serde_json::json!([
            {"psd": "fra4", "seed": 1, "wavelengths": [2.0, 50.0], "step": 0.25, "length": 1000.0},
            {"psd": "fra4", "seed": 1, "wavelengths": [2.0, 50.0]},
        ]);
        let p = estimate(&v, Path::new("."), [0.0, 400.0]);
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].what, "[track] irregularity[0]: 4001 samples");
        assert_eq!(p[0].bytes, 2.0 * 4001.0 * 72.0);
        // Defaults: step λmin/8 = 0.25 m over the mesh [0, 400] m: 1601 samples.
        assert_eq!(p[1].bytes, 2.0 * 1601.0 * 72.0);
        let dir = std::env::temp_dir().join(format!("railfem_irr_est_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("t.csv"),
            "# c\nstation_m,vertical_mm\n0,0\n1,0.5\n",
        )
        .unwrap();
        let p = estimate(&serde_json::json!({"file": "t.csv"}), &dir, [0.0, 1.0]);
        // Four lines (the comment and the header counted as rows: an upper bound), two
        // columns, 48 bytes a value.
        assert_eq!(p[0].bytes, 4.0 * 2.0 * 48.0);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
