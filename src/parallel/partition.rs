//! METIS partition of the cells among the ranks.
//!
//! The dual graph joins two cells that share a node (METIS `ncommon = 1`, so beams that meet
//! at a joint and shells that meet at a corner are neighbours). Rank 0 partitions and
//! broadcasts, so every rank holds the identical partition; METIS's fixed default seed makes
//! it deterministic for a given mesh and rank count.
use mpi::traits::{Communicator, Root};

/// Errors of the partitioner.
#[derive(Debug, thiserror::Error)]
pub enum PartitionError {
    /// METIS failed.
    #[error("METIS could not partition {n_cells} cells into {n_parts} parts: {message}")]
    Metis {
        /// Cells.
        n_cells: usize,
        /// Parts.
        n_parts: usize,
        /// What METIS said.
        message: String,
    },
}

/// Collective. The part (rank) of each cell, given the cells' node lists.
///
/// With one rank, or fewer cells than ranks, no METIS call is made: cells are dealt out in
/// contiguous blocks.
pub fn partition_cells(comm: &impl Communicator, cells: &[&[usize]]) -> Result<Vec<usize>, PartitionError> {
    let n_parts = comm.size() as usize;
    let n = cells.len();
    if n_parts == 1 {
        return Ok(vec![0; n]);
    }
    if n < 2 * n_parts {
        return Ok((0..n).map(|i| i * n_parts / n.max(1)).collect());
    }
    let mut part: Vec<i32> = vec![0; n];
    let mut status: i32 = 0;
    let mut failure = None;
    if comm.rank() == 0 {
        match metis_dual(cells, n_parts) {
            Ok(p) => part = p,
            Err(e) => {
                status = 1;
                failure = Some(e);
            }
        }
    }
    let root = comm.process_at_rank(0);
    root.broadcast_into(&mut status);
    if status != 0 {
        // Every rank returns an error; rank 0's, with METIS's message, is the one that is printed.
        return Err(failure.unwrap_or(PartitionError::Metis { n_cells: n, n_parts, message: String::new() }));
    }
    root.broadcast_into(&mut part[..]);
    Ok(part.into_iter().map(|p| p as usize).collect())
}

fn metis_dual(cells: &[&[usize]], n_parts: usize) -> Result<Vec<i32>, PartitionError> {
    let failed = |message: String| PartitionError::Metis { n_cells: cells.len(), n_parts, message };
    // Compact node numbering: METIS infers the node count from the largest index.
    let mut compact = std::collections::HashMap::new();
    let mut eptr: Vec<metis::Idx> = Vec::with_capacity(cells.len() + 1);
    let mut eind: Vec<metis::Idx> = Vec::new();
    eptr.push(0);
    for c in cells {
        for &node in c.iter() {
            let next = compact.len() as metis::Idx;
            eind.push(*compact.entry(node).or_insert(next));
        }
        eptr.push(eind.len() as metis::Idx);
    }
    let mut epart = vec![0 as metis::Idx; cells.len()];
    let mut npart = vec![0 as metis::Idx; compact.len()];
    let mesh = metis::Mesh::new(n_parts as metis::Idx, &eptr, &eind).map_err(|e| failed(format!("{e:?}")))?;
    mesh.part_dual(&mut epart, &mut npart).map_err(|e| failed(e.to_string()))?;
    Ok(epart.into_iter().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metis_splits_a_chain_into_two_connected_halves() {
        // 0-1-2-...-40: forty 2-node cells in a chain; a good bisection cuts it once.
        let cells: Vec<Vec<usize>> = (0..40).map(|i| vec![i, i + 1]).collect();
        let refs: Vec<&[usize]> = cells.iter().map(|c| c.as_slice()).collect();
        let p = metis_dual(&refs, 2).unwrap();
        assert_eq!(p.iter().filter(|&&x| x == 0).count(), 20);
        let cuts = p.windows(2).filter(|w| w[0] != w[1]).count();
        assert_eq!(cuts, 1, "{p:?}");
        // Deterministic: the same input gives the same partition.
        assert_eq!(p, metis_dual(&refs, 2).unwrap());
    }
}
