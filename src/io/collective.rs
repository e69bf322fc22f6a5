//! Cheap agreement between ranks before a collective HDF5 call.
//!
//! HDF5's parallel metadata calls (creating a group or a dataset) must be made by every rank with
//! the same arguments, and an error on one rank alone leaves the others waiting. So before each
//! collective call the ranks exchange one flag (did the local checks pass?) and one 64-bit key
//! (a hash of the arguments) with a single `MPI_Allgather`; every rank then takes the same
//! decision from the same gathered data.

use mpi::traits::{Communicator, CommunicatorCollectives};

/// The outcome of [`agree`], identical on every rank.
#[derive(Debug, Default, PartialEq, Eq)]
pub(crate) struct Verdict {
    /// Ranks whose local checks failed.
    pub failed: Vec<i32>,
    /// Ranks whose key differs from rank 0's.
    pub differ: Vec<i32>,
}

impl Verdict {
    /// True when every rank passed and all keys are equal.
    pub(crate) fn ok(&self) -> bool {
        self.failed.is_empty() && self.differ.is_empty()
    }
}

/// Collective. Gathers `(ok, key)` from every rank and reports who failed and who disagrees.
pub(crate) fn agree<C: Communicator>(comm: &C, ok: bool, key: u64) -> Verdict {
    let n = comm.size() as usize;
    let mine = [u64::from(ok), key];
    let mut all = vec![0u64; 2 * n];
    comm.all_gather_into(&mine[..], &mut all[..]);
    verdict(&all)
}

/// The verdict from the gathered `[ok_0, key_0, ok_1, key_1, ...]`.
fn verdict(all: &[u64]) -> Verdict {
    let mut v = Verdict::default();
    let key0 = all.get(1).copied().unwrap_or(0);
    for (r, pair) in all.chunks_exact(2).enumerate() {
        if pair[0] == 0 {
            v.failed.push(r as i32);
        } else if pair[1] != key0 {
            v.differ.push(r as i32);
        }
    }
    v
}

/// 64-bit FNV-1a hash of a byte string (offset basis 0xcbf29ce484222325, prime 0x100000001b3,
/// from the FNV reference); used only to compare arguments across ranks, never stored.
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdict_names_failed_and_differing_ranks() {
        assert!(verdict(&[1, 7, 1, 7, 1, 7]).ok());
        let v = verdict(&[1, 7, 0, 7, 1, 8]);
        assert_eq!(v.failed, vec![1]);
        assert_eq!(v.differ, vec![2]);
    }

    #[test]
    fn fnv1a_reference_values() {
        // Test vectors of the FNV reference implementation (draft-eastlake-fnv): "" and "a".
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}
