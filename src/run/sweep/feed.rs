//! The hunt's source of tasks, on world rank 0 (group 0's leader): one chain per material and
//! record (`hunt.rs`), each with one member in flight at most, the chains side by side, so that
//! the groups run the hunts of several records at once. A member's result is read from its
//! `outcome.json` when its group asks for its next task. On a restart the chains replay their
//! decisions from the outcomes on disk and go on where they stopped (a member killed mid-way is
//! handed out again and resumes from its checkpoint).
//!
//! A task is `chain << 40 | level on the 1e-4 lattice`, so that every rank of the receiving group
//! rebuilds the member from the number alone.
use super::hunt::{lattice_index, on_lattice, Chain, HuntEnd, Next, Response};
use super::member::member_dir;
use super::outcome::{Outcome, Status};
use crate::config::{HuntRules, Member, SweepJob};
use crate::parallel::{Answer, Log, TaskSource};
use std::path::Path;

const LEVEL_BITS: u32 = 40;

/// The member of task `k`.
pub fn member_of_task(job: &SweepJob, k: usize) -> Member {
    let chain = k >> LEVEL_BITS;
    let level = on_lattice((k & ((1 << LEVEL_BITS) - 1)) as f64 * crate::config::LEVEL_RESOLUTION);
    let (v, r) = (chain / job.records.len(), chain % job.records.len());
    job.member(0, v, r, level, None)
}

fn task_of(chain: usize, level: f64) -> usize {
    (chain << LEVEL_BITS) | lattice_index(level) as usize
}

/// How the hunt reads an outcome: the shares of the limits' substructures, the peak drift.
pub fn response(job: &SweepJob, o: &Outcome) -> Response {
    match o.status {
        Status::Completed => Response::Completed {
            shares: job.spec.sweep.limit.iter().map(|l| o.share_dt(&l.group)).collect(),
            drift: o.peak_drift_ratio.unwrap_or(0.0),
        },
        Status::Stopped => Response::Stopped,
        Status::GravityFailed => Response::GravityFailed,
    }
}

/// The chains of a hunt and what is in flight.
pub struct HuntFeed<'a> {
    job: &'a SweepJob,
    chains: Vec<Chain<'a>>,
    in_flight: Vec<bool>,
    log: Log,
    /// Tasks handed out by this run.
    pub handed_out: usize,
}

impl<'a> HuntFeed<'a> {
    /// Empty chains for every material and record of `job`.
    pub fn new(job: &'a SweepJob, rules: &'a HuntRules, log: Log) -> HuntFeed<'a> {
        let shares: Vec<f64> = job.spec.sweep.limit.iter().map(|l| l.share).collect();
        let n = job.variants.len() * job.records.len();
        let chains = (0..n).map(|_| Chain::new(rules, shares.clone())).collect();
        HuntFeed { job, chains, in_flight: vec![false; n], log, handed_out: 0 }
    }

    /// "rec-a / base": the chain's record and material.
    fn label(&self, c: usize) -> String {
        let n = self.job.records.len();
        format!("{} / {}", self.job.records[c % n].name, self.job.variants[c / n].name)
    }

    /// Replays every chain's decisions from the outcomes in `out` (a restart); how many members
    /// were done.
    pub fn restore(&mut self, out: &Path) -> usize {
        let mut done = 0;
        for c in 0..self.chains.len() {
            while let Some(n) = self.chains[c].next() {
                let m = member_of_task(self.job, task_of(c, n.level()));
                let Some(o) = Outcome::read(&member_dir(out, &m)) else { break };
                self.chains[c].add(n.level(), response(self.job, &o));
                done += 1;
            }
        }
        done
    }

    /// Every member run, by material, record and level.
    pub fn members(&self) -> Vec<Member> {
        let mut out = Vec::new();
        for (c, chain) in self.chains.iter().enumerate() {
            for x in chain.levels() {
                let m = member_of_task(self.job, task_of(c, x));
                out.push(Member { index: out.len(), ..m });
            }
        }
        out
    }

    fn announce(&self, c: usize, n: &Next) {
        let im = self.job.spec.sweep.scale_by.label();
        let line = match *n {
            Next::Hunt { level, step } => {
                format!("hunt {}: {im} {level:.4} m/s² (level {} of the hunt)", self.label(c), step + 1)
            }
            Next::Fill { level, limit, lower, upper } => {
                let l = &self.job.spec.sweep.limit[limit];
                format!(
                    "fill {}: {} {:.0} % passed between {lower:.4} and {upper:.4}: {im} {level:.4} m/s²",
                    self.label(c),
                    l.group,
                    100.0 * l.share
                )
            }
        };
        self.log.info(line);
    }

    fn report(&self, c: usize, level: f64, r: &Response) {
        let what = match r {
            Response::Completed { shares, drift } => {
                let per: Vec<String> = self
                    .job
                    .spec
                    .sweep
                    .limit
                    .iter()
                    .zip(shares)
                    .map(|(l, s)| {
                        let passed = if *s >= l.share { "passed" } else { "not passed" };
                        format!("{} {:.1} % ({passed} {:.0} %)", l.group, 100.0 * s, 100.0 * l.share)
                    })
                    .collect();
                format!("{}; peak drift ratio {drift:.3e}", per.join(", "))
            }
            Response::Stopped => "stopped converging (the flat end)".into(),
            Response::GravityFailed => "no gravity state".into(),
        };
        self.log.info(format!("hunt {} at {level:.4}: {what}", self.label(c)));
        let chain = &self.chains[c];
        if chain.next().is_none() {
            let end = chain
                .hunt_end()
                .map_or(String::new(), |(e, x)| format!(", the hunt ended at {x:.4} ({})", end_name(e)));
            self.log.info(format!("hunt {}: done after {} member(s){end}", self.label(c), chain.levels().len()));
        }
    }
}

/// How a hunt ended, for people.
pub fn end_name(e: HuntEnd) -> &'static str {
    match e {
        HuntEnd::AllPassed => "every limit passed",
        HuntEnd::Stopped => "stopped converging",
        HuntEnd::Flat => "flat",
        HuntEnd::Cap => "the cap, some limit not passed",
        HuntEnd::GravityFailed => "no gravity state",
    }
}

impl TaskSource for HuntFeed<'_> {
    fn next(&mut self) -> Answer {
        for c in 0..self.chains.len() {
            if self.in_flight[c] {
                continue;
            }
            if let Some(n) = self.chains[c].next() {
                self.in_flight[c] = true;
                self.handed_out += 1;
                self.announce(c, &n);
                return Answer::Task(task_of(c, n.level()));
            }
        }
        if self.in_flight.iter().any(|&f| f) {
            Answer::Wait
        } else {
            Answer::Stop
        }
    }

    fn finished(&mut self, task: usize) {
        let c = task >> LEVEL_BITS;
        let m = member_of_task(self.job, task);
        let r = match Outcome::read(&member_dir(&self.job.output_dir, &m)) {
            Some(o) => response(self.job, &o),
            None => {
                self.log.warn(format!("member {} left no outcome: taken as stopped", m.name));
                Response::Stopped
            }
        };
        self.in_flight[c] = false;
        self.chains[c].add(m.level, r.clone());
        self.report(c, m.level, &r);
    }
}
