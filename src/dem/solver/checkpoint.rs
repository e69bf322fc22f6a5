//! Checkpoints of a virtual test: the mechanical state ([`SolverState`]) with the stage walk it
//! stands in ([`StageWalk`]), so that a killed run continues where it was, and the result of a
//! finished test, so that it is not run again.
//!
//! A test hands a [`TestCheckpoint`] to its [`CheckpointSink`] after each committed load step
//! the sink finds due, and one at its end (`finished`). The file (little-endian), after the
//! conventions of the time history's checkpoints:
//!
//! ```text
//!   magic      8 bytes  "MHPCDEM1"
//!   u64 + JSON          the header: format version, fingerprint (stones, beams, the stones'
//!                       geometry, seed, mechanical parameters, test)
//!   u64 + JSON          the body: SolverState, the stage walk, counters, seconds so far,
//!                       and for a finished test how it ended
//!   u64                 FNV-1a checksum of everything before it
//! ```
//!
//! JSON keeps every finite `f64` exactly (shortest round-trip digits written, `serde_json`'s
//! `float_roundtrip` parser reading them back), so the state read is bit for bit the state
//! written. A committed state holds finite numbers only; a non-finite one would read as an
//! error, never as another number. Written to `NAME.tmp`, synced and renamed over `NAME`: a run
//! killed at any moment leaves the previous checkpoint or the new one, whole.
//!
//! A resumed test rebuilds the workspace (a fresh factorization in place of the updated one), so
//! its path agrees with the uninterrupted one to the round-off of that factorization and to the
//! equilibrium tolerance (the state module's docs); the broken beams are the same in the same
//! order unless two beams are that close to breaking together.
use super::error::DemError;
use super::profile::Counters;
use super::state::SolverState;
use super::test_result::{RunStats, TestEnd};
use super::walk::StageWalk;
use crate::dem::mechanics::MechParams;
use crate::dem::sample::Sample;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file's first eight bytes.
pub const MAGIC: &[u8; 8] = b"MHPCDEM1";

/// The body layout's version (in the header): a file of another version is refused by name.
pub const FORMAT_VERSION: u32 = 1;

/// What a checkpoint belongs to: a resumed test must be the same sample under the same
/// mechanics and the same test.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fingerprint {
    /// Stones of the sample.
    pub stones: usize,
    /// Beams of the sample.
    pub beams: usize,
    /// FNV-1a digest of the stones' centroids and vertices (bits) and the beams' ends.
    pub geometry: u64,
    /// The sample's seed.
    pub seed: u64,
    /// The mechanical parameters, as JSON.
    pub mechanics: String,
    /// The test with its parameters, as JSON.
    pub test: String,
}

impl Fingerprint {
    /// The fingerprint of `test` (any serializable description of it) on `sample`, built from
    /// `seed`, with the parameters `params`.
    pub fn new(sample: &Sample, seed: u64, params: &MechParams, test: &impl Serialize) -> Fingerprint {
        let mut g = Fnv::default();
        for p in &sample.particles {
            g.floats(&p.centroid);
            p.polygon.vertices.iter().for_each(|v| g.floats(v));
        }
        for b in &sample.beams {
            g.bytes(&(b.i as u64).to_le_bytes());
            g.bytes(&(b.j as u64).to_le_bytes());
        }
        Fingerprint {
            stones: sample.particles.len(),
            beams: sample.beams.len(),
            geometry: g.0,
            seed,
            mechanics: json(params),
            test: json(test),
        }
    }

    /// What differs from `other` (the job's), in words (`None`: the same).
    pub fn difference(&self, other: &Fingerprint) -> Option<String> {
        let mut d = Vec::new();
        if self.stones != other.stones {
            d.push(format!("{} stones, the sample has {}", self.stones, other.stones));
        }
        if self.beams != other.beams {
            d.push(format!("{} beams, the sample has {}", self.beams, other.beams));
        }
        if self.geometry != other.geometry && self.stones == other.stones {
            d.push("the stones' geometry differs (another [sample] layout?)".to_string());
        }
        if self.seed != other.seed {
            d.push(format!("seed {}, the sample's is {}", self.seed, other.seed));
        }
        if self.mechanics != other.mechanics {
            d.push(format!("mechanics {}, the job's are {}", self.mechanics, other.mechanics));
        }
        if self.test != other.test {
            d.push(format!("test {}, the job's is {}", self.test, other.test));
        }
        (!d.is_empty()).then(|| d.join("; "))
    }
}

