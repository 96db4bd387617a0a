//! Whole-file writes that a kill, a full disk or a power cut cannot leave half done: the
//! bytes go to a temporary name in the same folder, are flushed and synced to the disk,
//! and the temporary file is renamed over the target (a rename within one file system
//! replaces the target whole, POSIX `rename(2)`). A failed write removes its temporary
//! file and names the file it was writing; the target keeps its previous contents.

use crate::framework::FemError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The temporary name of `path` for this process: `.NAME.PID.tmp` beside it (one per
/// process, so that two processes writing the same file never rename each other's).
pub fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

/// Replaces `path` by `bytes` atomically (module documentation).
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), FemError> {
    let tmp = temporary(path);
    let written = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.flush()?;
        f.sync_all()
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(FemError::output(path, e));
    }
    if let Err(e) = std::fs::rename(&tmp, path) {
        let _ = std::fs::remove_file(&tmp);
        return Err(FemError::output(path, e));
    }
    // The rename itself is durable once the folder is synced (best effort: not every
    // file system lets a folder be opened for it).
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}
