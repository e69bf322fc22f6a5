//! Progress of the time history on rank 0: a log line every few seconds (step, time,
//! iterations, residual, ETA), and when standard error is a terminal, a status line redrawn in
//! place between them.
use crate::parallel::Log;
use std::io::{IsTerminal, Write};
// A progress clock (ETA, spacing of the log lines), not a phase timer: the phases are
// timed by the driver (`parallel::Phases`).
use std::time::Instant;

/// Progress reporter.
pub struct Progress {
    start: Instant,
    last_line: Instant,
    first_step: usize,
    total: usize,
    every_seconds: f64,
    tty: bool,
}

impl Progress {
    /// For steps `first_step..total`, a log line at most every `every_seconds`.
    pub fn new(log: &Log, first_step: usize, total: usize, every_seconds: f64) -> Progress {
        let now = Instant::now();
        Progress {
            start: now,
            last_line: now,
            first_step,
            total,
            every_seconds,
            tty: log.is_root() && std::io::stderr().is_terminal(),
        }
    }

    /// Estimated seconds left after `step` steps.
    pub fn eta(&self, step: usize) -> f64 {
        let done = step.saturating_sub(self.first_step).max(1) as f64;
        self.start.elapsed().as_secs_f64() / done * self.total.saturating_sub(step) as f64
    }

    /// Reports step `step` at time `t`.
    pub fn step(&mut self, log: &Log, step: usize, t: f64, iterations: usize, substeps: usize, residual: f64) {
        let line = format!(
            "step {step}/{} t = {t:.4} s: {iterations} iteration(s){}, residual {residual:.2e}, ETA {:.0} s",
            self.total,
            if substeps > 1 { format!(" in {substeps} substeps") } else { String::new() },
            self.eta(step)
        );
        if self.last_line.elapsed().as_secs_f64() >= self.every_seconds || step == self.total || substeps > 1 {
            if self.tty {
                eprint!("\r\x1b[2K");
            }
            log.info(&line);
            self.last_line = Instant::now();
        } else if self.tty {
            let bar = (40 * step / self.total.max(1)).min(40);
            eprint!("\r\x1b[2K[{}{}] {line}", "#".repeat(bar), " ".repeat(40 - bar));
            let _ = std::io::stderr().flush();
        }
    }
}