/// JSON text of `v` for the fingerprint (a message in its place in the impossible case that it
/// does not serialize: it then differs from every real one).
fn json(v: &impl Serialize) -> String {
    serde_json::to_string(v).unwrap_or_else(|e| format!("(not serializable: {e})"))
}

#[derive(Serialize, Deserialize)]
struct Header {
    version: u32,
    fingerprint: Fingerprint,
}

/// How a finished test ended: what its result needs beyond the state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finished {
    /// How it ended.
    pub end: TestEnd,
    /// Its statistics.
    pub stats: RunStats,
}

/// A virtual test at a committed load step, or finished.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TestCheckpoint {
    /// The mechanics.
    pub state: SolverState,
    /// Where the current stage's walk stands (`None` once the test finished).
    pub(super) walk: Option<StageWalk>,
    /// The counters so far.
    pub counters: Counters,
    /// Wall time of the test so far [s].
    pub seconds: f64,
    /// `Some` once the test finished.
    pub finished: Option<Finished>,
}

/// Receives a test's checkpoints: asked after every committed load step whether one is due,
/// and given one at the test's end whatever it answers.
pub trait CheckpointSink {
    /// Whether a checkpoint of `state` is due now.
    fn due(&mut self, state: &SolverState) -> bool;
    /// Writes `c`. An error ends the test with it ([`DemError::Checkpoint`]).
    fn write(&mut self, c: TestCheckpoint) -> Result<(), DemError>;
}

/// Why a checkpoint file cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Unreadable {
    /// Not a checkpoint of a virtual test.
    #[error("not a DEM checkpoint (bad magic or too short)")]
    NotACheckpoint,
    /// The checksum does not match.
    #[error("checksum mismatch (a damaged file)")]
    Checksum,
    /// The file ends early or its parts do not parse.
    #[error("damaged file: {0}")]
    Damaged(String),
    /// Written by another format version.
    #[error("format version {found}, this program reads {FORMAT_VERSION}")]
    Version {
        /// The file's version.
        found: u32,
    },
    /// Written for another sample or test.
    #[error("written for another sample or test: {0}")]
    Mismatch(String),
}

/// FNV-1a, 64 bits.
struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf29ce484222325)
    }
}

impl Fnv {
    fn bytes(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u64;
            self.0 = self.0.wrapping_mul(0x100000001b3);
        }
    }

    fn floats(&mut self, x: &[f64]) {
        x.iter().for_each(|v| self.bytes(&v.to_bits().to_le_bytes()));
    }
}

fn fnv(bytes: &[u8]) -> u64 {
    let mut h = Fnv::default();
    h.bytes(bytes);
    h.0
}

/// Magic, the two length-prefixed parts, the checksum.
fn assemble(header: &[u8], body: &[u8]) -> Vec<u8> {
    let mut b = Vec::with_capacity(8 + 16 + header.len() + body.len() + 8);
    b.extend_from_slice(MAGIC);
    for part in [header, body] {
        b.extend_from_slice(&(part.len() as u64).to_le_bytes());
        b.extend_from_slice(part);
    }
    let h = fnv(&b);
    b.extend_from_slice(&h.to_le_bytes());
    b
}

/// The file's bytes.
pub fn encode(fingerprint: &Fingerprint, c: &TestCheckpoint) -> Result<Vec<u8>, serde_json::Error> {
    let header = serde_json::to_vec(&Header { version: FORMAT_VERSION, fingerprint: fingerprint.clone() })?;
    Ok(assemble(&header, &serde_json::to_vec(c)?))
}

