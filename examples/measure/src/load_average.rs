//! The machine's load averages, printed beside timings so that a reader can tell a quiet
//! run from a loaded one.

/// The three load averages of `/proc/loadavg` (empty where there is none).
pub fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .unwrap_or_default()
        .split_whitespace()
        .take(3)
        .collect::<Vec<_>>()
        .join(" ")
}
