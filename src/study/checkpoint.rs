//! The checkpoint of a study, `DIR/study.checkpoint`, and its verification on resume.
//!
//! The first line names the format, the plan's fingerprint and its case count; then one
//! line per finished case, `CHECKSUM ROW`: the case's `study.csv` row preceded by 16 hex
//! digits of FNV-1a over the plan's fingerprint and the row ([`row_sum`]). Rows are
//! appended, flushed and synced as each case ends; the first line, and any rewrite, goes
//! through a temporary file renamed over the checkpoint ([`crate::atomic_file`]).
//!
//! On resume every line is verified before any is used: the checksum, the column count of
//! the plan's table, a case id of the plan, the axis values of that case, a status of `ok`
//! or `failed`, and no case twice. A line that fails is refused with one line naming the
//! checkpoint, the line and the fix (delete the row, or start afresh with `--restart`),
//! and nothing is published. A last line cut by a kill (no line end) is not a finished
//! case: it is dropped, and that case runs again. A checkpoint of another plan (or of an
//! earlier format) is refused as a whole.
//!
//! One writer at a time: opening takes an exclusive advisory lock (`flock`) on the output
//! folder, held until the study ends (the kernel drops it when the process dies, so a kill
//! leaves no stale lock). A second study on the same folder while the first runs — two
//! commands given the same `--out`, or ranks of an MPI launch that did not join one world
//! and each ran the study alone — is refused at once instead of appending the same cases
//! twice.

use super::cases::{fnv1a, Case};
use super::plan::Plan;
use super::table;
use crate::framework::FemError;
use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::path::{Path, PathBuf};

/// File name of the checkpoint in the output folder.
pub const FILE: &str = "study.checkpoint";

/// The fix every refused row names.
const FIX: &str = "delete the row, or start afresh with `--restart`";

/// The first line of a checkpoint.
fn head(fingerprint: u64, cases: usize) -> String {
    format!("railfem-study-checkpoint v2 plan={fingerprint:016x} cases={cases}")
}

/// The checksum of a row under a plan: FNV-1a (64 bits) over the plan's fingerprint in hex,
/// a space and the row. A row copied from another plan's checkpoint fails it, as does any
/// change of a byte of the row.
pub fn row_sum(fingerprint: u64, row: &str) -> u64 {
    fnv1a(format!("{fingerprint:016x} {row}").as_bytes())
}

/// A row as the checkpoint stores it (without its line end).
pub fn line(fingerprint: u64, row: &str) -> String {
    format!("{:016x} {row}", row_sum(fingerprint, row))
}

/// An open checkpoint: the verified rows (by case id) and the file to append to.
pub struct Checkpoint {
    /// Rows of the finished cases, by id (each one of a case of the plan).
    pub rows: BTreeMap<String, String>,
    path: PathBuf,
    file: std::fs::File,
    fingerprint: u64,
    /// Bytes of whole lines in the file: what a failed append is cut back to.
    len: u64,
    /// An append failed: later rows are not written (the file ends on its last whole line).
    broken: bool,
    /// The output folder, opened and locked for as long as the checkpoint lives.
    _lock: WriterLock,
}

/// An exclusive `flock` on the output folder (module documentation); released on drop or
/// when the process ends. Where the file system cannot lock, the study runs without it.
struct WriterLock {
    #[cfg(unix)]
    _dir: std::fs::File,
}

