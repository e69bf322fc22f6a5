//! The checkpoints of a DEM job's tests: one file per sample, `checkpoints/sample-KKK.ckpt` in
//! the results folder ([`crate::dem::solver::checkpoint`] describes the format).
//!
//! A sample's test writes its checkpoint when `[analysis] checkpoint_minutes` of wall time have
//! passed since its last one (after a load step), and once when it ends. `--restart` reads
//! them back: a finished sample's result comes from its checkpoint, a running one continues
//! from it, a sample without one starts afresh. A checkpoint of another sample, mechanics or
//! test, or a damaged one, is an error of the job's input (exit code 2) that names the file.
use crate::dem::solver::checkpoint::{decode, encode, write_atomic};
use crate::dem::solver::{CheckpointSink, DemError, Fingerprint, SolverState, TestCheckpoint};
use crate::error::JobError;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Sample `k`'s checkpoint in the results folder `out`.
pub(super) fn checkpoint_file(out: &Path, k: usize) -> PathBuf {
    out.join("checkpoints").join(format!("sample-{k:03}.ckpt"))
}

/// Writes sample `sample`'s checkpoints to its file: one after a load step once `every` has
/// passed since the last one (or since the test started), and every one it is handed at the
/// end.
pub(super) struct FileSink {
    sample: usize,
    file: PathBuf,
    fingerprint: Fingerprint,
    every: Duration,
    last: Instant,
    written: usize,
}

impl FileSink {
    /// A sink writing sample `sample`'s checkpoints to its file in the results folder `out`
    /// every `minutes` (> 0), for the test `fingerprint` describes.
    pub(super) fn new(out: &Path, sample: usize, fingerprint: Fingerprint, minutes: f64) -> FileSink {
        let every = Duration::try_from_secs_f64(60.0 * minutes).unwrap_or(Duration::MAX);
        let file = checkpoint_file(out, sample);
        FileSink { sample, file, fingerprint, every, last: Instant::now(), written: 0 }
    }
}

impl CheckpointSink for FileSink {
    fn due(&mut self, _: &SolverState) -> bool {
        self.last.elapsed() >= self.every
    }

    fn write(&mut self, c: TestCheckpoint) -> Result<(), DemError> {
        let failed = |e: &dyn std::fmt::Display| DemError::Checkpoint(format!("{}: {e}", self.file.display()));
        let bytes = encode(&self.fingerprint, &c).map_err(|e| failed(&e))?;
        if let Some(dir) = self.file.parent() {
            std::fs::create_dir_all(dir).map_err(|e| failed(&e))?;
        }
        write_atomic(&self.file, &bytes).map_err(|e| failed(&e))?;
        self.last = Instant::now();
        self.written += 1;
        // Tests of a killed run: the kill lands right after this checkpoint.
        crate::fault::kill_point(&format!("dem_sample_{}_checkpoint_{}", self.sample, self.written));
        Ok(())
    }
}

/// The checkpoint in `file`, if there is one, checked against `fingerprint`.
pub(super) fn read_checkpoint(file: &Path, fingerprint: &Fingerprint) -> Result<Option<TestCheckpoint>, JobError> {
    let bytes = match std::fs::read(file) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => return Err(JobError::DemCheckpointRead { file: file.to_path_buf(), source }),
    };
    decode(&bytes, fingerprint).map(Some).map_err(|source| JobError::DemCheckpoint { file: file.to_path_buf(), source })
}
