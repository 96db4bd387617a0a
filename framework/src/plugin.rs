//! Dynamic plugins (placeholder until the plugin loader lands).
use crate::error::FemError;
/// Loads a plugin library.
pub fn load(path: &std::path::Path) -> Result<(), FemError> {
    Err(FemError::Plugin(format!(
        "{}: plugins are not supported yet",
        path.display()
    )))
}
