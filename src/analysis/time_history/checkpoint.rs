//! Checkpoints: the whole state of a time history, written atomically, read back by `--restart`.
//!
//! Layout under the results folder:
//!
//! ```text
//!   checkpoint/latest.json              {"step", "time", "ranks", "dir"} — the only entry point
//!   checkpoint/step-000120/rank-0000.bin  one file per rank (its owned DOFs and elements)
//! ```
//!
//! Each rank writes `rank-RRRR.bin.tmp`, syncs it and renames it; after a barrier rank 0
//! replaces `latest.json` the same way, then removes older step folders. A run killed at any
//! moment leaves `latest.json` pointing at a complete checkpoint (the previous one until the new
//! one is whole). The rank file (little-endian): magic `MHPCCKP2` (`MHPCCKP1`, six energies, is
//! still read); u64 ranks, rank, owned DOFs,
//! step, elements, node-envelope and cell-envelope lengths; f64 time and the eight energies
//! ([`super::EnergyBalance::to_array`]); the
//! vectors u, v, a, f_int, C v; per element its state length (u64) then all states (f64); the
//! envelopes; the substep level the next step starts with (u64, [`State::substep_level`]; a
//! file without it, written before the damage control, reads as level 0); an FNV-1a checksum
//! of everything before it. A restart needs the same rank count
//! (the partition, hence the owned DOFs and elements, depends on it).
use super::envelope::Envelopes;
use super::integration::SavedEnvelopes;
use super::petsc_system::PetscSystem;
use super::stepper::State;
use super::system::DynamicSystem;
use super::EnergyBalance;
use crate::config::DynamicsConfig;
use crate::element::Element;
use crate::error::{AnalysisError, Error};
use crate::parallel::{agree, Context};
use mpi::traits::{Communicator, CommunicatorCollectives, Root};
use std::path::{Path, PathBuf};
use std::time::Instant;

const MAGIC: &[u8; 8] = b"MHPCCKP2";
/// The layout before the law's dissipation was part of the energies (six of them).
const OLD_MAGIC: &[u8; 8] = b"MHPCCKP1";

/// The state of one rank at the end of a converged step.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    /// Steps done.
    pub step: usize,
    /// Time [s].
    pub t: f64,
    /// Energies ([`super::EnergyBalance::to_array`]).
    pub energy: [f64; super::EnergyBalance::N_VALUES],
    /// u, v, a, f_int, C v (owned entries).
    pub vectors: [Vec<f64>; 5],
    /// Committed state of every owned element.
    pub states: Vec<Vec<f64>>,
    /// Node envelopes (owned nodes).
    pub node_envelope: Vec<f64>,
    /// Cell envelopes (owned cells).
    pub cell_envelope: Vec<f64>,
    /// [`State::substep_level`].
    pub substep_level: u32,
}

/// The committed states of `elements`.
pub fn element_states(elements: &[Box<dyn Element>]) -> Result<Vec<Vec<f64>>, Error> {
    elements
        .iter()
        .map(|e| {
            let mut s = vec![0.0; e.n_state()];
            e.save_state(&mut s)
                .map(|_| s)
                .map_err(|source| Error::from(AnalysisError::SaveState { kind: e.kind_name(), source }))
        })
        .collect()
}

fn checkpoint_dir(results: &Path) -> PathBuf {
    results.join("checkpoint")
}

fn io_err(path: &Path, e: impl std::fmt::Display) -> Error {
    AnalysisError::Checkpoint { file: path.to_path_buf(), reason: e.to_string() }.into()
}

fn fnv(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let tmp = path.with_extension("tmp");
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)
}

