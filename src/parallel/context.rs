//! The run context: the communicator and the one place that decides what gets printed.
use mpi::topology::SimpleCommunicator;
use mpi::traits::Communicator;
use std::io::Write;
use std::time::Instant;

/// Rank-aware log: rank 0 reports progress; other ranks speak only about their own errors.
#[derive(Clone, Debug)]
pub struct Log {
    rank: i32,
    quiet: bool,
    start: Instant,
}

impl Log {
    /// A log for `rank`; `quiet` silences progress (errors are always printed).
    pub fn new(rank: i32, quiet: bool) -> Log {
        Log { rank, quiet, start: Instant::now() }
    }

    /// The same log (clock, quietness) for a rank that prints progress when `speaks` (a group's
    /// leader in a sweep) and only its errors otherwise.
    pub fn speaking(&self, speaks: bool) -> Log {
        Log { rank: if speaks { 0 } else { 1 }, ..self.clone() }
    }

    /// Whether this rank prints progress.
    pub fn is_root(&self) -> bool {
        self.rank == 0 && !self.quiet
    }

    /// A progress line, printed by rank 0 with the elapsed wall time.
    pub fn info(&self, msg: impl AsRef<str>) {
        if self.is_root() {
            let t = self.start.elapsed().as_secs_f64();
            let mut out = std::io::stdout().lock();
            let _ = writeln!(out, "[{t:8.2}s] {}", msg.as_ref());
            let _ = out.flush();
        }
    }

    /// A warning, printed by rank 0 to stderr.
    pub fn warn(&self, msg: impl AsRef<str>) {
        if self.rank == 0 {
            print_error(&format!("warning: {}", msg.as_ref()));
        }
    }

    /// Seconds since the log was created.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

/// Writes `message` and a newline to stderr in one `write` call. `eprintln!` writes the pieces of
/// its format one by one (stderr is unbuffered), and under `mpirun` another process's output,
/// such as Open MPI's `MPI_ABORT` banner, can land between them and split the line.
pub fn print_error(message: &str) {
    let line = format!("{message}\n");
    let _ = std::io::stderr().lock().write_all(line.as_bytes());
}

/// What every phase of a run needs: the communicator and the log.
pub struct Context {
    /// The communicator the run uses (the world, for a plain run).
    pub comm: SimpleCommunicator,
    /// This rank.
    pub rank: usize,
    /// Number of ranks.
    pub size: usize,
    /// Rank-aware log.
    pub log: Log,
}

impl Context {
    /// A context over `comm`.
    pub fn new(comm: SimpleCommunicator, quiet: bool) -> Context {
        let rank = comm.rank() as usize;
        let size = comm.size() as usize;
        Context { comm, rank, size, log: Log::new(rank as i32, quiet) }
    }
}

/// Collective. Σ over the ranks of `ctx` of each rank's `x`.
pub fn global_sum(ctx: &Context, x: f64) -> f64 {
    use mpi::collective::SystemOperation;
    use mpi::traits::CommunicatorCollectives;
    let mut out = 0.0;
    ctx.comm.all_reduce_into(&x, &mut out, SystemOperation::sum());
    out
}

/// Collective. Whether `local` holds on every rank of `ctx` (a logical and).
pub fn all_ranks(ctx: &Context, local: bool) -> bool {
    use mpi::collective::SystemOperation;
    use mpi::traits::CommunicatorCollectives;
    let mut all = local;
    ctx.comm.all_reduce_into(&local, &mut all, SystemOperation::logical_and());
    all
}
