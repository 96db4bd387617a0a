//! The checkpoint of a study, `DIR/study.checkpoint`: a first line naming the plan's
//! fingerprint and case count, then one line per finished case (its `study.csv` row),
//! appended and flushed as each case ends. A rerun of the same plan reads it and skips the
//! cases it lists; a checkpoint of another plan is refused. A last line cut by a kill (no
//! line end) is dropped, so that case runs again.

use crate::framework::FemError;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

/// File name of the checkpoint in the output folder.
pub const FILE: &str = "study.checkpoint";

/// The first line of a checkpoint.
fn head(fingerprint: u64, cases: usize) -> String {
    format!("railfem-study-checkpoint v1 plan={fingerprint:016x} cases={cases}")
}

/// An open checkpoint: the rows found (by case id) and the file to append to.
pub struct Checkpoint {
    /// Rows of the finished cases, by id.
    pub rows: BTreeMap<String, String>,
    path: PathBuf,
    file: std::fs::File,
}

impl Checkpoint {
    /// Opens (or starts) the checkpoint of a plan in `dir`.
    pub fn open(dir: &Path, fingerprint: u64, cases: usize) -> Result<Checkpoint, FemError> {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        let path = dir.join(FILE);
        let want = head(fingerprint, cases);
        let mut rows = BTreeMap::new();
        let mut text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
            Err(e) => return Err(FemError::output(&path, e)),
        };
        if !text.is_empty() {
            let first = text.lines().next().unwrap_or("");
            if first != want {
                return Err(FemError::input(
                    path.display().to_string(),
                    format!(
                        "this checkpoint belongs to another plan (`{first}`, this plan is `{want}`): the plan, its base or its records changed; remove {} to start over, or give another --out",
                        path.display()
                    ),
                ));
            }
            // Drop a last line cut by a kill, keeping the file ending on a line end.
            if !text.ends_with('\n') {
                let keep = text.rfind('\n').map_or(0, |i| i + 1);
                text.truncate(keep);
                std::fs::write(&path, &text).map_err(|e| FemError::output(&path, e))?;
            }
            for line in text.lines().skip(1).filter(|l| !l.is_empty()) {
                let id = line.split(',').next().unwrap_or("").to_string();
                rows.insert(id, line.to_string());
            }
        }
        let mut file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .map_err(|e| FemError::output(&path, e))?;
        if text.is_empty() {
            writeln!(file, "{want}").map_err(|e| FemError::output(&path, e))?;
            file.flush().map_err(|e| FemError::output(&path, e))?;
        }
        Ok(Checkpoint { rows, path, file })
    }

    /// Records a finished case: appends its row and flushes it to the file.
    pub fn record(&mut self, id: &str, row: String) -> Result<(), FemError> {
        writeln!(self.file, "{row}").map_err(|e| FemError::output(&self.path, e))?;
        self.file
            .flush()
            .map_err(|e| FemError::output(&self.path, e))?;
        self.rows.insert(id.to_string(), row);
        Ok(())
    }
}