fn encode(c: &Checkpoint, ranks: usize, rank: usize) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(MAGIC);
    let n = c.vectors[0].len();
    for v in [ranks, rank, n, c.step, c.states.len(), c.node_envelope.len(), c.cell_envelope.len()] {
        b.extend_from_slice(&(v as u64).to_le_bytes());
    }
    b.extend_from_slice(&c.t.to_le_bytes());
    let f = |b: &mut Vec<u8>, xs: &[f64]| xs.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    f(&mut b, &c.energy);
    for v in &c.vectors {
        f(&mut b, v);
    }
    for s in &c.states {
        b.extend_from_slice(&(s.len() as u64).to_le_bytes());
    }
    for s in &c.states {
        f(&mut b, s);
    }
    f(&mut b, &c.node_envelope);
    f(&mut b, &c.cell_envelope);
    b.extend_from_slice(&(c.substep_level as u64).to_le_bytes());
    let h = fnv(&b);
    b.extend_from_slice(&h.to_le_bytes());
    b
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn u64(&mut self) -> Option<u64> {
        let s = self.b.get(self.at..self.at + 8)?;
        self.at += 8;
        Some(u64::from_le_bytes(s.try_into().ok()?))
    }
    fn f64s(&mut self, n: usize) -> Option<Vec<f64>> {
        let s = self.b.get(self.at..self.at.checked_add(n.checked_mul(8)?)?)?;
        self.at += 8 * n;
        Some(s.chunks_exact(8).map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]])).collect())
    }
}

/// Why a rank's checkpoint file cannot be read.
#[derive(Debug, PartialEq, thiserror::Error)]
enum Unreadable {
    /// The layout of an older version.
    #[error(
        "written by an older version (six energies, without the law's dissipation); start the time history again without --restart"
    )]
    OldVersion,
    /// Not a checkpoint file.
    #[error("not a checkpoint file (bad magic or too short)")]
    NotACheckpoint,
    /// The checksum does not match.
    #[error("checksum mismatch (a damaged file)")]
    Checksum,
    /// The file ends early.
    #[error("truncated file")]
    Truncated,
    /// Written by a run on another rank count.
    #[error("written by a run on {written} rank(s); restart it on {written} rank(s) (mpirun -n {written})")]
    Ranks {
        /// The rank count it was written on.
        written: usize,
    },
    /// Another rank's file.
    #[error("holds rank {holds}, expected {expected}")]
    Rank {
        /// The rank it holds.
        holds: usize,
        /// The rank reading it.
        expected: usize,
    },
}

/// Decodes a rank file; checks magic, checksum and the rank layout.
fn decode(b: &[u8], ranks: usize, rank: usize) -> Result<Checkpoint, Unreadable> {
    if b.len() >= 8 && &b[..8] == OLD_MAGIC {
        return Err(Unreadable::OldVersion);
    }
    if b.len() < 8 + 8 * 8 + 8 || &b[..8] != MAGIC {
        return Err(Unreadable::NotACheckpoint);
    }
    let (body, tail) = b.split_at(b.len() - 8);
    let want = u64::from_le_bytes(tail.try_into().map_err(|_| Unreadable::Truncated)?);
    if fnv(body) != want {
        return Err(Unreadable::Checksum);
    }
    let mut r = Reader { b: body, at: 8 };
    let bad = || Unreadable::Truncated;
    let h: Vec<usize> = (0..7).map(|_| r.u64().map(|v| v as usize)).collect::<Option<_>>().ok_or_else(bad)?;
    if h[0] != ranks {
        return Err(Unreadable::Ranks { written: h[0] });
    }
    if h[1] != rank {
        return Err(Unreadable::Rank { holds: h[1], expected: rank });
    }
    let (n, step, n_el, n_ne, n_ce) = (h[2], h[3], h[4], h[5], h[6]);
    let t = r.f64s(1).ok_or_else(bad)?[0];
    let e = r.f64s(super::EnergyBalance::N_VALUES).ok_or_else(bad)?;
    let energy: [f64; super::EnergyBalance::N_VALUES] = e.try_into().map_err(|_| bad())?;
    let mut vecs = Vec::new();
    for _ in 0..5 {
        vecs.push(r.f64s(n).ok_or_else(bad)?);
    }
    let lens: Vec<usize> = (0..n_el).map(|_| r.u64().map(|v| v as usize)).collect::<Option<_>>().ok_or_else(bad)?;
    let states = lens.iter().map(|&l| r.f64s(l)).collect::<Option<Vec<_>>>().ok_or_else(bad)?;
    let node_envelope = r.f64s(n_ne).ok_or_else(bad)?;
    let cell_envelope = r.f64s(n_ce).ok_or_else(bad)?;
    // Absent from the files written before the damage control: level 0, dt.
    let substep_level = if r.at == body.len() { 0 } else { r.u64().ok_or_else(bad)?.min(u32::MAX as u64) as u32 };
    let [u, v, a, fi, cv]: [Vec<f64>; 5] = vecs.try_into().map_err(|_| bad())?;
    Ok(Checkpoint { step, t, energy, vectors: [u, v, a, fi, cv], states, node_envelope, cell_envelope, substep_level })
}

