//! Typed errors of the framework, and the helpers that make them useful.
//!
//! Every error a user's input can cause is a [`FemError`] whose `Display` is one line naming
//! the file, the place and the fix; the CLI prints it and exits with code 2. Nothing here
//! panics on bad input.

use thiserror::Error;

/// Everything that can go wrong in building or running a model.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FemError {
    /// Bad input: `origin` names the file and the place, `message` what is wrong and the fix.
    #[error("{origin}: {message}")]
    Input {
        /// File and place (`"bridge.toml: element[3] (id 7)"`).
        origin: String,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A plugin could not be loaded or refused to load.
    #[error("plugin: {0}")]
    Plugin(String),
    /// The model is singular: a DOF has no stiffness.
    #[error("singular model: {0}")]
    Singular(String),
    /// A step did not converge even after cutting the step.
    #[error("no convergence: {0}")]
    Convergence(String),
    /// A NaN or infinity appeared.
    #[error("non-finite value: {0}")]
    NonFinite(String),
    /// An element failed.
    #[error("element {id} ({kind}): {message}")]
    Element {
        /// User id of the element.
        id: u64,
        /// Registered type.
        kind: String,
        /// What happened.
        message: String,
    },
    /// Writing an output failed (the files written end on whole lines; a full disk, a size
    /// limit, a folder that cannot be written, a device that failed: [`FemError::output`]).
    #[error("output {path}: {message}; {fix}")]
    Output {
        /// File that could not be written.
        path: String,
        /// The operating system's reason.
        message: String,
        /// What to do about it: make room for a full disk or a size limit, check the disk
        /// and its mount for an I/O error.
        fix: String,
    },
    /// Several independent problems found in one pass (a model file with more than one
    /// mistake). `Display` is the first one plus a count, one line; [`FemError::problems`]
    /// lists them all (what `railfem check` prints).
    #[error("{}", many_line(.0))]
    Many(Vec<FemError>),
    /// The run was asked to stop (SIGINT, SIGTERM: [`crate::interrupt`]) and stopped at the
    /// end of the step that reached time `t`; its outputs are flushed and whole.
    #[error("interrupted at t = {t:.6} s")]
    Interrupted {
        /// Time (s) of the last completed step.
        t: f64,
    },
    /// A command made of whole units of work (the cases of a sweep or a study, the load
    /// steps of a static analysis) was asked to stop and stopped at the boundary after
    /// `after` (`"12 of 45 cases"`); what it writes holds the completed units only.
    #[error("interrupted after {after}")]
    InterruptedAfter {
        /// The completed units, in words.
        after: String,
    },
}

