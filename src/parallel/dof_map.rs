//! Node ownership, global numbering, ghosts, fixed DOFs and matrix preallocation.
//!
//! Given the cells of the model and their parts, every rank computes the same ownership of
//! every node (no communication needed: the mesh and the partition are replicated):
//!
//! * a node is *active* when some cell touches it, and is owned by the lowest part among them;
//! * global node numbers run over rank 0's owned nodes (in mesh order), then rank 1's, ...;
//! * equation `6 g + d` is DOF `d` (ux uy uz rx ry rz) of global node `g`, so rank `r` owns the
//!   contiguous equations `[6 offset_r, 6 offset_{r+1})` and a node's six DOFs form one block;
//! * a fixed DOF keeps its equation number (so blocks stay whole) but its row and column hold
//!   only a diagonal entry: see [`DofMap::equation`].
//!
//! The *local* node order of a rank is its owned nodes, then its ghosts (nodes its cells touch
//! that other ranks own) in ascending global number: the order of a PETSc ghosted vector's
//! local form.

/// DOFs per node: three translations, three rotations.
pub const DOFS_PER_NODE: usize = 6;

const INACTIVE: usize = usize::MAX;

/// Ownership and numbering of the nodes and equations of one rank.
#[derive(Clone, Debug)]
pub struct DofMap {
    /// This rank.
    pub rank: usize,
    /// Owner rank of each mesh node (`usize::MAX` for nodes no cell touches).
    pub owner: Vec<usize>,
    /// Global number of each mesh node (`usize::MAX` when inactive).
    pub global: Vec<usize>,
    /// Number of active nodes over all ranks.
    pub n_global_nodes: usize,
    /// First global node number of each rank, plus the total at the end.
    pub offsets: Vec<usize>,
    /// Mesh indices of the owned nodes, in global order.
    pub owned: Vec<usize>,
    /// Mesh indices of the ghost nodes, in global order.
    pub ghosts: Vec<usize>,
    /// Fixed-DOF bit mask of each mesh node (bit `d` set = DOF `d` fixed).
    pub fixed: Vec<u8>,
}

/// Nonzeros per owned row for PETSc preallocation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Preallocation {
    /// Per owned scalar row: columns in the diagonal block.
    pub d_nnz: Vec<i32>,
    /// Per owned scalar row: columns in the off-diagonal block.
    pub o_nnz: Vec<i32>,
    /// Per owned node (block row of size 6): block columns in the diagonal block.
    pub d_nnz_blocks: Vec<i32>,
    /// Per owned node: block columns in the off-diagonal block.
    pub o_nnz_blocks: Vec<i32>,
}

impl DofMap {
    /// Builds the map of `rank` among `n_ranks` from the model's cells (their mesh node indices),
    /// their parts, and the fixed-DOF masks of the mesh nodes (`fixed.len()` = mesh node count).
    pub fn build(cells: &[&[usize]], part: &[usize], fixed: Vec<u8>, rank: usize, n_ranks: usize) -> DofMap {
        let n_nodes = fixed.len();
        let mut owner = vec![INACTIVE; n_nodes];
        for (c, &p) in cells.iter().zip(part) {
            for &n in c.iter() {
                owner[n] = owner[n].min(p);
            }
        }
        let mut counts = vec![0usize; n_ranks];
        for &o in &owner {
            if o != INACTIVE {
                counts[o] += 1;
            }
        }
        let mut offsets = vec![0usize; n_ranks + 1];
        for r in 0..n_ranks {
            offsets[r + 1] = offsets[r] + counts[r];
        }
        let mut next = offsets.clone();
        let mut global = vec![INACTIVE; n_nodes];
        for (n, &o) in owner.iter().enumerate() {
            if o != INACTIVE {
                global[n] = next[o];
                next[o] += 1;
            }
        }
        let owned: Vec<usize> = (0..n_nodes).filter(|&n| owner[n] == rank).collect();
        let mut ghosts: Vec<usize> = cells
            .iter()
            .zip(part)
            .filter(|(_, &p)| p == rank)
            .flat_map(|(c, _)| c.iter().copied())
            .filter(|&n| owner[n] != rank)
            .collect();
        ghosts.sort_unstable_by_key(|&n| global[n]);
        ghosts.dedup();
        DofMap { rank, owner, global, n_global_nodes: offsets[n_ranks], offsets, owned, ghosts, fixed }
    }

    /// Global number of this rank's first owned node.
    pub fn node_offset(&self) -> usize {
        self.offsets[self.rank]
    }

    /// Number of owned equations (6 per owned node).
    pub fn n_owned_dofs(&self) -> usize {
        DOFS_PER_NODE * self.owned.len()
    }

    /// Global equation of DOF `d` of mesh node `n` (free or fixed).
    pub fn dof(&self, n: usize, d: usize) -> i32 {
        debug_assert!(self.global[n] != INACTIVE, "node {n} is not active");
        (DOFS_PER_NODE * self.global[n] + d) as i32
    }

    /// Whether DOF `d` of mesh node `n` is fixed.
    pub fn is_fixed(&self, n: usize, d: usize) -> bool {
        self.fixed[n] & (1 << d) != 0
    }

