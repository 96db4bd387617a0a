//! Size guards: every generator estimates what it will allocate, or how many steps it will
//! take, before it does the work, and asks this module whether that fits.
//!
//! Two budgets, process-wide like a `ulimit`:
//!
//! - `max_memory` (bytes): the default is half the machine's available memory
//!   (`MemAvailable` of `/proc/meminfo`; [`FALLBACK_MEMORY`] where that cannot be read).
//!   Half, because an estimate counts only the dominant arrays of a generator, and the
//!   measured cost of a model (2.3–4.9 KiB per DOF measured, docs/performance.md) varies by a
//!   factor of about two.
//! - `max_steps`: time steps of a transient, load steps of a static analysis (default
//!   [`DEFAULT_MAX_STEPS`]).
//!
//! Each budget is the command-line value (`--max-memory`, `--max-steps`), else the model
//! file's `[limits]` table, else the default. A refusal is one message that gives the
//! estimate, the key that caused it and the flag or key that raises the limit; the caller
//! adds the file and the place ([`crate::FemError::input`]). Numbers in messages are
//! printed with [`fmt_num`], which never hides a size (`1e200`, not `0.0`).

use std::sync::{OnceLock, RwLock};

/// Memory limit when `/proc/meminfo` cannot be read (bytes): 4 GiB.
pub const FALLBACK_MEMORY: u64 = 4 << 30;
/// Default largest number of time or load steps of one analysis.
pub const DEFAULT_MAX_STEPS: u64 = 10_000_000;
/// The step budget no setting can raise: 1e9 steps. At the fastest step measured (a few
/// microseconds, a single-DOF model) that is about an hour; a real model takes days. A run
/// asking for more is a mistake in `duration` or `dt` (`duration = 1e300`), refused before
/// its first step instead of never ending.
pub const ABSOLUTE_MAX_STEPS: u64 = 1_000_000_000;
/// Estimated bytes per equation (DOF) of an assembled model: the smallest per-DOF cost
/// measured for the train–bridge models below 1M DOF (docs/performance.md; 2.3 KiB at 1M DOF),
/// so that an estimate refuses only what is within that ratio of the limit.
pub const BYTES_PER_DOF: f64 = 2.9 * 1024.0;
/// Estimated bytes of a node without free DOFs (id, coordinates, DOF map entries).
pub const BYTES_PER_NODE: f64 = 256.0;

/// Budgets given by one source (command line or model file); `None` = not given.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LimitSpec {
    /// Memory budget (bytes).
    pub max_memory: Option<u64>,
    /// Step budget.
    pub max_steps: Option<u64>,
}

static COMMAND_LINE: RwLock<LimitSpec> = RwLock::new(LimitSpec {
    max_memory: None,
    max_steps: None,
});
static MODEL_FILE: RwLock<LimitSpec> = RwLock::new(LimitSpec {
    max_memory: None,
    max_steps: None,
});

/// Sets the budgets given on the command line (they override a model file's).
pub fn set_command_line(spec: LimitSpec) {
    *COMMAND_LINE.write().unwrap_or_else(|e| e.into_inner()) = spec;
}

/// Sets the budgets of the model file being read (its `[limits]` table).
pub fn set_model_file(spec: LimitSpec) {
    *MODEL_FILE.write().unwrap_or_else(|e| e.into_inner()) = spec;
}

/// The budgets given: the command line's where given, else the model file's.
fn given() -> LimitSpec {
    let cli = *COMMAND_LINE.read().unwrap_or_else(|e| e.into_inner());
    let file = *MODEL_FILE.read().unwrap_or_else(|e| e.into_inner());
    LimitSpec {
        max_memory: cli.max_memory.or(file.max_memory),
        max_steps: cli.max_steps.or(file.max_steps),
    }
}

/// The memory budget in force (bytes).
pub fn max_memory() -> u64 {
    given().max_memory.unwrap_or_else(default_memory)
}

/// Half the available memory, read once per process so that a long run's guards do not
/// change their answer as other programs come and go.
fn default_memory() -> u64 {
    static DEFAULT: OnceLock<u64> = OnceLock::new();
    *DEFAULT.get_or_init(|| available_memory().unwrap_or(2 * FALLBACK_MEMORY) / 2)
}

/// The step budget in force.
pub fn max_steps() -> u64 {
    given().max_steps.unwrap_or(DEFAULT_MAX_STEPS)
}