/// Collective. Writes `c` (this rank's part) as the latest checkpoint under `results`.
pub fn write(ctx: &Context, results: &Path, c: &Checkpoint) -> Result<PathBuf, Error> {
    let root = checkpoint_dir(results);
    let name = format!("step-{:09}", c.step);
    let dir = root.join(&name);
    let file = dir.join(format!("rank-{:04}.bin", ctx.rank));
    let mine = std::fs::create_dir_all(&dir)
        .and_then(|_| write_atomic(&file, &encode(c, ctx.size, ctx.rank)))
        .map_err(|e| io_err(&file, e));
    crate::parallel::agree(&ctx.comm, mine, Error::exit_code)?;
    let latest = root.join("latest.json");
    let published = if ctx.rank == 0 {
        let text = serde_json::json!({ "step": c.step, "time": c.t, "ranks": ctx.size, "dir": name }).to_string();
        let done = write_atomic(&latest, text.as_bytes()).map_err(|e| io_err(&latest, e));
        if done.is_ok() {
            // Older checkpoints are no longer referenced.
            if let Ok(entries) = std::fs::read_dir(&root) {
                for e in entries.flatten() {
                    let p = e.path();
                    if p.is_dir()
                        && p.file_name().is_some_and(|f| {
                            f.to_string_lossy().starts_with("step-") && f.to_string_lossy() != name.as_str()
                        })
                    {
                        let _ = std::fs::remove_dir_all(p);
                    }
                }
            }
        }
        done
    } else {
        Ok(())
    };
    crate::parallel::agree(&ctx.comm, published, Error::exit_code)?;
    ctx.comm.barrier();
    Ok(dir)
}

/// Collective. Reads this rank's part of the latest checkpoint under `results`.
pub fn read_latest(ctx: &Context, results: &Path) -> Result<Checkpoint, Error> {
    let root = checkpoint_dir(results);
    let latest = root.join("latest.json");
    let read = (|| -> Result<Checkpoint, Error> {
        let text = std::fs::read_to_string(&latest)
            .map_err(|e| io_err(&latest, format!("{e} (no checkpoint to restart from)")))?;
        let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| io_err(&latest, e))?;
        let dir = v["dir"].as_str().ok_or_else(|| io_err(&latest, "no \"dir\" entry"))?;
        let file = root.join(dir).join(format!("rank-{:04}.bin", ctx.rank));
        let bytes = std::fs::read(&file).map_err(|e| io_err(&file, e))?;
        decode(&bytes, ctx.size, ctx.rank).map_err(|e| io_err(&file, e))
    })();
    Ok(crate::parallel::agree(&ctx.comm, read, Error::exit_code)?)
}

