//! The EGO loop over MPI ranks. Rank 0 owns the optimizer ([`super::ego::Ego`]); each round it
//! broadcasts a command — evaluate these points, stop, or fail with a message — and every rank
//! takes part in the dynamic batch (`parallel::run_batch`) that evaluates the points, each
//! point as `tasks_per_point` independent tasks (e.g. random DEM samples):
//!
//! ```text
//!  rank 0: design ─┐          ┌─ tell ─ ask ─┐          ┌─ tell ─ ask ─ … ─ Stop
//!                  └ bcast ── batch ─────────┴ bcast ── batch ─┘
//!  rank r:           bcast ── batch ───────────bcast ── batch ─ …       ─ Stop
//! ```
//! A failure on rank 0 (the surrogate) is broadcast as `Fail`, so no rank waits forever.
use super::ego::{Ego, EgoSettings};
use super::error::EvalError;
use super::error::IdentifyError;
use crate::parallel::{run_batch, Context};
use mpi::traits::{Communicator, Root};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// What rank 0 tells the others each round.
#[derive(Serialize, Deserialize)]
enum Command {
    Evaluate(Vec<Vec<f64>>),
    Stop,
    Fail(String),
}

/// Collective. `value` (given on rank 0) on every rank, through JSON bytes.
pub fn broadcast_json<T: Serialize + DeserializeOwned>(ctx: &Context, value: Option<&T>) -> Result<T, IdentifyError> {
    let root = ctx.comm.process_at_rank(0);
    let mut bytes = match value {
        Some(v) if ctx.rank == 0 => serde_json::to_vec(v).map_err(|e| IdentifyError::Batch(e.to_string()))?,
        _ => Vec::new(),
    };
    let mut len = bytes.len() as u64;
    root.broadcast_into(&mut len);
    bytes.resize(len as usize, 0);
    root.broadcast_into(&mut bytes[..]);
    serde_json::from_slice(&bytes).map_err(|e| IdentifyError::Batch(format!("broadcast: {e}")))
}

/// The outcome of one task of a search: its result, or why it has none.
pub type TaskResult<R> = crate::parallel::TaskResult<R, EvalError>;

/// One evaluated point with its tasks' raw results.
#[derive(Clone, Debug, Serialize)]
pub struct PointRecord<R> {
    /// The infill iteration (0 = design).
    pub iteration: usize,
    /// Unit-cube coordinates.
    pub unit: Vec<f64>,
    /// Objective, or why it failed.
    pub value: Result<f64, EvalError>,
    /// The tasks' results.
    pub tasks: Vec<TaskResult<R>>,
}