/// `MemAvailable` of `/proc/meminfo` (bytes), if readable.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Refuses unless `count` items of `bytes_each` bytes fit the memory budget. `cause`
/// names the key and its value (`` `element_length` = 1e-9 m over 30 m of track ``),
/// `what` the items (`"rail nodes"`), `fix` how to ask for less.
pub fn check_memory(
    cause: &str,
    count: f64,
    what: &str,
    bytes_each: f64,
    fix: &str,
) -> Result<(), String> {
    let bytes = count * bytes_each;
    let limit = max_memory();
    if count.is_finite() && bytes.is_finite() && bytes <= limit as f64 {
        return Ok(());
    }
    Err(format!(
        "{cause} implies {} {what} (about {}), more than the memory limit {}; {fix}, or raise the limit with `[limits] max_memory` or `--max-memory`",
        fmt_count(count),
        fmt_bytes(bytes),
        fmt_bytes(limit as f64)
    ))
}

/// Refuses unless `count` items fit a fixed cap (a count that costs time rather than
/// memory, e.g. the points of a profile whose checks are quadratic).
pub fn check_count(cause: &str, count: f64, what: &str, cap: f64, fix: &str) -> Result<(), String> {
    if count.is_finite() && count <= cap {
        return Ok(());
    }
    Err(format!(
        "{cause} implies {} {what}, more than {}; {fix}",
        fmt_count(count),
        fmt_count(cap)
    ))
}

/// Refuses unless `steps` fit the step budget; `cause` names the keys
/// (`` `duration` = 1e6 s at `dt` = 1e-6 s ``).
pub fn check_steps(cause: &str, steps: f64, fix: &str) -> Result<(), String> {
    let limit = max_steps();
    if steps.is_finite() && steps <= limit as f64 {
        return Ok(());
    }
    Err(format!(
        "{cause} is {} steps, more than the limit of {} steps; {fix}, or raise the limit with `[limits] max_steps` or `--max-steps`",
        fmt_count(steps),
        fmt_count(limit as f64)
    ))
}

/// Refuses a file larger than the memory budget before it is read; `what` names it.
pub fn check_file(path: &std::path::Path, what: &str) -> Result<(), String> {
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(()); // the read that follows reports a missing file
    };
    let limit = max_memory();
    if meta.len() <= limit {
        return Ok(());
    }
    Err(format!(
        "{what} {} is {}, more than the memory limit {}; give a smaller file, or raise the limit with `[limits] max_memory` or `--max-memory`",
        path.display(),
        fmt_bytes(meta.len() as f64),
        fmt_bytes(limit as f64)
    ))
}

/// The names of the budgets, as `[limits]` keys (the command line spells them with `-`).
pub const LIMIT_KEYS: [&str; 2] = ["max_memory", "max_steps"];

/// Reads budget `key` (one of [`LIMIT_KEYS`]) from its text into `spec`, for the model
/// file's `[limits]` and the command line alike; the error says what to give.
pub fn set_from_text(spec: &mut LimitSpec, key: &str, text: &str) -> Result<(), String> {
    match key {
        "max_memory" => {
            spec.max_memory = Some(
                parse_bytes(text).ok_or("give bytes (e.g. 8e9) or a size such as 8G or 512M")?,
            )
        }
        "max_steps" => {
            let n = parse_count(text).ok_or("give a whole number of steps ≥ 1 (e.g. 1e8)")?;
            if n > ABSOLUTE_MAX_STEPS {
                return Err(format!(
                    "{} steps is more than any run can take; give at most {} (1e9)",
                    fmt_count(n as f64),
                    ABSOLUTE_MAX_STEPS
                ));
            }
            spec.max_steps = Some(n);
        }
        _ => return Err(format!("valid keys: {}", LIMIT_KEYS.join(", "))),
    }
    Ok(())
}

/// Parses a byte count: a number of bytes (`8e9`) or a number with a binary suffix
/// `K`, `M`, `G`, `T` (optionally followed by `iB` or `B`: `8G`, `512MiB`).
pub fn parse_bytes(text: &str) -> Option<u64> {
    let t = text.trim();
    let t = t
        .strip_suffix("iB")
        .or_else(|| t.strip_suffix('B'))
        .unwrap_or(t);
    let (num, scale) = match t.chars().last()? {
        'K' | 'k' => (&t[..t.len() - 1], 1u64 << 10),
        'M' | 'm' => (&t[..t.len() - 1], 1 << 20),
        'G' | 'g' => (&t[..t.len() - 1], 1 << 30),
        'T' | 't' => (&t[..t.len() - 1], 1 << 40),
        _ => (t, 1),
    };
    let v: f64 = num.trim().parse().ok()?;
    let bytes = v * scale as f64;
    (bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64).then_some(bytes as u64)
}

