//! A fill-reducing ordering of the DEM operator for its sparse Cholesky factorization: METIS's
//! nested dissection (`METIS_NodeND`) of the matrix graph.
//!
//! The stones form a planar graph; nested dissection orders each half of a small separator
//! before the separator, recursively, which for planar graphs bounds the factor by
//! `O(n log n)` entries and `O(n^{3/2})` flops (George 1973; Lipton, Rose & Tarjan 1979), where
//! the minimum-degree family (faer's AMD, the default of [`super::factor`]) has no such bound
//! and, on the DEM operators of 10k stones and more, makes more fill. METIS compresses the
//! identical rows of a stone's three DOFs itself (`METIS_OPTION_COMPRESS`, on by default).
//!
//! The permutation is `perm[new] = old` (METIS's `perm`; faer's forward array), `inv` its
//! inverse.
use metis_sys as m;

/// Why no ordering was computed.
#[derive(Clone, Debug, PartialEq)]
pub struct OrderingError(pub String);

/// METIS nested dissection of the graph of a symmetric `n × n` matrix given by the pattern of
/// one triangle in compressed columns (`col_ptr`, `row_idx`; the diagonal is ignored).
/// Returns `(perm, inv)`.
pub fn nested_dissection(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<(Vec<usize>, Vec<usize>), OrderingError> {
    let err = |s: String| OrderingError(s);
    if col_ptr.len() != n + 1 || col_ptr.last().is_none_or(|&e| e > row_idx.len()) {
        return Err(err(format!("pattern of {} column pointers for {n} columns", col_ptr.len())));
    }
    if n == 0 {
        return Ok((Vec::new(), Vec::new()));
    }
    let too_big = |v: usize| m::idx_t::try_from(v).map_err(|_| err(format!("{v} does not fit METIS's index type")));
    // Symmetric adjacency lists without the diagonal.
    let mut degree = vec![0usize; n];
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if i >= n {
                return Err(err(format!("row index {i} out of {n}")));
            }
            if i != j {
                degree[i] += 1;
                degree[j] += 1;
            }
        }
    }
    let mut xadj: Vec<m::idx_t> = Vec::with_capacity(n + 1);
    let mut start = vec![0usize; n + 1];
    for k in 0..n {
        start[k + 1] = start[k] + degree[k];
    }
    for &s in &start {
        xadj.push(too_big(s)?);
    }
    let mut adjncy: Vec<m::idx_t> = vec![0; start[n]];
    let mut fill = start.clone();
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if i != j {
                adjncy[fill[i]] = too_big(j)?;
                fill[i] += 1;
                adjncy[fill[j]] = too_big(i)?;
                fill[j] += 1;
            }
        }
    }
    let mut nvtxs = too_big(n)?;
    let mut perm: Vec<m::idx_t> = vec![0; n];
    let mut iperm: Vec<m::idx_t> = vec![0; n];
    // SAFETY: the arrays have the lengths METIS_NodeND reads and writes (xadj n+1, adjncy
    // xadj[n], perm and iperm n); null vertex weights and options select METIS's defaults.
    let status = unsafe {
        m::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != m::rstatus_et_METIS_OK {
        return Err(err(format!("METIS_NodeND returned status {status}")));
    }
    let to_usize = |v: &[m::idx_t]| -> Result<Vec<usize>, OrderingError> {
        v.iter()
            .map(|&x| usize::try_from(x).ok().filter(|&x| x < n).ok_or_else(|| err(format!("index {x} out of {n}"))))
            .collect()
    };
    let (perm, inv) = (to_usize(&perm)?, to_usize(&iperm)?);
    if perm.iter().enumerate().any(|(k, &p)| inv[p] != k) {
        return Err(err("METIS returned a permutation and an inverse that do not match".into()));
    }
    Ok((perm, inv))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orders_a_grid_by_a_permutation() {
        // A 7 × 7 grid graph (5-point stencil, upper triangle with diagonal): the result is a
        // permutation with its inverse (METIS's separators on a grid are not straight rows or
        // columns, so where they land is not checked here).
        let k = 7;
        let id = |r: usize, c: usize| r * k + c;
        let (mut cp, mut ri) = (vec![0usize], Vec::new());
        for j in 0..k * k {
            let (r, c) = (j / k, j % k);
            if r > 0 {
                ri.push(id(r - 1, c));
            }
            if c > 0 {
                ri.push(id(r, c - 1));
            }
            ri.push(j);
            cp.push(ri.len());
        }
        let (perm, inv) = nested_dissection(k * k, &cp, &ri).unwrap();
        let mut seen = vec![false; k * k];
        for (new, &old) in perm.iter().enumerate() {
            assert_eq!(inv[old], new);
            assert!(!seen[old]);
            seen[old] = true;
        }
    }

    #[test]
    fn bad_pattern_is_an_error() {
        assert!(nested_dissection(3, &[0, 1], &[0]).is_err());
        assert!(nested_dissection(2, &[0, 1, 2], &[0, 5]).is_err());
    }
}
