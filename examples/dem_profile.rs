//! Where a DEM compression test of a random sample spends its time: runs the event-driven solver
//! on N random stones (seed 7, 1 m × 1 m, default parameters) in compression to `max_strain` in
//! `steps` load steps, and prints one JSON line with the events, the wall time, the solver's
//! profile ([`masonry_hpc::dem::solver::SolverProfile`]: Newton and GMRES iterations, Woodbury
//! columns, refactorizations by cause, seconds per phase), the peak stress and E.
//!
//!     target/release/examples/dem_profile 1000 2e-3 40 [curve.csv]
//!
//! `DEM_SEED=k` places the stones with seed k instead of 7.
//! `DEM_MAX_EVENTS=N` stops after N beam breaks (the profile of the start of a long run).
//! `DEM_JACOBIAN_REUSE=0.01` reuses a contact's Jacobian while it has moved by less than 1 % of
//! its penetration (default 0: every Jacobian exact at every Newton iteration,
//! `dem::solver::tangent`).
//!
//! `DEM_SLIP_TERMS=s:n` keeps the share `s` of a sliding contact's `k_t c cᵀ` in the
//! preconditioner, a stick/slip flip reaching the factor after `n` more Newton iterations in its
//! new regime (`SolverOptions::slip_terms`, `dem::solver::slip_terms`); `DEM_SLIP_TERMS=1`:
//! every contact keeps `k_t c cᵀ`; `DEM_SLIP_TERMS=0`: sliding contacts keep none, flips at once;
//! `DEM_FORCING=1e-8` fixes the linear tolerance of Newton steps (default: Eisenstat–Walker),
//! `DEM_FORCING=ew:0.01` sets Eisenstat–Walker's `η_max`.
//! `DEM_BROKEN_CSV=path` writes the broken beams in order (event, beam, mode, state).
//! `DEM_CONTACTS=0` runs without contacts between unbonded stones (the lattice alone: the
//! linear phase of the algorithm throughout, `dem::solver::linear`).
//! `DEM_UPDOWN=1` keeps the factor current by CHOLMOD's updates and downdates in place
//! (`dem::solver::cholmod`), `DEM_UPDOWN=0` by Woodbury columns and refactorizations; unset,
//! the solver's default chooses by size (`dem::solver::FactorUpdates::Auto`: in place from
//! 1,000 unknowns, every sample of the benchmarks).
//! `DEM_SPARSE_RHS=0` solves every contact-free Newton step densely (default, with updates in
//! place: a sparse residual by a forward substitution over its reach,
//! `dem::solver::factor`).
//! `DEM_LINEAR=0` finds every equilibrium by Newton's method, also without contacts (the
//! former path; default: one solve, `dem::solver::linear`).
//! `DEM_FILL=x` (with `DEM_UPDOWN=1`) refactorizes once the fill that updates brought has cost
//! x factorizations (`SolverOptions::fill_refactor`; `inf`: never).
//! `DEM_REFRESH=0.2` replaces a contact term of the factorized operator once it drifted by more
//! than that fraction from the contact's current one (`SolverOptions::refresh_drift`).
//! `DEM_BREAKS=n` breaks up to n beams per equilibrium (`SolverOptions::breaks_per_equilibrium`,
//! an approximation; default 1, the exact algorithm).
//! `DEM_TOL=x` sets the relative residual tolerance of every equilibrium (`SolverOptions::tol`,
//! default 1e-8).
//! `DEM_TRACE=1` keeps the Newton history of the last equilibrium attempts and prints it to
//! stderr when the test stops on an error (`dem::solver::trace`).
//! `DEM_BREAK_SEARCH=tangent` predicts each load step's first break from one tangent solve and
//! solves the equilibrium at the break only (`SolverOptions::break_search`,
//! `dem::solver::break_search`; default `trial`: the step's end first; `trial_landed`: the
//! step's end first, each break then landed on P = 1 as the search's are).
//! `DEM_PRECONDITIONER_COPY=0` applies GMRES's preconditioner with CHOLMOD's factor throughout;
//! `DEM_PRECONDITIONER_COPY=n` with its `f32` supernodal copy from n entries of the factor on
//! (default 800,000, about 5,000 stones; `SolverOptions::preconditioner_copy_from`,
//! `dem::solver::supernodes`).
//! `DEM_PREDICT=0` starts every load step from the committed state (no step predictor,
//! `dem::solver::step_predictor`).
//!
//! The profile's `phases` splits the Newton and GMRES iterations, the Jacobians and the
//! evaluations by what each equilibrium was solved for (trial, λ*, release, cascade, cut-back;
//! `dem::solver::phases`) and keeps GMRES iterations against the sliding contacts.
//!
//! Progress goes to stderr every 25 recorded states (with the Newton and GMRES iterations by
//! phase so far: differences between two lines give a stretch of the run). With a fourth argument the curve (state, strain, stress in Pa, broken beams) is written there.
use std::io::Write;
use std::time::Instant;

