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
//! of leader 0's steps (or one of its tasks without steps). Tasks come from a [`TaskSource`]: a
//! fixed order, or tasks decided from the results of earlier ones; a READY also says that the
//! leader's previous task is done, and a leader asking while the source waits for results in
//! flight is answered when they come. Every leader broadcasts its answer in its group. With Threading::Funneled, so no thread of its own:
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

/// Why the world cannot be split into groups.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GroupError {
    /// The group size does not divide the rank count.
    #[error(
        "a group size of {size} rank(s) does not divide the {ranks} rank(s) of the run: use a divisor of {ranks}, or run on a multiple of {size} ranks"
    )]
    Size {
        /// The group size.
        size: usize,
        /// The ranks of the run.
        ranks: usize,
    },
    /// MPI could not create a communicator.
    #[error("the {which} communicator could not be created")]
    Communicator {
        /// Which (`group`, `leaders'`).
        which: &'static str,
    },
}

impl Groups {
    /// Collective over `world`. Splits it into groups of `size` consecutive ranks; `size` must
    /// divide the rank count (the error says so, with both numbers).
    pub fn split(world: &SimpleCommunicator, size: usize) -> Result<Groups, GroupError> {
        let n = world.size() as usize;
        if size == 0 || n % size != 0 {
            return Err(GroupError::Size { size, ranks: n });
        }
        let rank = world.rank() as usize;
        let index = rank / size;
        let group =
            world.split_by_color(Color::with_value(index as i32)).ok_or(GroupError::Communicator { which: "group" })?;
        let is_leader = group.rank() == 0;
        let leaders = world.split_by_color(if is_leader { Color::with_value(0) } else { Color::undefined() });
        if is_leader && leaders.is_none() {
            return Err(GroupError::Communicator { which: "leaders'" });
        }
        Ok(Groups { group, leaders, index, count: n / size })
    }
}

/// What leader 0's source of tasks says when a group asks for work.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Answer {
    /// Run this task.
    Task(usize),
    /// Nothing now: tasks in flight will decide what comes next.
    Wait,
    /// Nothing left.
    Stop,
}

/// Leader 0's source of tasks: a fixed order ([`Dispatcher::new`]), or tasks decided from the
/// results of earlier ones (the hunt of a sweep). `finished` is called when the group that held a
/// task asks for its next one (its results are written by then).
pub trait TaskSource {
    /// The next task for a group asking now.
    fn next(&mut self) -> Answer;
    /// `task` is done.
    fn finished(&mut self, task: usize);
}

/// Tasks in a fixed order, next last.
struct Queue(Vec<usize>);

impl TaskSource for Queue {
    fn next(&mut self) -> Answer {
        self.0.pop().map_or(Answer::Stop, Answer::Task)
    }
    fn finished(&mut self, _: usize) {}
}

enum Tasks<'s> {
    Queue(Queue),
    Borrowed(&'s mut dyn TaskSource),
}

impl Tasks<'_> {
    fn get(&mut self) -> &mut dyn TaskSource {
        match self {
            Tasks::Queue(q) => q,
            Tasks::Borrowed(s) => &mut **s,
        }
    }
}

/// Hands out task indices to groups, one at a time to whichever group asks; a group that asks
/// while the source waits for results is answered when they come.
pub struct Dispatcher<'g> {
    groups: &'g Groups,
    /// Where tasks come from (leader 0 only).
    source: Tasks<'g>,
    /// The task each remote leader holds, by its rank among the leaders (leader 0 only).
    held: Vec<Option<usize>>,
    /// This group's task (leader 0 only).
    own: Option<usize>,
    /// Remote leaders waiting for an answer (leader 0 only).
    waiting: std::collections::VecDeque<i32>,
    /// Remote leaders told to stop (leader 0 only).
    stopped: usize,
    /// Whether every remote leader has had its first answer (leader 0 only).
    started: bool,
}