/// The checkpoint in `b`, checked against `expected` (magic, checksum, version, fingerprint).
pub fn decode(b: &[u8], expected: &Fingerprint) -> Result<TestCheckpoint, Unreadable> {
    if b.len() < 8 + 8 + 8 + 8 || &b[..8] != MAGIC {
        return Err(Unreadable::NotACheckpoint);
    }
    let (body, tail) = b.split_at(b.len() - 8);
    let want = u64::from_le_bytes(tail.try_into().map_err(|_| Unreadable::NotACheckpoint)?);
    if fnv(body) != want {
        return Err(Unreadable::Checksum);
    }
    let mut at = 8;
    let mut part = || -> Result<&[u8], Unreadable> {
        let short = || Unreadable::Damaged("truncated".into());
        let len = body.get(at..at + 8).ok_or_else(short)?;
        let len = u64::from_le_bytes(len.try_into().map_err(|_| short())?) as usize;
        let p = body.get(at + 8..(at + 8).checked_add(len).ok_or_else(short)?).ok_or_else(short)?;
        at += 8 + len;
        Ok(p)
    };
    let header: Header = serde_json::from_slice(part()?).map_err(|e| Unreadable::Damaged(format!("header: {e}")))?;
    if header.version != FORMAT_VERSION {
        return Err(Unreadable::Version { found: header.version });
    }
    if let Some(d) = header.fingerprint.difference(expected) {
        return Err(Unreadable::Mismatch(d));
    }
    serde_json::from_slice(part()?).map_err(|e| Unreadable::Damaged(format!("state: {e}")))
}