use masonry_hpc::dem::mechanics::MechParams;

#[path = "common/random_sample.rs"]
mod random_sample;
use masonry_hpc::dem::solver::gmres::Forcing;
use masonry_hpc::dem::solver::{
    BreakSearch, DofControl, DofMap, FactorUpdates, LoadPoint, Model, Observer, SlipTerms, Solver, SolverOptions,
    SolverProfile, StageEnd, StateRecord,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1000);
    let max_strain: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(2e-3);
    let steps: usize = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(40);
    // DEM_SEED=k places the stones with seed k (default 7, the benchmarks' sample).
    let seed = match std::env::var("DEM_SEED") {
        Ok(v) => v.parse().map_err(|e| format!("DEM_SEED={v}: {e}"))?,
        Err(_) => 7,
    };
    let sample = random_sample::random_square_seeded(n, seed)?;
    let mut params = MechParams::default();
    // DEM_CRUSHING=σ_c:G_c (Pa, J/m²) turns crushing on (a compressive peak).
    if let Ok(v) = std::env::var("DEM_CRUSHING") {
        let (s, g) = v.split_once(':').ok_or_else(|| format!("DEM_CRUSHING={v}: expected stress:energy"))?;
        let num = |x: &str| x.parse::<f64>().map_err(|e| format!("DEM_CRUSHING={v}: {e}"));
        params.crushing = Some(masonry_hpc::dem::mechanics::Crushing { stress: num(s)?, energy: num(g)? });
    }
    let map = DofMap::new(&sample, [[DofControl::Prescribed; 3]; 2])?;
    let model = Model::new(&sample, &params, map)?;
    let n_eq = model.map.n_eq();
    let zero = LoadPoint { prescribed: vec![0.0; 6], forces: vec![] };
    let target = LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 0.0, -max_strain * sample.height, 0.0], forces: vec![] };
    let clock = Instant::now();
    // DEM_MAX_EVENTS stops the test after that many beam breaks (the profile of a part of a long
    // run: the line then says "stopped: ... events").
    let mut opts = SolverOptions::default();
    if let Ok(v) = std::env::var("DEM_MAX_EVENTS") {
        opts.max_events = v.parse().map_err(|e| format!("DEM_MAX_EVENTS={v}: {e}"))?;
    }
    if let Ok(v) = std::env::var("DEM_CONTACTS") {
        opts.contacts = v != "0";
    }
    if let Ok(v) = std::env::var("DEM_UPDOWN") {
        opts.factor_updates = if v == "0" { FactorUpdates::Woodbury } else { FactorUpdates::InPlace };
    }
    if let Ok(v) = std::env::var("DEM_LINEAR") {
        opts.linear_phase = v != "0";
    }
    if let Ok(v) = std::env::var("DEM_SPARSE_RHS") {
        opts.sparse_rhs = v != "0";
    }
    if let Ok(v) = std::env::var("DEM_PREDICT") {
        opts.predict_steps = v != "0";
    }
    if let Ok(v) = std::env::var("DEM_BREAKS") {
        opts.breaks_per_equilibrium = v.parse().map_err(|e| format!("DEM_BREAKS={v}: {e}"))?;
    }
    if let Ok(v) = std::env::var("DEM_FILL") {
        opts.fill_refactor = v.parse().map_err(|e| format!("DEM_FILL={v}: {e}"))?;
    }
    if let Ok(v) = std::env::var("DEM_REFRESH") {
        opts.refresh_drift = v.parse().map_err(|e| format!("DEM_REFRESH={v}: {e}"))?;
    }
    if let Ok(v) = std::env::var("DEM_SLIP_TERMS") {
        opts.slip_terms = match v.split_once(':') {
            Some((share, lag)) => SlipTerms {
                share: share.parse().map_err(|e| format!("DEM_SLIP_TERMS={v}: {e}"))?,
                lag: lag.parse().map_err(|e| format!("DEM_SLIP_TERMS={v}: {e}"))?,
            },
            None if v == "0" => SlipTerms::STICK_ONLY,
            None => SlipTerms::FULL,
        };
    }
    if let Ok(v) = std::env::var("DEM_FORCING") {
        let num = |x: &str| x.parse::<f64>().map_err(|e| format!("DEM_FORCING={v}: {e}"));
        opts.forcing = match v.strip_prefix("ew:") {
            Some(eta_max) => match opts.forcing {
                Forcing::EisenstatWalker { gamma, alpha, eta_min, .. } => {
                    Forcing::EisenstatWalker { gamma, alpha, eta_max: num(eta_max)?, eta_min }
                }
                f => f,
            },
            None => Forcing::Fixed(num(&v)?),
        };
    }
    if let Ok(v) = std::env::var("DEM_TOL") {
        opts.tol = v.parse().map_err(|e| format!("DEM_TOL={v}: {e}"))?;
    }
    if let Ok(v) = std::env::var("DEM_BREAK_SEARCH") {
        opts.break_search = match v.as_str() {
            "tangent" => BreakSearch::Tangent,
            "trial" => BreakSearch::Trial,
            "trial_landed" => BreakSearch::TrialLanded,
            _ => return Err(format!("DEM_BREAK_SEARCH={v}: expected trial, trial_landed or tangent").into()),
        };
    }
    if let Ok(v) = std::env::var("DEM_TRACE") {
        opts.trace = v != "0";
    }
    if let Ok(v) = std::env::var("DEM_PRECONDITIONER_COPY") {
        opts.preconditioner_copy_from = match v.as_str() {
            "0" => usize::MAX,
            _ => v.parse().map_err(|e| format!("DEM_PRECONDITIONER_COPY={v}: {e}"))?,
        };
    }
    let settings = format!(
        "tol={} slip_terms={:?} forcing={:?} contacts={} linear_phase={} sparse_rhs={} factor_updates={:?} fill_refactor={} refresh_drift={} breaks_per_equilibrium={} break_search={:?} preconditioner_copy_from={}",
        opts.tol, opts.slip_terms, opts.forcing, opts.contacts, opts.linear_phase, opts.sparse_rhs, opts.factor_updates, opts.fill_refactor, opts.refresh_drift,
        opts.breaks_per_equilibrium,
        opts.break_search,
        opts.preconditioner_copy_from
    );
    let breaks_per_equilibrium = opts.breaks_per_equilibrium;
    let mut solver = Solver::new(model, opts, zero)?;
    // DEM_JACOBIAN_REUSE sets the reuse threshold of contact Jacobians (0: recompute each time).
    if let Ok(v) = std::env::var("DEM_JACOBIAN_REUSE") {
        solver.set_jacobian_reuse(v.parse().map_err(|e| format!("DEM_JACOBIAN_REUSE={v}: {e}"))?)?;
    }
    // Progress on stderr every 25 recorded states: a run stopped by a time limit still says how
    // far it got, and the profile's counters and phase seconds so far say where each stretch of
    // the run went (differences between two lines).
    let area = sample.width * params.t_z;
    solver.diag.observer =
        Some(Box::new(Progress { clock, height: sample.height, area, peak: 0.0, line: String::new() }));
    let end = solver.start().and_then(|()| solver.run_stage(&target, steps, Some((1, 1))));
    let seconds = clock.elapsed().as_secs_f64();
    let end = match end {
        Ok(StageEnd::Completed) => "target".to_string(),
        Ok(StageEnd::LossOfLoad) => "loss_of_load".to_string(),
        Err(e) => {
            if let Some(tr) = solver.diag.trace.as_ref() {
                eprintln!("{}", tr.report());
            }
            format!("stopped: {e}")
        }
    };
    let curve: Vec<(f64, f64, usize)> = solver
        .states()
        .iter()
        .map(|s| (s.platen[1][1] / sample.height, s.platen_force[1][1] / area, s.broken[0]))
        .collect();
    let peak = curve.iter().fold(0.0f64, |m, c| m.max(c.1.abs()));
    let strain_at_peak = curve.iter().find(|c| c.1.abs() == peak).map_or(0.0, |c| c.0.abs());
    // The energy account of the last state: external work, stored, dissipated (fracture,
    // friction, relaxation, crushing), J.
    let energy = solver.states().last().map(|s| (s.external_work, s.stored, s.dissipated));
    let e = curve.iter().find(|c| c.0 != 0.0).map_or(0.0, |c| c.1 / c.0);
    if let Some(path) = args.get(4) {
        let mut f = std::fs::File::create(path)?;
        writeln!(f, "state,strain,stress,broken")?;
        for (k, c) in curve.iter().enumerate() {
            writeln!(f, "{k},{:.12e},{:.12e},{}", c.0, c.1, c.2)?;
        }
    }
    if let Ok(path) = std::env::var("DEM_BROKEN_CSV") {
        let mut f = std::fs::File::create(&path)?;
        writeln!(f, "event,beam,mode,state")?;
        for (k, b) in solver.broken().iter().enumerate() {
            writeln!(f, "{k},{},{:?},{}", b.beam, b.mode, b.state)?;
        }
    }
    let events = solver.broken().len();
    // Peak resident memory of the process (Linux: VmHWM in /proc/self/status), kB.
    let vm_hwm_kb: Option<u64> = std::fs::read_to_string("/proc/self/status").ok().and_then(|s| {
        s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
    });
    let line = serde_json::json!({
        "stones": sample.particles.len(), "equations": n_eq, "end": end, "events": events,
        "seconds": seconds, "events_per_second": events as f64 / seconds.max(1e-9),
        "peak_stress_pa": peak, "strain_at_peak": strain_at_peak, "e_pa": e,
        "external_work_j": energy.map(|e| e.0), "stored_j": energy.map(|e| e.1),
        "dissipated_j": energy.map(|e| e.2), "dissipated_total_j": energy.map(|e| e.2.iter().sum::<f64>()), "solves": solver.diag.counters.solves, "cutbacks": solver.diag.counters.cutbacks,
        "vm_hwm_kb": vm_hwm_kb, "breaks_per_equilibrium": breaks_per_equilibrium, "settings": settings, "factorizations": solver.factor_stats().0, "symbolic_analyses": solver.factor_stats().1, "profile": solver.diag.profile,
    });
    println!("{line}");
    Ok(())
}