impl WriterLock {
    /// Takes the lock on `dir`, or says that another study holds it.
    fn take(dir: &Path) -> Result<WriterLock, FemError> {
        #[cfg(unix)]
        {
            use std::os::fd::AsRawFd;
            let d = std::fs::File::open(dir).map_err(|e| FemError::output(dir, e))?;
            // SAFETY: flock on a descriptor this function owns; no memory is shared.
            let rc = unsafe { libc::flock(d.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
            if rc != 0 {
                let e = std::io::Error::last_os_error();
                if e.kind() == std::io::ErrorKind::WouldBlock {
                    return Err(FemError::input(
                        dir.join(FILE).display().to_string(),
                        "another `railfem study` is writing this checkpoint (the same --out \
                         given twice, or MPI ranks that did not join one job); wait for it to \
                         end or give another --out",
                    ));
                }
                // A file system without locks (some network mounts): run unguarded, as
                // before the lock existed, rather than refuse the study.
            }
            Ok(WriterLock { _dir: d })
        }
        #[cfg(not(unix))]
        {
            let _ = dir;
            Ok(WriterLock {})
        }
    }
}

/// What a row of this plan must look like.
struct Expected<'a> {
    fingerprint: u64,
    columns: usize,
    /// Case id → the case.
    by_id: HashMap<&'a str, &'a Case>,
    cases: usize,
}

impl Expected<'_> {
    /// The row of checkpoint line `text`, or what is wrong with it.
    fn verify(&self, text: &str) -> Result<(String, String), String> {
        let (sum, row) = match (text.get(..16), text.get(16..17), text.get(17..)) {
            (Some(s), Some(" "), Some(r)) if s.bytes().all(|b| b.is_ascii_hexdigit()) => (s, r),
            _ => {
                return Err(
                    "the row is damaged: it does not start with its 16-digit checksum".into(),
                )
            }
        };
        let cells = table::split_csv(row);
        let id = cells[0].as_str();
        let Some(case) = self.by_id.get(id) else {
            return Err(format!(
                "case `{id}` is not one of the plan's {} cases (ids {} to {})",
                self.cases,
                self.by_id.keys().min().copied().unwrap_or(""),
                self.by_id.keys().max().copied().unwrap_or("")
            ));
        };
        if cells.len() != self.columns {
            return Err(format!(
                "the row of case {id} is damaged: it has {} columns, the plan's table {}",
                cells.len(),
                self.columns
            ));
        }
        for (k, v) in case.values.iter().enumerate() {
            if cells[1 + k] != v.label() {
                return Err(format!(
                    "the row of case {id} is damaged: its value `{}` in column {} is not the case's `{}`",
                    cells[1 + k],
                    k + 2,
                    v.label()
                ));
            }
        }
        let status = cells[1 + case.values.len()].as_str();
        if status != "ok" && status != "failed" {
            return Err(format!(
                "the row of case {id} is damaged: its status is `{status}`, not `ok` or `failed`"
            ));
        }
        if u64::from_str_radix(sum, 16).ok() != Some(row_sum(self.fingerprint, row)) {
            return Err(format!(
                "the row of case {id} is damaged: its checksum does not match its contents (changed after it was written, or written for another plan)"
            ));
        }
        Ok((id.to_string(), row.to_string()))
    }
}