/// Writes `bytes` to `path` atomically: `path.tmp`, synced, renamed over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let tmp = path.with_extension("tmp");
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::solver::tests::small_wall;
    use crate::dem::solver::{run_test_checkpointed, Checkpoints, TestRun, VirtualTest};
    use std::cell::RefCell;
    use std::rc::Rc;

    /// Keeps every checkpoint it is given; one is due after every load step.
    struct Keep(Rc<RefCell<Vec<TestCheckpoint>>>);

    impl CheckpointSink for Keep {
        fn due(&mut self, _: &SolverState) -> bool {
            true
        }
        fn write(&mut self, c: TestCheckpoint) -> Result<(), DemError> {
            self.0.borrow_mut().push(c);
            Ok(())
        }
    }

    fn shear() -> VirtualTest {
        VirtualTest::Shear {
            vertical_stress: 1e6,
            max_displacement: 1e-3,
            steps: 8,
            preload_steps: 2,
            rotation: Default::default(),
        }
    }

    /// The checkpoints of a shear test of the small wall (seed 2): one per load step, the last
    /// one finished; and the fingerprint they belong to.
    fn checkpoints() -> (Vec<TestCheckpoint>, Fingerprint) {
        let (s, p) = (small_wall(2), MechParams::default());
        let kept = Rc::new(RefCell::new(Vec::new()));
        let c = Checkpoints { sink: Some(Box::new(Keep(kept.clone()))), resume: None };
        run_test_checkpointed(&s, &p, &shear(), TestRun { checkpoints: c, ..Default::default() }).unwrap();
        let fp = Fingerprint::new(&s, 2, &p, &shear());
        (kept.take(), fp)
    }

    #[test]
    fn a_checkpoint_reads_back_bit_for_bit() {
        let (cs, fp) = checkpoints();
        assert!(cs.len() > 3 && cs.last().unwrap().finished.is_some());
        // A running checkpoint with contact histories, its coordinates made awkward: negative
        // zero, the smallest subnormal, 0.1 + 0.2, the most negative finite number.
        let mut c = cs.iter().find(|c| c.finished.is_none() && !c.state.histories.is_empty()).unwrap().clone();
        let awkward = [-0.0, 5e-324, 0.1 + 0.2, f64::MIN];
        c.state.z[..4].copy_from_slice(&awkward);
        for c in [&c, cs.last().unwrap()] {
            let bytes = encode(&fp, c).unwrap();
            let back = decode(&bytes, &fp).unwrap();
            let bits = |z: &[f64]| z.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&back.state.z), bits(&c.state.z));
            assert_eq!(bits(&back.state.z_commit), bits(&c.state.z_commit));
            assert_eq!(back.state.histories, c.state.histories);
            assert_eq!(back.state.records, c.state.records);
            assert_eq!(back.state.broken, c.state.broken);
            assert_eq!((back.counters, back.seconds.to_bits()), (c.counters, c.seconds.to_bits()));
            assert_eq!(back.finished, c.finished);
            assert_eq!(back.walk.is_some(), c.walk.is_some());
            // Every other field too: written again, the bytes are the same.
            assert_eq!(encode(&fp, &back).unwrap(), bytes);
        }
    }

    #[test]
    fn a_flipped_byte_or_a_cut_file_is_refused() {
        let (cs, fp) = checkpoints();
        let bytes = encode(&fp, &cs[2]).unwrap();
        let n = bytes.len();
        // A bit flipped in the header's length, in the header, in the body, in the checksum.
        for at in [9, 20, n / 2, n - 20, n - 1] {
            let mut b = bytes.clone();
            b[at] ^= 0x10;
            assert_eq!(decode(&b, &fp).unwrap_err(), Unreadable::Checksum, "byte {at} of {n}");
        }
        assert_eq!(decode(&bytes[..n - 1], &fp).unwrap_err(), Unreadable::Checksum);
        assert_eq!(decode(&bytes[..20], &fp).unwrap_err(), Unreadable::NotACheckpoint);
        assert_eq!(decode(b"", &fp).unwrap_err(), Unreadable::NotACheckpoint);
    }

    #[test]
    fn another_magic_or_version_is_refused() {
        let (cs, fp) = checkpoints();
        let mut b = encode(&fp, &cs[1]).unwrap();
        b[7] = b'2';
        assert_eq!(decode(&b, &fp).unwrap_err(), Unreadable::NotACheckpoint);
        // Version 2, with a checksum that matches.
        let header = serde_json::to_vec(&Header { version: 2, fingerprint: fp.clone() }).unwrap();
        let b = assemble(&header, &serde_json::to_vec(&cs[1]).unwrap());
        let e = decode(&b, &fp).unwrap_err();
        assert_eq!(e, Unreadable::Version { found: 2 });
        assert_eq!(e.to_string(), "format version 2, this program reads 1");
    }

    #[test]
    fn a_fingerprint_mismatch_names_the_difference() {
        let (cs, fp) = checkpoints();
        let b = encode(&fp, &cs[1]).unwrap();
        let p = MechParams::default();
        let other_test = VirtualTest::Compression { max_strain: 1e-3, steps: 8 };
        let mismatch = |expected: &Fingerprint| match decode(&b, expected) {
            Err(Unreadable::Mismatch(m)) => m,
            other => panic!("expected a mismatch, got {other:?}"),
        };
        let m = mismatch(&Fingerprint::new(&small_wall(2), 2, &p, &other_test));
        assert_eq!(m, format!("test {}, the job's is {}", fp.test, json(&other_test)));
        assert!(m.contains(r#""type":"shear""#) && m.contains(r#""type":"compression""#), "{m}");
        let m = mismatch(&Fingerprint::new(&small_wall(2), 7, &p, &shear()));
        assert_eq!(m, "seed 2, the sample's is 7");
        let stiffer = MechParams { e_bar: 3e9, ..p };
        let m = mismatch(&Fingerprint::new(&small_wall(2), 2, &stiffer, &shear()));
        assert!(
            m.starts_with("mechanics {\"e_bar\":2500000000.0,") && m.contains("the job's are {\"e_bar\":3000000000.0,"),
            "{m}"
        );
        // Another sample of the same layout: the same stones, its own geometry.
        let other = small_wall(3);
        let m = mismatch(&Fingerprint::new(&other, 2, &p, &shear()));
        assert!(m.contains("the stones' geometry differs"), "{m}");
        assert_eq!(other.particles.len(), fp.stones);
    }
}