/// `s` on one line: a line break or other control character that user text brings into a
/// message (a key or a value echoed back, a file name) is written as its escape (`\n`),
/// so that every input message stays the one line the CLI prints.
fn one_line(s: String) -> String {
    if !s.chars().any(char::is_control) {
        return s;
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

fn fold_repeats(list: Vec<FemError>) -> Vec<FemError> {
    let mut out: Vec<(FemError, usize)> = Vec::new();
    for e in list {
        let same = out.iter_mut().find(|(f, _)| match (f, &e) {
            (FemError::Input { message: a, .. }, FemError::Input { message: b, .. }) => a == b,
            _ => false,
        });
        match same {
            Some((_, n)) => *n += 1,
            None => out.push((e, 0)),
        }
    }
    out.into_iter()
        .map(|(e, n)| match (e, n) {
            (FemError::Input { origin, message }, n) if n > 0 => FemError::Input {
                origin,
                message: format!(
                    "{message} (the same at {n} more place{})",
                    if n == 1 { "" } else { "s" }
                ),
            },
            (e, _) => e,
        })
        .collect()
}

fn many_line(list: &[FemError]) -> String {
    let flat: Vec<&FemError> = list.iter().flat_map(FemError::problems).collect();
    match flat.as_slice() {
        [] => "no problem".to_string(),
        [one] => one.to_string(),
        [first, rest @ ..] => format!(
            "{first} (and {} more problem{}; `railfem check` lists them)",
            rest.len(),
            if rest.len() == 1 { "" } else { "s" }
        ),
    }
}

impl FemError {
    /// A bad-input error at `origin`.
    pub fn input(origin: impl Into<String>, message: impl Into<String>) -> FemError {
        FemError::Input {
            origin: one_line(origin.into()),
            message: one_line(message.into()),
        }
    }

    /// Every problem this error stands for, flattened (one for all but [`FemError::Many`]).
    pub fn problems(&self) -> Vec<&FemError> {
        match self {
            FemError::Many(list) => list.iter().flat_map(FemError::problems).collect(),
            one => vec![one],
        }
    }

    /// `Ok` for no problem, the problem itself for one, [`FemError::Many`] for several.
    /// Bad-input problems with the same message at several places (one `wheel` table
    /// behind eight generated wheels, one mistake copied into many tables) are reported
    /// once, at the first place, with the count of the others.
    pub fn from_list(list: Vec<FemError>) -> Result<(), FemError> {
        let mut list = fold_repeats(list);
        match list.len() {
            0 => Ok(()),
            1 => Err(list.remove(0)),
            _ => Err(FemError::Many(list)),
        }
    }

    /// This error with `file` named at its front, unless it names it already: the
    /// command line's guarantee that every message names the model file, whichever layer
    /// (solver, element, load) found the problem.
    pub fn in_file(self, file: &str) -> FemError {
        if file.is_empty() || self.to_string().contains(file) {
            return self;
        }
        let at = |m: String| format!("{file}: {m}");
        match self {
            FemError::Input { origin, message } => FemError::Input {
                origin: at(origin),
                message,
            },
            FemError::Plugin(m) => FemError::Plugin(at(m)),
            FemError::Singular(m) => FemError::Singular(at(m)),
            FemError::Convergence(m) => FemError::Convergence(at(m)),
            FemError::NonFinite(m) => FemError::NonFinite(at(m)),
            FemError::Element { id, kind, message } => {
                FemError::input(format!("{file}: element {id} ({kind})"), message)
            }
            e @ FemError::Output { .. } => e,
            FemError::Interrupted { t } => FemError::Interrupted { t },
            FemError::InterruptedAfter { after } => FemError::InterruptedAfter { after },
            FemError::Many(list) => {
                FemError::Many(list.into_iter().map(|e| e.in_file(file)).collect())
            }
        }
    }

    /// An output error for `path`: the reason `e`, and the fix that reason calls for. An
    /// [`std::io::Error`] is read by [`FemError::output_io`] (a failing device is told from
    /// a full one); any other reason (a recorder's own fault, a figure's) gets the fix of a
    /// full disk.
    pub fn output(
        path: impl AsRef<std::path::Path>,
        e: impl std::fmt::Display + 'static,
    ) -> FemError {
        if let Some(io) = (&e as &dyn std::any::Any).downcast_ref::<std::io::Error>() {
            return FemError::output_io(path, io);
        }
        FemError::Output {
            path: path.as_ref().display().to_string(),
            message: e.to_string(),
            fix: MAKE_ROOM.to_string(),
        }
    }

    /// An output error for `path` from the operating system's error `e`. `EIO` (the disk,
    /// the network mount or the device failed the write: a hardware or mount fault, not a
    /// lack of room) says "I/O error" and to check the disk and its mount; anything else
    /// (`ENOSPC`, `EFBIG` past a size limit, `EDQUOT`, `EACCES`) says to make room or to
    /// write elsewhere.
    pub fn output_io(path: impl AsRef<std::path::Path>, e: &std::io::Error) -> FemError {
        let (message, fix) = if is_device_error(e) {
            (
                format!(
                    "I/O error: the device failed the write (os error {})",
                    e.raw_os_error().unwrap_or_default()
                ),
                CHECK_DEVICE,
            )
        } else {
            (e.to_string(), MAKE_ROOM)
        };
        FemError::Output {
            path: path.as_ref().display().to_string(),
            message,
            fix: fix.to_string(),
        }
    }
}

/// The fix of an output that found no room (a full disk, a size limit, a quota).
const MAKE_ROOM: &str = "make room there or write elsewhere (--out)";

/// The fix of an output whose device failed (`EIO`).
const CHECK_DEVICE: &str =
    "check the disk and its mount (the system log names the device), then run again or write elsewhere (--out)";

/// Whether `e` is the device's own failure (`EIO`) rather than a lack of room or of rights.
fn is_device_error(e: &std::io::Error) -> bool {
    #[cfg(unix)]
    {
        e.raw_os_error() == Some(libc::EIO)
    }
    #[cfg(not(unix))]
    {
        let _ = e;
        false
    }
}

/// Levenshtein edit distance between two strings (case-insensitive).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.to_lowercase().chars().collect();
    let b: Vec<char> = b.to_lowercase().chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        cur[0] = i;
        for j in 1..=b.len() {
            let sub = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = sub.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// The candidate nearest to `word`, if any is reasonably close.
pub fn nearest<'a>(word: &str, candidates: &[&'a str]) -> Option<&'a str> {
    nearest_n(word, candidates, 1).into_iter().next()
}

