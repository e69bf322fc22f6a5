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
//! in task order. A task that fails returns its typed error as `Err` in its slot; the batch goes on.
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

/// The outcome of one task: its result, or its error `E` (which crosses ranks as JSON).
pub type TaskResult<R, E> = Result<R, E>;

/// A task that produced no result (its worker panicked): the error in its slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize, thiserror::Error)]
#[error("task {task} produced no result")]
pub struct Unfinished {
    /// The task.
    pub task: usize,
}

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
pub fn run_batch<R, E, F, P>(
    comm: &SimpleCommunicator,
    n_tasks: usize,
    work: F,
    mut progress: P,
) -> Result<Option<Vec<TaskResult<R, E>>>, BatchError>
where
    R: Serialize + DeserializeOwned + Send,
    E: Serialize + DeserializeOwned + Send + From<Unfinished>,
    F: Fn(usize) -> TaskResult<R, E> + Sync,
    P: FnMut(usize, usize),
{
    if comm.rank() != 0 {
        work_for_root(comm, &work)?;
        return Ok(None);
    }
    let board = Board::new(n_tasks);
    let outcome = std::thread::scope(|s| {
        s.spawn(|| work_locally(&board, &work));
        // Remote ranks are done when `serve` returns; the local worker finishes what it took.
        serve(comm, &board, &mut progress)
    });
    outcome?;
    Ok(Some(board.results()))
}

/// A task's result as the bytes of a `TAG_RESULT` message: the task index (8 bytes, little
/// endian), then the result as JSON.
fn encode<R: Serialize, E: Serialize>(task: usize, r: &TaskResult<R, E>) -> Result<Vec<u8>, BatchError> {
    let mut bytes = (task as u64).to_le_bytes().to_vec();
    let body = serde_json::to_vec(r).map_err(|e| BatchError::Transfer { task, message: e.to_string() })?;
    bytes.extend(body);
    Ok(bytes)
}

/// The task index and the result of a `TAG_RESULT` message ([`encode`]'s bytes, at least 8).
fn decode<R: DeserializeOwned, E: DeserializeOwned>(msg: &[u8]) -> (usize, serde_json::Result<TaskResult<R, E>>) {
    let mut id = [0u8; 8];
    id.copy_from_slice(&msg[..8]);
    (u64::from_le_bytes(id) as usize, serde_json::from_slice::<TaskResult<R, E>>(&msg[8..]))
}

/// Rank r > 0: "ready", then task → compute → result (also a request) until rank 0 says STOP.
fn work_for_root<R: Serialize, E: Serialize>(
    comm: &SimpleCommunicator,
    work: &impl Fn(usize) -> TaskResult<R, E>,
) -> Result<(), BatchError> {
    let root = comm.process_at_rank(0);
    root.send_with_tag(&[0u8; 0][..], TAG_READY);
    loop {
        let (task, _) = root.receive_with_tag::<u64>(TAG_TASK);
        if task == STOP {
            return Ok(());
        }
        let k = task as usize;
        let r = work(k);
        root.send_with_tag(&encode(k, &r)?[..], TAG_RESULT);
    }
}

/// Rank 0's bookkeeping, shared by the scheduler and the local worker: the counter that hands
/// out task indices, the results by task, and how many have come in.
struct Board<R, E> {
    n_tasks: usize,
    /// The next task index to hand out (≥ `n_tasks`: none left).
    next: AtomicUsize,
    slots: Mutex<Vec<Option<TaskResult<R, E>>>>,
    /// Results come in (decoded or not).
    done: AtomicUsize,
}

impl<R, E: From<Unfinished>> Board<R, E> {
    /// No task handed out yet.
    fn new(n_tasks: usize) -> Self {
        Board {
            n_tasks,
            next: AtomicUsize::new(0),
            slots: Mutex::new((0..n_tasks).map(|_| None).collect()),
            done: AtomicUsize::new(0),
        }
    }

    /// The next task index (≥ `n_tasks`: none left).
    fn take(&self) -> usize {
        self.next.fetch_add(1, Ordering::SeqCst)
    }

    /// Keeps the result of task `k` (one out of range is dropped).
    fn store(&self, k: usize, r: TaskResult<R, E>) {
        if let Ok(mut v) = self.slots.lock() {
            if k < self.n_tasks {
                v[k] = Some(r);
            }
        }
    }

    /// Counts a result come in.
    fn count_done(&self) {
        self.done.fetch_add(1, Ordering::SeqCst);
    }

    /// Whether a task handed out has not reported yet.
    fn waiting(&self) -> bool {
        self.done.load(Ordering::SeqCst) < self.n_tasks.min(self.next.load(Ordering::SeqCst))
    }

    /// The results in task order; a task without one gets an `Err` saying so.
    fn results(self) -> Vec<TaskResult<R, E>> {
        // A worker that panicked poisons the lock: keep the results it did store (the missing ones
        // are reported per task below) rather than lose them all.
        let v = self.slots.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner());
        v.into_iter().enumerate().map(|(task, r)| r.unwrap_or_else(|| Err(E::from(Unfinished { task })))).collect()
    }
}

/// Rank 0's worker thread: takes task indices from the board and computes them until none is
/// left. It makes no MPI call.
fn work_locally<R, E: From<Unfinished>>(board: &Board<R, E>, work: &impl Fn(usize) -> TaskResult<R, E>) {
    loop {
        let k = board.take();
        if k >= board.n_tasks {
            break;
        }
        board.store(k, work(k));
        board.count_done();
    }
}

/// Rank 0's scheduler: serves remote ranks (stores the result a message carries, replies with
/// the next task or STOP) until each has been told to stop and the local worker has finished,
/// reporting progress as results come in from either. A result that cannot be decoded is the
/// batch's error, after the loop.
fn serve<R: DeserializeOwned, E: DeserializeOwned + From<Unfinished>>(
    comm: &SimpleCommunicator,
    board: &Board<R, E>,
    progress: &mut impl FnMut(usize, usize),
) -> Result<(), BatchError> {
    let n_remote = (comm.size() - 1) as usize;
    let mut outcome: Result<(), BatchError> = Ok(());
    let mut stopped = 0;
    let mut reported = 0;
    while stopped < n_remote || board.waiting() {
        let d = board.done.load(Ordering::SeqCst);
        if d > reported {
            reported = d;
            progress(d, board.n_tasks);
        }
        let Some(probed) = comm.any_process().immediate_matched_probe() else {
            std::thread::sleep(std::time::Duration::from_millis(2));
            continue;
        };
        let (msg, status) = probed.matched_receive_vec::<u8>();
        let from = comm.process_at_rank(status.source_rank());
        if status.tag() == TAG_RESULT && msg.len() >= 8 {
            match decode::<R, E>(&msg) {
                (k, Ok(r)) => board.store(k, r),
                (k, Err(e)) => outcome = Err(BatchError::Transfer { task: k, message: e.to_string() }),
            }
            board.count_done();
        }
        let k = board.take();
        if k < board.n_tasks {
            from.send_with_tag(&(k as u64), TAG_TASK);
        } else {
            from.send_with_tag(&STOP, TAG_TASK);
            stopped += 1;
        }
    }
    outcome
}