/// Parses a whole count ≥ 1 written as an integer or in exponent form (`1e8`).
pub fn parse_count(text: &str) -> Option<u64> {
    let v: f64 = text.trim().parse().ok()?;
    (v.is_finite() && v >= 1.0 && v.fract() == 0.0 && v < u64::MAX as f64).then_some(v as u64)
}

/// A number for a message, in a form that shows its size: plain for moderate magnitudes
/// (`0.6`, `30`, `-5`), exponent form for very large or very small ones (`1e200`,
/// `1e-300`), `NaN`/`inf` as such. Never rounds a nonzero value to `0`.
pub fn fmt_num(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if a == 0.0 || (1e-4..1e7).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A point or vector for a message, each component as [`fmt_num`] prints it
/// (`[0, 0, 1e200]`).
pub fn fmt_vec(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|x| fmt_num(*x)).collect();
    format!("[{}]", parts.join(", "))
}

/// A count, rounded up to a whole number; from 1e9 on in exponent form with three
/// significant digits (`3e10`, `1.67e13`).
fn fmt_count(v: f64) -> String {
    if !v.is_finite() || v < 1e9 {
        return format!("{}", v.ceil());
    }
    let s = format!("{:.2e}", v);
    match s.split_once('e') {
        Some((m, e)) => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
        None => s,
    }
}

/// A byte count with a binary unit (`3.2 GiB`).
pub fn fmt_bytes(b: f64) -> String {
    if !b.is_finite() {
        return "an unbounded number of bytes".into();
    }
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut v = b;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < units.len() {
        v /= 1024.0;
        u += 1;
    }
    if v >= 1024.0 {
        format!("{} B", fmt_num(b))
    } else if u == 0 {
        format!("{v:.0} B")
    } else {
        format!("{v:.1} {}", units[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_show_their_size() {
        assert_eq!(fmt_num(1e200), "1e200");
        assert_eq!(fmt_num(1e-300), "1e-300");
        assert_eq!(fmt_num(-5.0), "-5");
        assert_eq!(fmt_num(0.6), "0.6");
        assert_eq!(fmt_num(0.0), "0");
        assert_eq!(fmt_num(f64::NAN), "NaN");
        assert_eq!(fmt_vec(&[0.0, 1e200, -2.5]), "[0, 1e200, -2.5]");
        assert_eq!(fmt_bytes(3.0 * 1024.0 * 1024.0 * 1024.0), "3.0 GiB");
        assert_eq!(fmt_bytes(512.0), "512 B");
        assert_eq!(fmt_count(3.000_000_000_5e10), "3e10");
        assert_eq!(fmt_count(1.666_666e13), "1.67e13");
        assert_eq!(fmt_count(12.2), "13");
    }

    #[test]
    fn byte_counts_parse() {
        assert_eq!(parse_bytes("8G"), Some(8 << 30));
        assert_eq!(parse_bytes("512MiB"), Some(512 << 20));
        assert_eq!(parse_bytes("1e9"), Some(1_000_000_000));
        assert_eq!(parse_bytes("-1G"), None);
        assert_eq!(parse_bytes("lots"), None);
        assert_eq!(parse_count("1e8"), Some(100_000_000));
        assert_eq!(parse_count("1.5"), None);
    }

    #[test]
    fn over_budget_is_refused_with_the_estimate_and_the_fix() {
        // 1e12 items of 8 bytes cannot fit any machine's half of available memory.
        let e = check_memory("`n` = 1e12", 1e12, "items", 8.0, "give fewer").unwrap_err();
        assert!(e.contains("1e12 items"), "{e}");
        assert!(e.contains("7.3 TiB"), "{e}");
        assert!(e.contains("--max-memory"), "{e}");
        assert!(check_memory("`n` = 10", 10.0, "items", 8.0, "").is_ok());
        assert!(check_memory("`n` = NaN", f64::NAN, "items", 8.0, "").is_err());
        let e = check_steps("`duration` = 1", 1e12, "give a larger dt").unwrap_err();
        assert!(e.contains("1e12 steps") && e.contains("max_steps"), "{e}");
    }
}