/// Up to `n` candidates nearest to `word`, closest first, excluding hopeless ones.
pub fn nearest_n<'a>(word: &str, candidates: &[&'a str], n: usize) -> Vec<&'a str> {
    let mut scored: Vec<(usize, &str)> = candidates
        .iter()
        .map(|c| {
            let d = edit_distance(word, c);
            // A prefix or substring match is as good as one edit.
            let d = if c.contains(word) || word.contains(c) {
                d.min(1)
            } else {
                d
            };
            (d, *c)
        })
        .filter(|(d, c)| *d <= (c.len().max(word.len()) / 2).max(2))
        .collect();
    scored.sort();
    scored.into_iter().take(n).map(|(_, c)| c).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn user_text_with_line_breaks_stays_on_one_line() {
        let e = FemError::input("m.json", "unknown key `a\nb\r\tc`").to_string();
        assert_eq!(e, "m.json: unknown key `a\\nb\\r\\tc`");
    }

    #[test]
    fn many_problems_print_the_first_and_a_count_on_one_line() {
        let e = FemError::from_list(vec![
            FemError::input("m.toml: node[0]", "a"),
            FemError::Many(vec![
                FemError::input("m.toml: node[1]", "b"),
                FemError::input("m.toml: node[2]", "c"),
            ]),
        ])
        .unwrap_err();
        assert_eq!(e.problems().len(), 3);
        assert_eq!(
            e.to_string(),
            "m.toml: node[0]: a (and 2 more problems; `railfem check` lists them)"
        );
        assert!(FemError::from_list(Vec::new()).is_ok());
    }

    #[test]
    fn distances() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(
            nearest("beam3", &["beam3d", "mass", "spring_damper"]),
            Some("beam3d")
        );
        assert_eq!(nearest("zzzzzzzz", &["beam3d", "mass"]), None);
    }

    /// A writer whose device fails or is full: every write returns the OS error `code`.
    struct Failing(i32);

    impl std::io::Write for Failing {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::Error::from_raw_os_error(self.0))
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// The line a recorder's failed write gives: rows buffered as the recorders buffer
    /// them, the error surfacing at the flush and mapped as they map it.
    fn recorder_line(code: i32) -> String {
        use std::io::Write;
        let mut out = std::io::BufWriter::new(Failing(code));
        writeln!(out, "time [s],1_ux [m]").unwrap();
        let e = out.flush().unwrap_err();
        FemError::output("out/disp.csv", e).to_string()
    }

    #[cfg(unix)]
    #[test]
    fn an_io_error_says_so_and_to_check_the_disk_a_full_disk_to_make_room() {
        assert_eq!(
            recorder_line(libc::EIO),
            format!(
                "output out/disp.csv: I/O error: the device failed the write (os error {}); \
                 check the disk and its mount (the system log names the device), then run \
                 again or write elsewhere (--out)",
                libc::EIO
            )
        );
        let full = recorder_line(libc::ENOSPC);
        assert!(
            full.starts_with("output out/disp.csv: No space left on device")
                && full.ends_with("; make room there or write elsewhere (--out)"),
            "{full}"
        );
        assert!(!full.contains("I/O error"), "{full}");
        // A reason that is not the system's keeps the fix of a full disk.
        assert_eq!(
            FemError::output("out/run.json", "a fault").to_string(),
            "output out/run.json: a fault; make room there or write elsewhere (--out)"
        );
        // And an output error named in a model file keeps its own path and fix.
        let e = FemError::output_io(
            "out/disp.csv",
            &std::io::Error::from_raw_os_error(libc::EIO),
        );
        assert_eq!(e.clone().in_file("m.toml"), e);
    }
}
