//! The results folder: created if missing; a previous run's results are backed up, replaced or
//! kept according to `[output] existing`, and the log says which.
use super::Error;
use crate::config::ExistingOutput;
use crate::parallel::Log;
use std::path::{Path, PathBuf};

/// Rank 0 only. Prepares `dir` for a new run; returns what was done, for the log.
pub fn prepare_output_dir(dir: &Path, policy: ExistingOutput, log: &Log) -> Result<(), Error> {
    let err = |source| Error::OutputDir { path: dir.to_path_buf(), source };
    let has_results = dir.is_dir() && std::fs::read_dir(dir).map_err(err)?.next().is_some();
    if has_results {
        match policy {
            ExistingOutput::Error => return Err(Error::OutputExists(dir.to_path_buf())),
            ExistingOutput::Overwrite => {
                log.warn(format!("replacing the previous results in {}", dir.display()));
                std::fs::remove_dir_all(dir).map_err(err)?;
            }
            ExistingOutput::Backup => {
                let backup = backup_path(dir);
                if backup.exists() {
                    std::fs::remove_dir_all(&backup).map_err(err)?;
                }
                std::fs::rename(dir, &backup).map_err(err)?;
                log.warn(format!(
                    "previous results in {} moved to {} (set [output] existing to change this)",
                    dir.display(),
                    backup.display()
                ));
            }
        }
    }
    std::fs::create_dir_all(dir).map_err(err)?;
    Ok(())
}

/// `<dir>.previous`
pub fn backup_path(dir: &Path) -> PathBuf {
    let mut s = dir.as_os_str().to_owned();
    s.push(".previous");
    PathBuf::from(s)
}
