//! `masonry-hpc`: the command-line driver.
//!
//! ```text
//! mpirun -n 2 masonry-hpc jobs/tower.toml [PETSc options...]
//! masonry-hpc check jobs/tower.toml
//! masonry-hpc check --strict jobs/tower.toml     # implausible values (units) are errors
//! masonry-hpc keys dem                            # every key of a DEM job file
//! masonry-hpc keys --markdown > docs/input.md     # the reference page of every job kind
//! ```
//!
//! MPI lives exactly as long as the `Universe` in `main`; PETSc is started inside the run and
//! finalized before the universe drops. An error every rank knows (bad input) is printed once by
//! rank 0 and all ranks exit with its code; an error only one rank has is printed by that rank,
//! which then aborts every rank (`MPI_Abort`), so a run never hangs.
use clap::{Parser, Subcommand};
use masonry_hpc::parallel::{print_error, Context};
use masonry_hpc::run::{self, Error};
use mpi::traits::Communicator;
use std::path::PathBuf;
use std::process::ExitCode;

/// Seismic assessment of historical masonry buildings: MPI-parallel finite elements.
#[derive(Parser, Debug)]
#[command(name = "masonry-hpc", version, about, args_conflicts_with_subcommands = true)]
#[command(after_help = "Examples:\n  mpirun -n 2 masonry-hpc jobs/tower.toml\n  \
    masonry-hpc jobs/tower.toml -ksp_type cg -pc_type gamg -ksp_rtol 1e-10\n  \
    masonry-hpc check jobs/tower.toml\n  \
    masonry-hpc --restart jobs/tower-earthquake.toml")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// The job file (TOML) to run.
    job: Option<PathBuf>,
    /// PETSc options (e.g. -ksp_type cg -pc_type gamg); they win over the job's [solver.petsc].
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, value_name = "PETSC_OPTIONS")]
    petsc: Vec<String>,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
    /// Continue a killed time history, sweep or DEM job from the checkpoints in its results folder.
    #[arg(long)]
    restart: bool,
    /// Treat the warnings of implausible input (units) as errors: exit code 2.
    #[arg(long, global = true)]
    strict: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Validate a job, its mesh and every file it references, without running it.
    Check {
        /// The job file.
        job: PathBuf,
    },
    /// Print every key of a kind of job file (or of all kinds): type, default, unit, meaning.
    Keys {
        /// A job kind (structural, sweep, record_set, spectrum, dem, identification,
        /// material_point) or an `[analysis] type`; all kinds when absent.
        kind: Option<String>,
        /// Write Markdown: the page docs/input.md.
        #[arg(long)]
        markdown: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(Command::Keys { kind, markdown }) = &cli.command {
        // No MPI: the keys come from the config types alone.
        return keys(kind.as_deref(), *markdown);
    }
    // Funneled: only the main thread calls MPI; batch runs compute on a second thread of rank 0.
    let Some((universe, threading)) = mpi::initialize_with_threading(mpi::Threading::Funneled) else {
        print_error("error: MPI could not be initialized (was it initialized twice?)");
        return ExitCode::from(70);
    };
    if threading < mpi::Threading::Funneled {
        print_error(&format!("error: the MPI library does not support MPI_THREAD_FUNNELED (got {threading:?})"));
        return ExitCode::from(70);
    }
    let ctx = Context::new(universe.world(), cli.quiet);
    let result = match (&cli.command, &cli.job) {
        (Some(Command::Check { job }), _) => check(&ctx, job, cli.strict),
        (Some(Command::Keys { .. }), _) => unreachable!("answered before MPI starts"),
        (None, Some(job)) => run::run_job_with(&ctx, job, &cli.petsc, cli.restart, cli.strict),
        (None, None) => {
            if ctx.rank == 0 {
                print_error("error: no job file given\n\nUsage: masonry-hpc <JOB> [PETSC_OPTIONS]...\n       masonry-hpc check <JOB>\n\nFor more information, try '--help'.");
            }
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Error::Agreed(a)) => {
            if ctx.rank == 0 {
                print_error(&format!("error: {}", a.message));
            }
            ExitCode::from(a.exit_code.clamp(1, 255) as u8)
        }
        Err(m @ (Error::Mechanism { .. } | Error::SingularStiffness(_))) => {
            // Found identically by every rank: one message.
            if ctx.rank == 0 {
                print_error(&format!("error: {m}"));
            }
            ExitCode::from(2)
        }
        Err(e) => {
            let code = e.exit_code();
            if ctx.size > 1 {
                print_error(&format!("error (rank {}): {e}", ctx.rank));
                ctx.comm.abort(code)
            }
            print_error(&format!("error: {e}"));
            ExitCode::from(code.clamp(1, 255) as u8)
        }
    }
}

fn check(ctx: &Context, job: &std::path::Path, strict: bool) -> Result<(), Error> {
    let what = run::check_job(ctx, job, strict)?;
    ctx.log.info(format!("check: OK — {what}"));
    Ok(())
}

/// `masonry-hpc keys [KIND] [--markdown]`: the keys of one kind or of all, on standard output.
fn keys(kind: Option<&str>, markdown: bool) -> ExitCode {
    use masonry_hpc::config::{all_keys, keys_markdown, keys_of, keys_text, kind_named, KIND_NAMES};
    let kinds = match kind {
        None => all_keys(),
        Some(name) => match kind_named(name) {
            Some(k) => vec![keys_of(k)],
            None => {
                let names: Vec<&str> = KIND_NAMES.iter().map(|(n, _)| *n).collect();
                print_error(&format!(
                    "error: unknown job kind '{name}', expected one of: {} (or an [analysis] type)",
                    names.join(", ")
                ));
                return ExitCode::from(2);
            }
        },
    };
    print!("{}", if markdown { keys_markdown(&kinds) } else { keys_text(&kinds) });
    ExitCode::SUCCESS
}
