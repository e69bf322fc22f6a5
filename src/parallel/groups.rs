//! Groups of ranks that each run one task at a time on their own communicator, under dynamic
//! scheduling: the members of a sweep, each a parallel time history. Groups of 1 rank on a
//! workstation, of 16–64 on a cluster node.
//!
//! ```text
//!  world      ranks 0 … n−1, split by rank / size into groups 0 … n/size − 1
//!  group g    its own communicator: the task's collectives (PETSc, HDF5, agreement) run there
//!  leaders    rank 0 of every group; world rank 0 (group 0's leader) keeps the task counter
//! ```
//!
//! Protocol, on the leaders' communicator: a leader wanting work sends READY to leader 0 and
//! waits for a task index or STOP. Leader 0 first waits for every other leader's first READY and
//! hands them the first tasks, then takes one itself (so no group idles while leader 0 computes
//! a first task that has no hook, e.g. a gravity state); after that it answers whenever it polls
//! ([`Dispatcher::serve`]): when its own group asks for a task, and after every step of its own
//! group's time history (a hook of the time stepping), so that a waiting leader waits at most one
//! of leader 0's steps (or one of its tasks without steps). Every leader broadcasts its answer in
//! its group. With Threading::Funneled, so no thread of its own:
//! leader 0 computes and schedules on its main thread.
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::{Color, SimpleCommunicator};
use mpi::traits::{Communicator, Root};

const TAG_READY: i32 = 7201;
const TAG_TASK: i32 = 7202;
const STOP: u64 = u64::MAX;

/// A world split into groups of equal size.
pub struct Groups {
    /// This rank's group.
    pub group: SimpleCommunicator,
    /// The leaders' communicator (on group leaders only).
    leaders: Option<SimpleCommunicator>,
    /// This rank's group index.
    pub index: usize,
    /// Number of groups.
    pub count: usize,
}

impl Groups {
    /// Collective over `world`. Splits it into groups of `size` consecutive ranks; `size` must
    /// divide the rank count (the error says so, with both numbers).
    pub fn split(world: &SimpleCommunicator, size: usize) -> Result<Groups, String> {
        let n = world.size() as usize;
        if size == 0 || n % size != 0 {
            return Err(format!(
                "a group size of {size} rank(s) does not divide the {n} rank(s) of the run: use a divisor of {n}, or run on a multiple of {size} ranks"
            ));
        }
        let rank = world.rank() as usize;
        let index = rank / size;
        let group = world
            .split_by_color(Color::with_value(index as i32))
            .ok_or_else(|| "the group communicator could not be created".to_string())?;
        let is_leader = group.rank() == 0;
        let leaders = world.split_by_color(if is_leader { Color::with_value(0) } else { Color::undefined() });
        if is_leader && leaders.is_none() {
            return Err("the leaders' communicator could not be created".into());
        }
        Ok(Groups { group, leaders, index, count: n / size })
    }
}

/// Hands out task indices to groups, in a given order, one at a time to whichever group asks.
pub struct Dispatcher<'g> {
    groups: &'g Groups,
    /// Task indices still to hand out, next last (leader 0 only).
    queue: Vec<usize>,
    /// Remote leaders told to stop (leader 0 only).
    stopped: usize,
    /// Whether every remote leader has had its first answer (leader 0 only).
    started: bool,
}

impl<'g> Dispatcher<'g> {
    /// Tasks handed out in `order`.
    pub fn new(groups: &'g Groups, order: &[usize]) -> Dispatcher<'g> {
        Dispatcher { groups, queue: order.iter().rev().copied().collect(), stopped: 0, started: false }
    }

    fn is_root(&self) -> bool {
        self.groups.leaders.as_ref().is_some_and(|l| l.rank() == 0)
    }

    fn take(&mut self) -> u64 {
        self.queue.pop().map_or(STOP, |k| k as u64)
    }

    /// Collective over the group. The next task of this group, or `None` when none is left.
    pub fn next_task(&mut self) -> Option<usize> {
        let mut k = STOP;
        if let Some(l) = &self.groups.leaders {
            if l.rank() == 0 {
                if !self.started {
                    self.first_round();
                }
                self.serve();
                k = self.take();
            } else {
                let root = l.process_at_rank(0);
                root.send_with_tag(&[0u8; 0][..], TAG_READY);
                k = root.receive_with_tag::<u64>(TAG_TASK).0;
            }
        }
        self.groups.group.process_at_rank(0).broadcast_into(&mut k);
        (k != STOP).then_some(k as usize)
    }

    /// Leader 0: waits for the first READY of every other leader and answers each (the first
    /// tasks go to the other groups).
    fn first_round(&mut self) {
        let remote = self.groups.count - 1;
        for _ in 0..remote {
            let Some(l) = &self.groups.leaders else { return };
            let (_, status) = l.any_process().receive_vec_with_tag::<u8>(TAG_READY);
            let k = self.take();
            if k == STOP {
                self.stopped += 1;
            }
            if let Some(l) = &self.groups.leaders {
                l.process_at_rank(status.source_rank()).send_with_tag(&k, TAG_TASK);
            }
        }
        self.started = true;
    }

    /// Leader 0: answers every request waiting now, without blocking. Elsewhere nothing.
    pub fn serve(&mut self) {
        if !self.is_root() {
            return;
        }
        while let Some((msg, status)) =
            self.groups.leaders.as_ref().and_then(|l| l.any_process().immediate_matched_probe_with_tag(TAG_READY))
        {
            let _: (Vec<u8>, _) = (msg, status).matched_receive_vec();
            let k = self.take();
            if k == STOP {
                self.stopped += 1;
            }
            if let Some(l) = &self.groups.leaders {
                l.process_at_rank(status.source_rank()).send_with_tag(&k, TAG_TASK);
            }
        }
    }

    /// Leader 0: serves until every other leader has been told to stop (call after this group's
    /// own `next_task` returned `None`). Elsewhere nothing.
    pub fn finish(&mut self) {
        if !self.is_root() {
            return;
        }
        if !self.started {
            self.first_round();
        }
        let remote = self.groups.count - 1;
        while self.stopped < remote {
            self.serve();
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
    }
}