impl Checkpoint {
    /// Opens the checkpoint of `plan` (whose expansion is `cases`, fingerprint
    /// `fingerprint`) in `dir`, verifying every row (module documentation), or starts it
    /// afresh when there is none or `restart` asks so.
    pub fn open(
        dir: &Path,
        plan: &Plan,
        cases: &[Case],
        fingerprint: u64,
        restart: bool,
    ) -> Result<Checkpoint, FemError> {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        let lock = WriterLock::take(dir)?;
        let path = dir.join(FILE);
        let want = head(fingerprint, cases.len());
        let mut text = match std::fs::read(&path) {
            Ok(_) if restart => String::new(),
            Ok(b) => String::from_utf8(b).map_err(|e| {
                let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
                    .iter()
                    .filter(|b| **b == b'\n')
                    .count();
                FemError::input(
                    format!("{}: line {line}", path.display()),
                    format!("the row is damaged: it is not UTF-8 text; {FIX}"),
                )
            })?,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
            Err(e) => return Err(FemError::output(&path, e)),
        };
        // A last line cut by a kill is no finished case (a first line cut so is no
        // checkpoint: it is started again).
        let cut = !text.ends_with('\n') && !text.is_empty();
        if cut {
            text.truncate(text.rfind('\n').map_or(0, |i| i + 1));
        }
        let mut rows = BTreeMap::new();
        if let Some(first) = text.lines().next() {
            if first != want {
                let why = if first.starts_with("railfem-study-checkpoint v1 ") {
                    "it was written by an earlier railfem, without row checksums".to_string()
                } else {
                    format!("it belongs to another plan (`{first}`, this plan is `{want}`): the plan, its base or its records changed")
                };
                return Err(FemError::input(
                    format!("{}: line 1", path.display()),
                    format!("{why}; start afresh with `--restart`, or give another --out"),
                ));
            }
            let expected = Expected {
                fingerprint,
                columns: table::split_csv(&table::header(plan)).len(),
                by_id: cases.iter().map(|c| (c.id.as_str(), c)).collect(),
                cases: cases.len(),
            };
            for (k, l) in text.lines().enumerate().skip(1) {
                let place = format!("{}: line {}", path.display(), k + 1);
                let (id, row) = expected
                    .verify(l)
                    .map_err(|why| FemError::input(&place, format!("{why}; {FIX}")))?;
                if rows.insert(id.clone(), row).is_some() {
                    return Err(FemError::input(
                        place,
                        format!("case {id} is in the checkpoint twice; {FIX}"),
                    ));
                }
            }
        }
        if text.is_empty() {
            text = format!("{want}\n");
            crate::atomic_file::write(&path, text.as_bytes())?;
        } else if cut {
            crate::atomic_file::write(&path, text.as_bytes())?;
        }
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| FemError::output(&path, e))?;
        Ok(Checkpoint {
            rows,
            path,
            file,
            fingerprint,
            len: text.len() as u64,
            broken: false,
            _lock: lock,
        })
    }

    /// Records a finished case: appends its line in one write, flushes and syncs it. A
    /// failed write (a full disk) cuts the file back to its last whole line and records
    /// nothing more.
    pub fn record(&mut self, id: &str, row: String) -> Result<(), FemError> {
        if self.broken {
            return Ok(());
        }
        let text = line(self.fingerprint, &row) + "\n";
        let written = self
            .file
            .write_all(text.as_bytes())
            .and_then(|_| self.file.flush())
            .and_then(|_| self.file.sync_data());
        if let Err(e) = written {
            self.broken = true;
            let _ = self.file.set_len(self.len);
            return Err(FemError::output(&self.path, e));
        }
        self.len += text.len() as u64;
        self.rows.insert(id.to_string(), row);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A second writer on the same folder is refused with an input error naming the
    /// checkpoint, and the folder is free again once the first checkpoint is dropped.
    #[test]
    fn a_second_writer_is_refused_while_the_first_holds_the_folder() {
        let dir = std::env::temp_dir().join(format!("railfem-ck-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let plan_file = dir.join("plan.toml");
        std::fs::write(
            &plan_file,
            "case = \"train-bridge\"\n[options]\ncars = 1\nspans = 1\nspan = 10.0\n\
             element_length = 2.5\ndt = 0.01\nduration = 0.2\n[[axis]]\nname = \"speed\"\n\
             values = [60, 100]\n",
        )
        .unwrap();
        let plan = super::super::plan::read(&plan_file).unwrap();
        let cases = super::super::cases::expand(&plan);
        let fp = super::super::cases::fingerprint(&plan, &cases).unwrap();
        let out = dir.join("out");
        let first = Checkpoint::open(&out, &plan, &cases, fp, false).unwrap();
        let second = Checkpoint::open(&out, &plan, &cases, fp, false);
        let Err(e) = second else {
            panic!("a second writer was let in")
        };
        let text = e.to_string();
        assert!(matches!(e, FemError::Input { .. }), "{text}");
        assert!(text.contains(FILE) && text.contains("another"), "{text}");
        drop(first);
        assert!(Checkpoint::open(&out, &plan, &cases, fp, false).is_ok());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
