//! The names of everything a run writes into its output directory, and the check that no
//! two writers claim the same file and that nothing is written outside the directory.
//!
//! railfem's own files of `railfem run` are listed once here ([`ENERGY_CSV`],
//! [`LAST_STATE_CSV`], [`MODES_CSV`]; the driver writes them under these names). Recorder
//! files must be relative paths inside `--out` — no absolute path, no `..`, not empty —
//! unique across recorders after normalisation (`a.csv`, `./a.csv` and `sub//a.csv` vs
//! `sub/a.csv` are the same file), and distinct from railfem's own files. The check runs
//! when the model is built, before anything is written.

use std::path::{Component, Path, PathBuf};

/// The energy balance of a transient run (`time, kinetic, strain, …`).
pub const ENERGY_CSV: &str = "energy.csv";
/// The last converged state, written when a transient step fails.
pub const LAST_STATE_CSV: &str = "last_converged_state.csv";
/// Mode shapes and frequencies of a modal analysis.
pub const MODES_CSV: &str = "modes.csv";

/// railfem's own files in a run's output directory, with what they hold.
pub const RUN_FILES: [(&str, &str); 3] = [
    (ENERGY_CSV, "railfem's energy balance"),
    (LAST_STATE_CSV, "railfem's last converged state"),
    (MODES_CSV, "railfem's mode shapes"),
];

/// `file` as a normalised relative path inside the output directory (`.` dropped, case
/// kept), or why it is not one.
pub fn normalise(file: &str) -> Result<PathBuf, &'static str> {
    if file.trim().is_empty() {
        return Err("is empty");
    }
    let p = Path::new(file);
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::Normal(x) => out.push(x),
            Component::CurDir => {}
            Component::ParentDir => return Err("contains `..`, which leaves the output directory"),
            Component::RootDir | Component::Prefix(_) => {
                return Err("is an absolute path, outside the output directory")
            }
        }
    }
    if out.as_os_str().is_empty() {
        return Err("names the output directory itself, not a file");
    }
    Ok(out)
}

/// Checks the recorder files `files` (in model order): each a relative path inside the
/// output directory, none claimed twice, none one of railfem's own [`RUN_FILES`]. The error
/// is `(index, message)` naming both claimants.
pub fn check_recorder_files(files: &[&str]) -> Result<(), (usize, String)> {
    let mut seen: Vec<PathBuf> = Vec::with_capacity(files.len());
    for (i, f) in files.iter().enumerate() {
        let p = normalise(f).map_err(|why| {
            (
                i,
                format!("`file` = \"{f}\" {why}; give a relative file name such as \"tip.csv\""),
            )
        })?;
        // The same file, or one recorder's file used as a directory by another.
        if let Some(j) = seen
            .iter()
            .position(|q| p.starts_with(q) || q.starts_with(&p))
        {
            let how = if seen[j] == p {
                "is also written by"
            } else {
                "needs a file as a directory, or a directory as a file, of"
            };
            return Err((
                i,
                format!(
                    "file \"{f}\" {how} recorder[{j}] (\"{}\"); give each recorder its own file",
                    files[j]
                ),
            ));
        }
        if let Some((own, what)) = RUN_FILES.iter().find(|(n, _)| p.starts_with(n)) {
            return Err((
                i,
                format!(
                    "file \"{f}\" is also written by railfem itself ({what}, `{own}`); rename the recorder's file"
                ),
            ));
        }
        seen.push(p);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_and_clashes_are_refused() {
        assert!(check_recorder_files(&["a.csv", "sub/b.csv"]).is_ok());
        let (i, m) = check_recorder_files(&["a.csv", "./a.csv"]).unwrap_err();
        assert_eq!(i, 1);
        assert!(m.contains("recorder[0]"), "{m}");
        let (i, m) = check_recorder_files(&["x.csv", "energy.csv"]).unwrap_err();
        assert_eq!(i, 1);
        assert!(m.contains("railfem itself"), "{m}");
        assert!(check_recorder_files(&["/tmp/a.csv"]).is_err());
        assert!(check_recorder_files(&["../a.csv"]).is_err());
        assert!(check_recorder_files(&["a/../../b.csv"]).is_err());
        assert!(check_recorder_files(&[""]).is_err());
        assert!(check_recorder_files(&["."]).is_err());
        assert!(check_recorder_files(&["sub//c.csv", "sub/c.csv"]).is_err());
        let (_, m) = check_recorder_files(&["a.csv", "a.csv/b.csv"]).unwrap_err();
        assert!(m.contains("as a directory"), "{m}");
        assert!(check_recorder_files(&["energy.csv/x.csv"]).is_err());
        assert!(check_recorder_files(&["sub/a.csv", "sub/b.csv", "subway.csv"]).is_ok());
    }
}
