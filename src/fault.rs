//! Fault injection, for testing that an error on one rank ends every rank.
//!
//! `MASONRY_HPC_INJECT_FAULT=<phase>@<rank>` makes rank `<rank>` fail when it reaches the named
//! phase (e.g. `assembly@1`), while the other ranks go on into the phase's collective calls.
//! Without the abort in `main` they would wait forever; with it, the run ends with the failing
//! rank's message. The variable is read once per phase; it is unset in normal use.
use crate::error::Error;

/// The environment variable that injects a fault.
pub const FAULT_VAR: &str = "MASONRY_HPC_INJECT_FAULT";

/// Returns an error if the fault variable names this `phase` and `rank`.
pub fn inject(phase: &str, rank: usize) -> Result<(), Error> {
    match std::env::var(FAULT_VAR) {
        Ok(spec) if spec == format!("{phase}@{rank}") => {
            Err(Error::Injected { phase: phase.to_string(), rank, variable: FAULT_VAR })
        }
        _ => Ok(()),
    }
}

/// The environment variable that kills the process at a named point, as a batch system's kill
/// would: no cleanup, no message (tests of resuming interrupted work).
pub const KILL_VAR: &str = "MASONRY_HPC_INJECT_KILL";

/// Ends the process at once (exit status 137, as after SIGKILL) if the kill variable names
/// `point`. Under mpirun the launcher then stops every rank.
pub fn kill_point(point: &str) {
    static KILL: std::sync::OnceLock<Option<String>> = std::sync::OnceLock::new();
    if KILL.get_or_init(|| std::env::var(KILL_VAR).ok()).as_deref() == Some(point) {
        std::process::exit(137);
    }
}