/// The record with the lowest objective among those that succeeded; an error naming the first
/// failure when none did.
pub fn best_record<R>(records: &[PointRecord<R>]) -> Result<&PointRecord<R>, IdentifyError> {
    records
        .iter()
        .filter_map(|r| r.value.as_ref().ok().map(|v| (r, *v)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(r, _)| r)
        .ok_or_else(|| IdentifyError::TooFewPoints {
            needed: 1,
            got: 0,
            first_failure: records
                .iter()
                .find_map(|r| r.value.as_ref().err())
                .map(|e| e.to_string())
                .unwrap_or_default(),
        })
}

/// Seconds between two progress lines of a batch of points.
const PROGRESS_SECONDS: f64 = 10.0;

/// Collective. Evaluates `points` (significant on rank 0) as `points × tasks_per_point` tasks
/// of a dynamic batch; rank 0 gets them grouped per point.
pub fn evaluate_points<R, W>(
    ctx: &Context,
    points: &[Vec<f64>],
    tasks_per_point: usize,
    work: &W,
) -> Result<Option<Vec<Vec<TaskResult<R>>>>, IdentifyError>
where
    R: Serialize + DeserializeOwned + Send,
    W: Fn(&[f64], usize) -> TaskResult<R> + Sync,
{
    let m = tasks_per_point.max(1);
    let n = points.len() * m;
    // A log line at most every PROGRESS_SECONDS (a batch of 16 points × 8 samples of the
    // paper's wall takes minutes), and at the end: a progress clock, not a phase timer.
    let mut last = std::time::Instant::now();
    let progress = |done: usize, total: usize| {
        if done == total || last.elapsed().as_secs_f64() >= PROGRESS_SECONDS {
            last = std::time::Instant::now();
            ctx.log.info(format!("  {done}/{total} runs done ({} point(s) × {m})", points.len()));
        }
    };
    let batch = run_batch(&ctx.comm, n, |t| work(&points[t / m], t % m), progress)
        .map_err(|e| IdentifyError::Batch(e.to_string()))?;
    Ok(batch.map(|all| {
        let mut grouped: Vec<Vec<TaskResult<R>>> = (0..points.len()).map(|_| Vec::with_capacity(m)).collect();
        for (t, r) in all.into_iter().enumerate() {
            grouped[t / m].push(r);
        }
        grouped
    }))
}

/// Collective. Runs EGO: the `design` (unit cube, rank 0's is used), then infill batches, each
/// point evaluated by `tasks_per_point` tasks of `work` and reduced to one objective value by
/// `reduce`. Rank 0 returns every point with its tasks; the others `None`.
#[allow(clippy::too_many_arguments)] // the search, its work and its reduction: each argument distinct
pub fn run_ego<R, W, F>(
    ctx: &Context,
    dim: usize,
    design: Vec<Vec<f64>>,
    settings: EgoSettings,
    tasks_per_point: usize,
    work: W,
    reduce: F,
    label: &str,
) -> Result<Option<Vec<PointRecord<R>>>, IdentifyError>
where
    R: Serialize + DeserializeOwned + Send + Clone,
    W: Fn(&[f64], usize) -> TaskResult<R> + Sync,
    F: Fn(&[f64], &[TaskResult<R>]) -> Result<f64, EvalError>,
{
    let mut ego = if ctx.rank == 0 { Some(Ego::new(dim, settings)?) } else { None };
    let mut records: Vec<PointRecord<R>> = Vec::new();
    let mut cmd = Command::Evaluate(design);
    loop {
        let c = broadcast_json(ctx, Some(&cmd))?;
        let points = match c {
            Command::Evaluate(p) => p,
            Command::Stop => break,
            Command::Fail(msg) => return Err(IdentifyError::Optimizer(msg)),
        };
        let results = evaluate_points(ctx, &points, tasks_per_point, &work)?;
        cmd = Command::Stop;
        if let (Some(ego), Some(results)) = (ego.as_mut(), results) {
            let iteration = ego.iteration();
            let values: Vec<Result<f64, EvalError>> = points.iter().zip(&results).map(|(p, r)| reduce(p, r)).collect();
            for ((p, r), v) in points.iter().zip(results).zip(&values) {
                records.push(PointRecord { iteration, unit: p.clone(), value: v.clone(), tasks: r });
            }
            ego.tell(&points, values);
            let best = ego.best().and_then(|b| b.value.clone().ok());
            ctx.log.info(format!(
                "{label}: iteration {iteration}: {} point(s) evaluated ({} in all), best objective {}",
                points.len(),
                records.len(),
                best.map_or("none yet".into(), |b| format!("{b:.6e}"))
            ));
            cmd = match ego.ask() {
                Ok(Some(p)) => Command::Evaluate(p),
                Ok(None) => Command::Stop,
                Err(e) => Command::Fail(e.to_string()),
            };
        }
    }
    Ok(if ctx.rank == 0 { Some(records) } else { None })
}

/// Collective. A sequence of evaluation rounds driven by rank 0: evaluate `first` (rank 0's),
/// each point as `tasks_per_point` tasks of `work`; then `next` (called on rank 0 only, with the
/// round's points and their tasks grouped per point) gives the next round's points, or `None` to
/// stop. An error of `next` is broadcast, so every rank returns it. The loop of [`run_ego`] for
/// searches that are not EGO (e.g. the elastic stage of the calibration, a 1-D root).
pub fn run_rounds<R, W, N>(
    ctx: &Context,
    first: Vec<Vec<f64>>,
    tasks_per_point: usize,
    work: W,
    mut next: N,
) -> Result<(), IdentifyError>
where
    R: Serialize + DeserializeOwned + Send,
    W: Fn(&[f64], usize) -> TaskResult<R> + Sync,
    N: FnMut(&[Vec<f64>], Vec<Vec<TaskResult<R>>>) -> Result<Option<Vec<Vec<f64>>>, IdentifyError>,
{
    let mut cmd = Command::Evaluate(first);
    loop {
        let points = match broadcast_json(ctx, Some(&cmd))? {
            Command::Evaluate(p) => p,
            Command::Stop => return Ok(()),
            Command::Fail(msg) => return Err(IdentifyError::Settings(msg)),
        };
        let results = evaluate_points(ctx, &points, tasks_per_point, &work)?;
        cmd = Command::Stop;
        if let Some(results) = results {
            cmd = match next(&points, results) {
                Ok(Some(p)) => Command::Evaluate(p),
                Ok(None) => Command::Stop,
                Err(e) => Command::Fail(e.to_string()),
            };
        }
    }
}
