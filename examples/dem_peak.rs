//! Why a DEM virtual test stops: runs samples of a DEM job file one by one (no MPI) with the
//! Newton history kept ([`masonry_hpc::dem::solver::trace`]) and prints, per sample, how it
//! ended, the last recorded states and the residual history of the last equilibrium attempts.
//!
//!     target/release/examples/dem_peak jobs/wall-compression.toml 1 3 8   # samples 1, 3, 8
//!     target/release/examples/dem_peak jobs/wall-compression.toml         # every sample
//!
//! `DEM_TRACE=0` leaves the history out (only the endings and seconds); `DEM_CONTINUATION=0`
//! turns the pseudo-transient continuation off (`SolverOptions::continuation`).
use masonry_hpc::config::{load_job, AnyJob};
use masonry_hpc::dem::sample::Sample;
use masonry_hpc::dem::solver::{run_test_with, SolverOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).ok_or("usage: dem_peak <dem job.toml> [sample ...]")?;
    let AnyJob::Dem(job) = load_job(std::path::Path::new(path))? else {
        return Err(format!("{path}: not a DEM job").into());
    };
    let mut which: Vec<usize> = args[2..].iter().map(|a| a.parse()).collect::<Result<_, _>>()?;
    if which.is_empty() {
        which = (0..job.spec.analysis.samples).collect();
    }
    let trace = std::env::var("DEM_TRACE").map_or(true, |v| v != "0");
    for k in which {
        let mut cfg = job.spec.sample.clone();
        cfg.seed = job.spec.sample.seed.wrapping_add(k as u64);
        let sample = Sample::build(&cfg)?;
        let continuation = std::env::var("DEM_CONTINUATION").map_or(true, |v| v != "0");
        let opts = SolverOptions { trace, continuation, ..Default::default() };
        let r = run_test_with(&sample, &job.params, &job.spec.test, opts)?;
        let peak = r.derived.peak_stress;
        let last = r.curve.last().map_or(0.0, |c| c.stress.abs());
        println!(
            "sample {k}: {:?}; {} events, {} cut-backs, {} continued steps, {} continuations, {:.2} s; peak {:.4} MPa at {:.3e}, last {:.4} MPa ({:.1} % of peak)",
            r.end,
            r.stats.events,
            r.stats.cutbacks,
            r.stats.continued_steps,
            r.stats.continuations,
            r.stats.seconds,
            peak / 1e6,
            r.derived.strain_at_peak,
            last / 1e6,
            100.0 * last / peak.max(1e-300)
        );
        if trace {
            for c in r.curve.iter().rev().take(6).collect::<Vec<_>>().into_iter().rev() {
                println!(
                    "  state {:4} {:?} strain {:.5e} stress {:.4} MPa broken {:?}",
                    c.state,
                    c.kind,
                    c.strain,
                    c.stress / 1e6,
                    c.broken
                );
            }
            if let Some(t) = &r.trace {
                print!("{}", t.report());
            }
        }
    }
    Ok(())
}