/// Collective. Restores a checkpoint into the system's elements; the state and envelopes.
pub(super) fn restore(
    ctx: &Context,
    sys: &mut PetscSystem,
    c: Checkpoint,
) -> Result<(State, Option<SavedEnvelopes>), Error> {
    let n = sys.len();
    let loaded = (|| -> Result<(), Error> {
        if c.vectors[0].len() != n || c.states.len() != sys.disc.elements.len() {
            return Err(AnalysisError::CheckpointMismatch {
                dofs: c.vectors[0].len(),
                elements: c.states.len(),
                rank: ctx.rank,
                model_dofs: n,
                model_elements: sys.disc.elements.len(),
            }
            .into());
        }
        // An element reads the layouts it knows (implicit, or with IMPL-EX's history: either is
        // a valid start for either integration) and refuses any other length.
        for (e, s) in sys.disc.elements.iter_mut().zip(&c.states) {
            e.load_state(s).map_err(|source| {
                Error::from(AnalysisError::LoadState { kind: e.kind_name(), values: s.len(), source })
            })?;
        }
        Ok(())
    })();
    agree(&ctx.comm, loaded, Error::exit_code)?;
    let [u, v, a, f_int, cv] = c.vectors;
    let energy = EnergyBalance::from_array(c.energy);
    let state = State { step: c.step, t: c.t, u, v, a, f_int, cv, energy, substep_level: c.substep_level };
    Ok((state, Some((c.node_envelope, c.cell_envelope))))
}

/// Collective. Checkpoints the committed state with the envelopes; the checkpoint's folder.
pub(super) fn save(
    ctx: &Context,
    sys: &PetscSystem,
    state: &State,
    env: &Envelopes,
    dir: &std::path::Path,
) -> Result<std::path::PathBuf, Error> {
    let states = element_states(&sys.disc.elements);
    let states = agree(&ctx.comm, states, Error::exit_code)?;
    let c = Checkpoint {
        step: state.step,
        t: state.t,
        energy: state.energy.to_array(),
        vectors: [state.u.clone(), state.v.clone(), state.a.clone(), state.f_int.clone(), state.cv.clone()],
        states,
        node_envelope: env.node.clone(),
        cell_envelope: env.cell.clone(),
        substep_level: state.substep_level,
    };
    write(ctx, dir, &c)
}

/// When a checkpoint is due by wall time (`[dynamics.checkpoint] every_minutes`): a clock, not a
/// phase timer; rank 0's reading decides for every rank.
pub(super) struct CheckpointClock {
    last: Instant,
}

impl Default for CheckpointClock {
    fn default() -> Self {
        CheckpointClock { last: Instant::now() }
    }
}

impl CheckpointClock {
    /// Collective. Whether a checkpoint is due after `step`: every `every_steps` steps, or when
    /// `every_minutes` have passed since the last one.
    pub(super) fn due(&self, ctx: &Context, cfg: &DynamicsConfig, step: usize) -> bool {
        let c = &cfg.checkpoint;
        let mut due = c.every_steps > 0 && step % c.every_steps == 0;
        if c.every_minutes > 0.0 {
            let mut by_time = self.last.elapsed().as_secs_f64() >= 60.0 * c.every_minutes;
            ctx.comm.process_at_rank(0).broadcast_into(&mut by_time);
            due |= by_time;
        }
        due
    }

    /// A checkpoint was just written.
    pub(super) fn restart(&mut self) {
        self.last = Instant::now();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_decode_round_trip_and_damage_detection() {
        let c = Checkpoint {
            step: 7,
            t: 0.07,
            energy: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0],
            vectors: [vec![1.0, -2.0], vec![3.0, 4.0], vec![5.0, 6.0], vec![7.0, 8.0], vec![9.0, 10.0]],
            states: vec![vec![], vec![0.1, 0.2, 0.3]],
            node_envelope: vec![1.5],
            cell_envelope: vec![0.25, 0.5],
            substep_level: 3,
        };
        let b = encode(&c, 2, 1);
        assert_eq!(decode(&b, 2, 1).unwrap(), c);
        // A file of the layout without the substep level (its last u64 before the checksum)
        // reads as level 0, the rest unchanged.
        let mut old = b[..b.len() - 16].to_vec();
        old.extend_from_slice(&fnv(&old).to_le_bytes());
        assert_eq!(decode(&old, 2, 1).unwrap(), Checkpoint { substep_level: 0, ..c.clone() });
        assert!(decode(&b, 1, 0).unwrap_err().to_string().contains("2 rank(s)"));
        let mut bad = b.clone();
        bad[100] ^= 1;
        assert!(decode(&bad, 2, 1).unwrap_err().to_string().contains("checksum"));
        assert!(decode(&b[..50], 2, 1).is_err());
    }
}
