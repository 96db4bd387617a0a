//! The run sidecar: `run.json` beside a command's outputs, saying what made them.
//!
//! It holds the railfem version and git revision, the command, its argv and the options as
//! parsed (with the output directory resolved), the start and end times (UTC, ISO 8601) and
//! the status: `"completed"`, `"interrupted at t = … s"` or `"failed: …"`. It is written when
//! the command ends, into its output directory if that exists by then (a run refused before
//! it wrote anything leaves no directory and no sidecar). The file is written whole to a
//! temporary name and renamed, so a reader never sees half a sidecar.

use serde_json::{json, Value};
use std::path::PathBuf;
use std::time::{SystemTime, UNIX_EPOCH};

/// File name of the sidecar.
pub const RUN_JSON: &str = "run.json";

/// What a sidecar records about one command.
#[derive(Debug, Clone)]
pub struct RunRecord {
    /// The command (`curve`, `run`, …).
    pub command: String,
    /// The arguments after the program name, as given (lossy UTF-8).
    pub argv: Vec<String>,
    /// The options as parsed, output directory resolved.
    pub options: Value,
    /// Where the outputs go.
    pub dir: PathBuf,
    /// When the command started.
    pub start: SystemTime,
}

impl RunRecord {
    /// The sidecar as JSON, ending now with `status`.
    pub fn to_json(&self, status: &str) -> Value {
        json!({
            "railfem": {
                "version": env!("CARGO_PKG_VERSION"),
                "git_revision": env!("RAILFEM_GIT_REVISION"),
            },
            "command": self.command,
            "argv": self.argv,
            "options": self.options,
            "start": iso8601(self.start),
            "end": iso8601(SystemTime::now()),
            "status": status,
        })
    }

    /// Writes `run.json` into the output directory if it exists; the path written, if any.
    pub fn write(&self, status: &str) -> std::io::Result<Option<PathBuf>> {
        if !self.dir.is_dir() {
            return Ok(None);
        }
        let path = self.dir.join(RUN_JSON);
        // One temporary name per process: the ranks of an MPI study (or two runs pointed at
        // the same directory) each write theirs and rename it; the last rename wins whole,
        // where a shared name let one process rename the file another was still to rename.
        let tmp = self
            .dir
            .join(format!(".run.json.{}.tmp", std::process::id()));
        let text =
            serde_json::to_string_pretty(&self.to_json(status)).map_err(std::io::Error::other)?;
        // A failed write (a full disk) leaves the previous run.json and no temporary file.
        let written = std::fs::write(&tmp, text + "\n").and_then(|()| std::fs::rename(&tmp, &path));
        if let Err(e) = written {
            let _ = std::fs::remove_file(&tmp);
            return Err(e);
        }
        Ok(Some(path))
    }
}

/// `t` as UTC ISO 8601 to the second, `2026-11-24T23:09:00Z`.
pub fn iso8601(t: SystemTime) -> String {
    let secs = match t.duration_since(UNIX_EPOCH) {
        Ok(d) => d.as_secs() as i64,
        Err(e) => -(e.duration().as_secs() as i64),
    };
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let (y, m, d) = civil_date(days);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// The proleptic Gregorian date (year, month 1–12, day 1–31) of `days` since 1970-01-01.
///
/// Derivation: count from 0000-03-01 so that the leap day is the last day of a "year"
/// (March..February). An era of 400 years has 146 097 days. Within an era, the year of day
/// `doe` (0..146 096) is `(doe − doe/1460 + doe/36524 − doe/146096) / 365`: each term
/// removes the leap days of the 4-, 100- and 400-year cycles before it. The day of that
/// year gives the month through the 153-day rhythm of five months (31,30,31,30,31) from
/// March: month index `mp = (5·doy + 2)/153`, first day of it `(153·mp + 2)/5`.
fn civil_date(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468; // 1970-01-01 is day 719 468 counted from 0000-03-01
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// This process's rank when an MPI launcher started it (`mpirun`/`mpiexec` of Open MPI,
/// MPICH/Hydra or PMIx set one of these variables in every rank's environment), else
/// `None`. Read from the environment, so the default build (without the `mpi` feature)
/// also knows it is one of several ranks.
pub fn launcher_rank() -> Option<u32> {
    ["OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.trim().parse().ok())
}

/// Ranks in the job when an MPI launcher started this process (the launcher's size
/// variable), else `None`.
pub fn launcher_size() -> Option<u32> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.trim().parse().ok())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn at(secs: u64) -> String {
        iso8601(UNIX_EPOCH + Duration::from_secs(secs))
    }

    #[test]
    fn dates_match_hand_counted_days() {
        assert_eq!(at(0), "1970-01-01T00:00:00Z");
        // 2000-02-29: 30 years of 365 days + 7 leap days (72..96) + 31 + 28 = 11 016 days.
        assert_eq!(at(11_016 * 86_400), "2000-02-29T00:00:00Z");
        assert_eq!(at(11_017 * 86_400 - 1), "2000-02-29T23:59:59Z");
        assert_eq!(at(11_017 * 86_400), "2000-03-01T00:00:00Z");
        // 1970-12-31 is day 364; 1972-12-31 (leap year) is day 365 + 365 + 365 = 1095.
        assert_eq!(at(364 * 86_400), "1970-12-31T00:00:00Z");
        assert_eq!(at(1095 * 86_400), "1972-12-31T00:00:00Z");
        // 2100 is not a leap year: 2100-03-01 follows 2100-02-28. Days to 2100-01-01:
        // 130 years, 32 leap days (1972..2096) → 47 482; + 31 + 28 = 47 541 for 03-01.
        assert_eq!(at(47_540 * 86_400), "2100-02-28T00:00:00Z");
        assert_eq!(at(47_541 * 86_400), "2100-03-01T00:00:00Z");
    }
}