impl<'g> Dispatcher<'g> {
    /// Tasks handed out in `order`.
    pub fn new(groups: &'g Groups, order: &[usize]) -> Dispatcher<'g> {
        Dispatcher::with(groups, Tasks::Queue(Queue(order.iter().rev().copied().collect())))
    }

    /// Tasks from `source` (consulted on leader 0 only).
    pub fn with_source(groups: &'g Groups, source: &'g mut dyn TaskSource) -> Dispatcher<'g> {
        Dispatcher::with(groups, Tasks::Borrowed(source))
    }

    fn with(groups: &'g Groups, source: Tasks<'g>) -> Dispatcher<'g> {
        Dispatcher {
            groups,
            source,
            held: vec![None; groups.count],
            own: None,
            waiting: Default::default(),
            stopped: 0,
            started: false,
        }
    }

    fn is_root(&self) -> bool {
        self.groups.leaders.as_ref().is_some_and(|l| l.rank() == 0)
    }

    /// Collective over the group. The next task of this group, or `None` when none is left.
    pub fn next_task(&mut self) -> Option<usize> {
        let mut k = STOP;
        if let Some(l) = &self.groups.leaders {
            if l.rank() == 0 {
                k = self.next_own();
            } else {
                let root = l.process_at_rank(0);
                root.send_with_tag(&[0u8; 0][..], TAG_READY);
                k = root.receive_with_tag::<u64>(TAG_TASK).0;
            }
        }
        self.groups.group.process_at_rank(0).broadcast_into(&mut k);
        (k != STOP).then_some(k as usize)
    }

    /// Leader 0: its own group's next task, after the waiting remote groups had theirs; waits
    /// (serving) while the source waits for results.
    fn next_own(&mut self) -> u64 {
        if let Some(t) = self.own.take() {
            self.source.get().finished(t);
        }
        if !self.started {
            self.first_round();
        }
        loop {
            self.serve();
            if self.waiting.is_empty() {
                match self.source.get().next() {
                    Answer::Task(k) => {
                        self.own = Some(k);
                        return k as u64;
                    }
                    Answer::Stop => return STOP,
                    Answer::Wait => {}
                }
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
    }

    /// Leader 0: waits for the first READY of every other leader and answers them (the first
    /// tasks go to the other groups).
    fn first_round(&mut self) {
        let remote = self.groups.count - 1;
        for _ in 0..remote {
            let Some(l) = &self.groups.leaders else { return };
            let (_, status) = l.any_process().receive_vec_with_tag::<u8>(TAG_READY);
            self.waiting.push_back(status.source_rank());
        }
        self.answer();
        self.started = true;
    }

    /// Leader 0: answers the waiting leaders while the source has tasks (or says stop).
    fn answer(&mut self) {
        while let Some(&r) = self.waiting.front() {
            let k = match self.source.get().next() {
                Answer::Wait => return,
                Answer::Task(k) => {
                    self.held[r as usize] = Some(k);
                    k as u64
                }
                Answer::Stop => {
                    self.stopped += 1;
                    STOP
                }
            };
            self.waiting.pop_front();
            if let Some(l) = &self.groups.leaders {
                l.process_at_rank(r).send_with_tag(&k, TAG_TASK);
            }
        }
    }

    /// Leader 0: takes every request waiting now, without blocking, and answers what it can.
    /// Elsewhere nothing.
    pub fn serve(&mut self) {
        if !self.is_root() {
            return;
        }
        while let Some((msg, status)) =
            self.groups.leaders.as_ref().and_then(|l| l.any_process().immediate_matched_probe_with_tag(TAG_READY))
        {
            let _: (Vec<u8>, _) = (msg, status).matched_receive_vec();
            let r = status.source_rank();
            if let Some(t) = self.held[r as usize].take() {
                self.source.get().finished(t);
            }
            self.waiting.push_back(r);
        }
        self.answer();
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