    /// The equation where DOF `d` of node `n` is assembled: its global number when free, `-1`
    /// when fixed (PETSc ignores negative indices, which removes the row and the column).
    pub fn equation(&self, n: usize, d: usize) -> i32 {
        if self.is_fixed(n, d) {
            -1
        } else {
            self.dof(n, d)
        }
    }

    /// Global equations of the ghost nodes' DOFs, in local order (for a ghosted vector).
    pub fn ghost_dofs(&self) -> Vec<i32> {
        self.ghosts.iter().flat_map(|&n| (0..DOFS_PER_NODE).map(move |d| self.dof_raw(n, d))).collect()
    }

    fn dof_raw(&self, n: usize, d: usize) -> i32 {
        (DOFS_PER_NODE * self.global[n] + d) as i32
    }

    /// Local index (owned first, then ghosts) of each mesh node this rank sees.
    pub fn local_index(&self) -> std::collections::HashMap<usize, usize> {
        self.owned.iter().chain(&self.ghosts).enumerate().map(|(i, &n)| (n, i)).collect()
    }

    /// Preallocation of the owned rows: for each owned node, the nodes that share a cell with
    /// it (over *all* cells, since other ranks' cells add into this rank's rows too).
    pub fn preallocation(&self, cells: &[&[usize]]) -> Preallocation {
        let n_nodes = self.owner.len();
        // node -> cells (CSR) restricted to owned nodes
        let mut local = vec![usize::MAX; n_nodes];
        for (i, &n) in self.owned.iter().enumerate() {
            local[n] = i;
        }
        let mut neigh: Vec<Vec<usize>> = vec![Vec::new(); self.owned.len()];
        for c in cells {
            for &a in c.iter() {
                if local[a] != usize::MAX {
                    neigh[local[a]].extend(c.iter().copied());
                }
            }
        }
        let mut p = Preallocation {
            d_nnz: Vec::with_capacity(self.n_owned_dofs()),
            o_nnz: Vec::with_capacity(self.n_owned_dofs()),
            d_nnz_blocks: Vec::with_capacity(self.owned.len()),
            o_nnz_blocks: Vec::with_capacity(self.owned.len()),
        };
        for list in &mut neigh {
            list.sort_unstable();
            list.dedup();
            let d = list.iter().filter(|&&n| self.owner[n] == self.rank).count() as i32;
            let o = list.len() as i32 - d;
            p.d_nnz_blocks.push(d);
            p.o_nnz_blocks.push(o);
            for _ in 0..DOFS_PER_NODE {
                p.d_nnz.push(DOFS_PER_NODE as i32 * d);
                p.o_nnz.push(DOFS_PER_NODE as i32 * o);
            }
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chain 0-1-2-3-4 (4 cells), cells 0,1 on rank 0 and 2,3 on rank 1; node 5 unused.
    fn chain() -> (Vec<Vec<usize>>, Vec<usize>) {
        ((0..4).map(|i| vec![i, i + 1]).collect(), vec![0, 0, 1, 1])
    }

    #[test]
    fn ownership_numbering_and_ghosts() {
        let (cells, part) = chain();
        let refs: Vec<&[usize]> = cells.iter().map(|c| c.as_slice()).collect();
        let m0 = DofMap::build(&refs, &part, vec![0; 6], 0, 2);
        let m1 = DofMap::build(&refs, &part, vec![0; 6], 1, 2);
        // Node 2 touches parts 0 and 1: the lowest (0) owns it.
        assert_eq!(m0.owned, vec![0, 1, 2]);
        assert_eq!(m1.owned, vec![3, 4]);
        assert_eq!(m0.ghosts, Vec::<usize>::new());
        assert_eq!(m1.ghosts, vec![2]);
        assert_eq!(m1.global, vec![0, 1, 2, 3, 4, usize::MAX]);
        assert_eq!(m1.offsets, vec![0, 3, 5]);
        assert_eq!(m1.ghost_dofs(), (12..18).collect::<Vec<i32>>());
        // Both ranks agree on everything global.
        assert_eq!(m0.global, m1.global);
    }

    #[test]
    fn preallocation_counts_other_ranks_cells() {
        let (cells, part) = chain();
        let refs: Vec<&[usize]> = cells.iter().map(|c| c.as_slice()).collect();
        let m0 = DofMap::build(&refs, &part, vec![0; 6], 0, 2);
        let p = m0.preallocation(&refs);
        // Node 2 (owned by 0) couples to 1, 2 (owned by 0) and 3 (owned by 1, via a rank-1 cell).
        assert_eq!(p.d_nnz_blocks, vec![2, 3, 2]);
        assert_eq!(p.o_nnz_blocks, vec![0, 0, 1]);
        assert_eq!(p.d_nnz.len(), 18);
        assert_eq!(p.d_nnz[12], 12);
        assert_eq!(p.o_nnz[12], 6);
    }

    #[test]
    fn fixed_dofs_get_no_equation() {
        let (cells, _) = chain();
        let refs: Vec<&[usize]> = cells.iter().map(|c| c.as_slice()).collect();
        let m = DofMap::build(&refs, &[0; 4], vec![0b000101, 0, 0, 0, 0, 0], 0, 1);
        assert_eq!(m.equation(0, 0), -1);
        assert_eq!(m.equation(0, 1), 1);
        assert_eq!(m.equation(0, 2), -1);
        assert_eq!(m.dof(0, 2), 2);
    }
}
