//! Embarrassingly parallel batches with dynamic scheduling: virtual tests of many samples,
//! the design points of an identification. Tasks differ in cost (a sample that cracks early
//! stops early), so tasks are handed out one at a time to whichever rank is free.
//!
//! Protocol (rank 0 schedules; every rank computes):
//!
//! ```text
//!  rank 0, main thread     : serves requests: receives (result of task k | "ready") from rank r,
//!                            replies with the next task index or STOP
//!  rank 0, worker thread   : takes task indices from the same counter and computes them
//!                            (it makes no MPI call: MPI is initialized with Threading::Funneled)
//!  rank r > 0              : "ready" → task k → compute → result of k (also a request) → ...
//! ```
//!
//! Results travel as JSON bytes, so any `Serialize` result works; they are returned on rank 0
//! in task order. A task that fails returns its message as `Err` in its slot; the batch goes on.
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::SimpleCommunicator;
use mpi::traits::Communicator;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

const TAG_READY: i32 = 7101;
const TAG_RESULT: i32 = 7102;
const TAG_TASK: i32 = 7103;
const STOP: u64 = u64::MAX;

/// The outcome of one task: its result, or the message of its failure.
pub type TaskResult<R> = Result<R, String>;

/// Errors of the batch machinery itself (not of the tasks).
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// A result could not be encoded or decoded.
    #[error("batch: task {task}: cannot transfer its result: {message}")]
    Transfer {
        /// The task.
        task: usize,
        /// What serde said.
        message: String,
    },
}

/// Collective. Runs tasks `0..n_tasks` with `work` over all ranks of `comm`, dynamically
/// scheduled. Rank 0 gets `Some(results)` in task order (and `progress(done, total)` after each
/// result arrives); other ranks get `None`.
pub fn run_batch<R, F, P>(
    comm: &SimpleCommunicator,
    n_tasks: usize,
    work: F,
    mut progress: P,
) -> Result<Option<Vec<TaskResult<R>>>, BatchError>
where
    R: Serialize + DeserializeOwned + Send,
    F: Fn(usize) -> TaskResult<R> + Sync,
    P: FnMut(usize, usize),
{
    let encode = |task: usize, r: &TaskResult<R>| -> Result<Vec<u8>, BatchError> {
        let mut bytes = (task as u64).to_le_bytes().to_vec();
        let body = serde_json::to_vec(r).map_err(|e| BatchError::Transfer { task, message: e.to_string() })?;
        bytes.extend(body);
        Ok(bytes)
    };
    if comm.rank() != 0 {
        let root = comm.process_at_rank(0);
        root.send_with_tag(&[0u8; 0][..], TAG_READY);
        loop {
            let (task, _) = root.receive_with_tag::<u64>(TAG_TASK);
            if task == STOP {
                return Ok(None);
            }
            let k = task as usize;
            let r = work(k);
            root.send_with_tag(&encode(k, &r)?[..], TAG_RESULT);
        }
    }

    // Rank 0.
    let next = AtomicUsize::new(0);
    let slots: Mutex<Vec<Option<TaskResult<R>>>> = Mutex::new((0..n_tasks).map(|_| None).collect());
    let done = AtomicUsize::new(0);
    let n_remote = (comm.size() - 1) as usize;
    let mut outcome: Result<(), BatchError> = Ok(());
    std::thread::scope(|s| {
        // The local worker: no MPI calls here.
        s.spawn(|| loop {
            let k = next.fetch_add(1, Ordering::SeqCst);
            if k >= n_tasks {
                break;
            }
            let r = work(k);
            if let Ok(mut v) = slots.lock() {
                v[k] = Some(r);
            }
            done.fetch_add(1, Ordering::SeqCst);
        });
        // The scheduler: serve remote ranks until each has been told to stop and the local
        // worker has finished, reporting progress as results come in from either.
        let mut stopped = 0;
        let mut reported = 0;
        while stopped < n_remote || done.load(Ordering::SeqCst) < n_tasks.min(next.load(Ordering::SeqCst)) {
            let d = done.load(Ordering::SeqCst);
            if d > reported {
                reported = d;
                progress(d, n_tasks);
            }
            let Some(probed) = comm.any_process().immediate_matched_probe() else {
                std::thread::sleep(std::time::Duration::from_millis(2));
                continue;
            };
            let (msg, status) = probed.matched_receive_vec::<u8>();
            let from = comm.process_at_rank(status.source_rank());
            if status.tag() == TAG_RESULT && msg.len() >= 8 {
                let mut id = [0u8; 8];
                id.copy_from_slice(&msg[..8]);
                let k = u64::from_le_bytes(id) as usize;
                match serde_json::from_slice::<TaskResult<R>>(&msg[8..]) {
                    Ok(r) => {
                        if let Ok(mut v) = slots.lock() {
                            if k < n_tasks {
                                v[k] = Some(r);
                            }
                        }
                    }
                    Err(e) => {
                        outcome = Err(BatchError::Transfer { task: k, message: e.to_string() });
                    }
                }
                done.fetch_add(1, Ordering::SeqCst);
            }
            let k = next.fetch_add(1, Ordering::SeqCst);
            if k < n_tasks {
                from.send_with_tag(&(k as u64), TAG_TASK);
            } else {
                from.send_with_tag(&STOP, TAG_TASK);
                stopped += 1;
            }
        }
        // Remote ranks are done; the local worker finishes what it took.
    });
    outcome?;
    // A worker that panicked poisons the lock: keep the results it did store (the missing ones
    // are reported per task below) rather than lose them all.
    let v = slots.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner());
    Ok(Some(
        v.into_iter()
            .enumerate()
            .map(|(k, r)| r.unwrap_or_else(|| Err(format!("task {k} produced no result"))))
            .collect(),
    ))
}