/// Prints a progress line every 25 recorded states: strain, compressive stress (Pa) and the
/// largest so far, breaks, seconds, and the profile's counters and phase seconds so far (a run
/// stopped by hand keeps where its curve went).
struct Progress {
    clock: Instant,
    height: f64,
    /// The loaded section (width × thickness), for the stress.
    area: f64,
    /// The largest compressive stress recorded so far (Pa).
    peak: f64,
    line: String,
}

impl Observer for Progress {
    fn recorded(&mut self, k: usize, st: &StateRecord, _: &[f64]) {
        self.line.clear();
        let stress = -st.platen_force[1][1] / self.area;
        self.peak = self.peak.max(stress);
        if k % 25 == 0 {
            let s = self.clock.elapsed().as_secs_f64();
            self.line = format!(
                "progress: state {k} strain {:.4e} stress {stress:.6e} peak_so_far {:.6e} events {} seconds {s:.2} contacts {}",
                -st.platen[1][1] / self.height,
                self.peak,
                st.broken[0],
                st.contacts
            );
        }
    }

    fn profiled(&mut self, _: usize, p: &SolverProfile) {
        if !self.line.is_empty() {
            let ph = &p.phases;
            eprintln!(
                "{} refreshed {} newton {} gmres {} gmres_solves {} direct {} evaluations {} continuation {} \
                 s_solve {:.2} s_gmres {:.2} s_tangent {:.2} s_evaluate {:.2} s_factor {:.2} s_columns {:.2} \
                 s_failure {:.2} s_commit {:.2} factorizations {} entries {} {} sliding_at_gmres {} \
                 newton_by_phase {} {} {} {} {} gmres_by_phase {} {} {} {} {} trials_discarded {} slip_flips {} {}",
                self.line,
                p.refreshed_terms,
                p.newton_iterations,
                p.gmres_iterations,
                p.gmres_solves,
                p.direct_solves,
                p.evaluations,
                p.continuation_iterations,
                p.solve_seconds,
                p.gmres_seconds,
                p.tangent_seconds,
                p.evaluate_seconds,
                p.factor_seconds,
                p.columns_seconds,
                p.failure_seconds,
                p.commit_seconds,
                p.refactorizations.total(),
                p.factor_entries[0],
                p.factor_entries[1],
                p.sliding_at_gmres,
                ph.trial.newton_iterations,
                ph.lambda.newton_iterations,
                ph.release.newton_iterations,
                ph.cascade.newton_iterations,
                ph.cut_back.newton_iterations,
                ph.trial.gmres_iterations,
                ph.lambda.gmres_iterations,
                ph.release.gmres_iterations,
                ph.cascade.gmres_iterations,
                ph.cut_back.gmres_iterations,
                ph.trial_discarded,
                p.slip_flips[0],
                p.slip_flips[1]
            );
        }
    }
}
