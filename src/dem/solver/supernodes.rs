//! A supernodal copy of CHOLMOD's simplicial `LDLᵀ` factor, for the dense solves of GMRES's
//! preconditioner.
//!
//! Updates and downdates in place need CHOLMOD's simplicial factor ([`super::cholmod`]): each
//! column of `L` is its own list of `(row, value)` pairs. Its substitutions scatter (forward) or
//! gather (backward) one entry of the solution per entry of `L`, a dependent, scattered access
//! each: on the 10k-stone operator (29k unknowns, 2.0M entries) a solve takes 4.1–4.8 ms, and
//! near the compression peak GMRES spends three quarters of the run in them
//! (docs/benchmarks.md, DEM (b)). A supernodal layout groups consecutive columns `s..=e` that
//! form a chain of the elimination tree (`parent(j) = j + 1`) into one dense block over the
//! union of their rows:
//!
//! ```text
//!   rows s..=e   │ T  (w × w unit lower triangle)        w = e − s + 1
//!   rows B       │ L_B (m × w, column-major)             B: the rows below e of any column
//!
//!   forward  (L y = b):   y_s ← T⁻¹ y_s;    t = L_B y_s;    y[B] −= t      (one scatter per row of B)
//!   backward (Lᵀ x = y):  t = y[B];          y_s −= L_Bᵀ t;  y_s ← T⁻ᵀ y_s  (one gather per row of B)
//! ```
//!
//! so that the solution is scattered and gathered once per row of a supernode instead of once
//! per entry, and the products run over contiguous memory. Merging a column whose rows are not
//! all in the block stores explicit zeros: a chain is extended while the block's entries stay
//! within [`RELAXATION`] times the structural ones (and [`MAX_WIDTH`] columns), the relaxed
//! supernodes of Ashcraft and Grimes (1989).
//!
//! The copy is exact (the same products in another order): the solution differs from CHOLMOD's
//! by round-off. Building it reads every entry of `L` once; the factor that owns it rebuilds it
//! after each change (factorization, update or downdate) on the next dense solve.

/// The largest dense block allowed, over the structural entries of its columns.
pub const RELAXATION: f64 = 1.5;
/// The widest supernode.
pub const MAX_WIDTH: usize = 64;

/// A simplicial `LDLᵀ` factor's columns as CHOLMOD keeps them: column `j` is
/// `i[p[j] .. p[j] + nz[j]]` with values in `x`, the diagonal `D_jj` first.
pub struct SimplicialColumns<'a> {
    /// Where each column starts in `i` and `x` (`n + 1` entries).
    pub p: &'a [i32],
    /// Each column's entries, the diagonal included.
    pub nz: &'a [i32],
    /// Row indices.
    pub i: &'a [i32],
    /// Values: `D_jj` first in column `j`, then `L_ij`.
    pub x: &'a [f64],
}

impl SimplicialColumns<'_> {
    fn column(&self, j: usize) -> (&[i32], &[f64]) {
        let p0 = self.p[j] as usize;
        let end = p0 + self.nz[j] as usize;
        (&self.i[p0..end], &self.x[p0..end])
    }
}

/// How a copy stores `L`'s values: `f64`, or `f32` for the preconditioner (half the bytes a
/// solve streams; the sums are carried in `f64`).
pub trait Stored: Copy + Default {
    /// The value stored for `v`.
    fn store(v: f64) -> Self;
    /// The stored value as an `f64`.
    fn load(self) -> f64;
}

impl Stored for f64 {
    fn store(v: f64) -> Self {
        v
    }
    fn load(self) -> f64 {
        self
    }
}

impl Stored for f32 {
    fn store(v: f64) -> Self {
        v as f32
    }
    fn load(self) -> f64 {
        f64::from(self)
    }
}

/// The supernodal copy (module docs), in the factor's own (permuted) order, its values stored
/// as `T`.
#[derive(Clone, Debug, Default)]
pub struct SupernodalFactor<T: Stored = f32> {
    n: usize,
    /// Supernode k covers the columns `start[k] .. start[k + 1]`.
    start: Vec<usize>,
    /// Its rows below the diagonal block: `rows[row_ptr[k] .. row_ptr[k + 1]]`, ascending.
    row_ptr: Vec<usize>,
    rows: Vec<u32>,
    /// Its values from `val_ptr[k]`: the `w × w` diagonal block (column-major, only the strict
    /// lower triangle read), then `L_B` (`m × w`, column-major).
    val_ptr: Vec<usize>,
    vals: Vec<T>,
    /// `1 / D_jj`.
    d_inv: Vec<f64>,
    /// Scratch of the widest `B`.
    t: Vec<f64>,
}

impl<T: Stored> SupernodalFactor<T> {
    /// The copy of a simplicial `LDLᵀ` of order `n`.
    pub fn from_simplicial(n: usize, l: &SimplicialColumns<'_>) -> Self {
        let (start, row_ptr, rows) = partition(n, l);
        let mut val_ptr = Vec::with_capacity(start.len());
        let mut total = 0;
        for k in 0..start.len() - 1 {
            val_ptr.push(total);
            let w = start[k + 1] - start[k];
            total += w * w + w * (row_ptr[k + 1] - row_ptr[k]);
        }
        val_ptr.push(total);
        let mut vals = vec![T::default(); total];
        let mut d_inv = vec![0.0; n];
        // pos[r]: r's place in the current supernode's B.
        let mut pos = vec![0usize; n];
        let mut widest = 0;
        for k in 0..start.len() - 1 {
            let (s, e1) = (start[k], start[k + 1]);
            let w = e1 - s;
            let b = &rows[row_ptr[k]..row_ptr[k + 1]];
            let m = b.len();
            widest = widest.max(m);
            for (q, &r) in b.iter().enumerate() {
                pos[r as usize] = q;
            }
            let (diag, below) = vals[val_ptr[k]..val_ptr[k + 1]].split_at_mut(w * w);
            for c in 0..w {
                let j = s + c;
                let (ri, rx) = l.column(j);
                d_inv[j] = 1.0 / rx[0];
                for (&r, &v) in ri.iter().zip(rx).skip(1) {
                    let r = r as usize;
                    if r < e1 {
                        diag[(r - s) + c * w] = T::store(v);
                    } else {
                        below[pos[r] + c * m] = T::store(v);
                    }
                }
            }
        }
        SupernodalFactor { n, start, row_ptr, rows, val_ptr, vals, d_inv, t: vec![0.0; widest] }
    }

    /// The order of `L`.
    pub fn order(&self) -> usize {
        self.n
    }

    /// The supernodes.
    pub fn supernodes(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// The entries stored (explicit zeros included).
    pub fn stored(&self) -> usize {
        self.vals.len()
    }

    /// Solves `L D Lᵀ y = b` in place, `y` in the factor's order.
    ///
    /// # Panics
    /// When `y` is not of the factor's order (the callers check it first).
    pub fn solve(&mut self, y: &mut [f64]) {
        assert_eq!(y.len(), self.n, "right-hand side of the factor's order");
        let t = &mut self.t;
        for k in 0..self.start.len() - 1 {
            let (s, w) = (self.start[k], self.start[k + 1] - self.start[k]);
            let b = &self.rows[self.row_ptr[k]..self.row_ptr[k + 1]];
            let m = b.len();
            let (diag, below) = self.vals[self.val_ptr[k]..self.val_ptr[k + 1]].split_at(w * w);
            let ys = &mut y[s..s + w];
            for c in 0..w {
                let yc = ys[c];
                for i in c + 1..w {
                    ys[i] -= diag[i + c * w].load() * yc;
                }
            }
            let t = &mut t[..m];
            t.iter_mut().for_each(|v| *v = 0.0);
            for c in 0..w {
                let yc = y[s + c];
                for (tv, &l) in t.iter_mut().zip(&below[c * m..(c + 1) * m]) {
                    *tv += l.load() * yc;
                }
            }
            for (&r, &tv) in b.iter().zip(t.iter()) {
                y[r as usize] -= tv;
            }
        }
        for (v, d) in y.iter_mut().zip(&self.d_inv) {
            *v *= d;
        }
        for k in (0..self.start.len() - 1).rev() {
            let (s, w) = (self.start[k], self.start[k + 1] - self.start[k]);
            let b = &self.rows[self.row_ptr[k]..self.row_ptr[k + 1]];
            let m = b.len();
            let (diag, below) = self.vals[self.val_ptr[k]..self.val_ptr[k + 1]].split_at(w * w);
            let t = &mut t[..m];
            for (tv, &r) in t.iter_mut().zip(b) {
                *tv = y[r as usize];
            }
            let ys = &mut y[s..s + w];
            for c in 0..w {
                let dot: f64 = below[c * m..(c + 1) * m].iter().zip(t.iter()).map(|(l, v)| l.load() * v).sum();
                ys[c] -= dot;
            }
            for c in (0..w).rev() {
                let mut v = ys[c];
                for i in c + 1..w {
                    v -= diag[i + c * w].load() * ys[i];
                }
                ys[c] = v;
            }
        }
    }
}

/// The relaxed supernodes of `L`: `(start, row_ptr, rows)` as in [`SupernodalFactor`].
///
/// Column `j + 1` joins the supernode ending at `j` when it is `j`'s parent in the elimination
/// tree (the smallest row below `j`'s diagonal), the block stays within [`MAX_WIDTH`] columns,
/// and its entries (the `w × w` triangle and `w |B|`) stay within [`RELAXATION`] times the
/// structural entries of its columns.
fn partition(n: usize, l: &SimplicialColumns<'_>) -> (Vec<usize>, Vec<usize>, Vec<u32>) {
    let mut start = Vec::new();
    let mut row_ptr = vec![0];
    let mut rows: Vec<u32> = Vec::new();
    // mark[r] == stamp: r is a row of the current supernode's columns below its last column.
    let mut mark = vec![usize::MAX; n];
    let mut members: Vec<usize> = Vec::new();
    let mut j = 0;
    while j < n {
        let s = j;
        start.push(s);
        members.clear();
        let mut below = 0usize; // |B|: marked rows > e
        let mut structural = 0usize; // off-diagonal entries of the columns
        let mut e = s;
        let add = |col: usize, mark: &mut [usize], members: &mut Vec<usize>, below: &mut usize| {
            let (ri, _) = l.column(col);
            for &r in &ri[1..] {
                let r = r as usize;
                if r > col && mark[r] != s {
                    mark[r] = s;
                    members.push(r);
                    *below += 1;
                }
            }
        };
        add(s, &mut mark, &mut members, &mut below);
        structural += l.nz[s] as usize - 1;
        loop {
            let next = e + 1;
            if next >= n || mark[next] != s || next - s + 1 > MAX_WIDTH {
                break;
            }
            // parent(e) == next: every row of e below it is > next or next itself.
            let (ri, _) = l.column(e);
            let parent = ri[1..].iter().map(|&r| r as usize).min();
            if parent != Some(next) {
                break;
            }
            // Rows of `next` below it not yet marked.
            let (rn, _) = l.column(next);
            let fresh = rn[1..].iter().filter(|&&r| mark[r as usize] != s).count();
            let w = next - s + 1;
            let m = below - 1 + fresh;
            let dense = w * (w - 1) / 2 + w * m;
            let structural_next = structural + l.nz[next] as usize - 1;
            if dense as f64 > RELAXATION * structural_next as f64 + 8.0 {
                break;
            }
            below -= 1; // next becomes a column of the block
            add(next, &mut mark, &mut members, &mut below);
            structural = structural_next;
            e = next;
        }
        let mut b: Vec<u32> = members.iter().filter(|&&r| r > e).map(|&r| r as u32).collect();
        b.sort_unstable();
        rows.extend_from_slice(&b);
        row_ptr.push(rows.len());
        j = e + 1;
    }
    start.push(n);
    (start, row_ptr, rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense `LDLᵀ` of a random SPD matrix with a sparse `L`, given as simplicial columns.
    fn simplicial(n: usize, seed: u64) -> (Vec<i32>, Vec<i32>, Vec<i32>, Vec<f64>) {
        let mut state = seed;
        let mut rnd = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64) / ((1u64 << 53) as f64)
        };
        let (mut p, mut nz, mut i, mut x) = (vec![], vec![], vec![], vec![]);
        for j in 0..n {
            p.push(i.len() as i32);
            i.push(j as i32);
            x.push(1.0 + rnd());
            let mut count = 1;
            // a chain to the parent j + 1 most of the time, and a few rows further down,
            // in no particular order
            let mut rs: Vec<usize> = (j + 1..n).filter(|_| rnd() < 0.15).collect();
            if j + 1 < n && rnd() < 0.7 && !rs.contains(&(j + 1)) {
                rs.push(j + 1);
            }
            rs.reverse();
            for r in rs {
                i.push(r as i32);
                x.push(rnd() - 0.5);
                count += 1;
            }
            nz.push(count);
        }
        p.push(i.len() as i32);
        (p, nz, i, x)
    }

    /// `L D Lᵀ y = b` by the columns themselves.
    fn reference_solve(n: usize, l: &SimplicialColumns<'_>, b: &[f64]) -> Vec<f64> {
        let mut y = b.to_vec();
        for j in 0..n {
            let (ri, rx) = l.column(j);
            for (&r, &v) in ri.iter().zip(rx).skip(1) {
                y[r as usize] -= v * y[j];
            }
        }
        for j in 0..n {
            y[j] /= l.column(j).1[0];
        }
        for j in (0..n).rev() {
            let (ri, rx) = l.column(j);
            let mut v = y[j];
            for (&r, &lv) in ri.iter().zip(rx).skip(1) {
                v -= lv * y[r as usize];
            }
            y[j] = v;
        }
        y
    }

    #[test]
    fn the_copy_solves_as_the_columns_do() {
        for (n, seed) in [(1, 1), (7, 2), (60, 3), (300, 4)] {
            let (p, nz, i, x) = simplicial(n, seed);
            let l = SimplicialColumns { p: &p, nz: &nz, i: &i, x: &x };
            let mut f = SupernodalFactor::<f64>::from_simplicial(n, &l);
            let b: Vec<f64> = (0..n).map(|k| ((k * 7919) % 13) as f64 - 6.0).collect();
            let want = reference_solve(n, &l, &b);
            let mut y = b.clone();
            f.solve(&mut y);
            let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (a, w) in y.iter().zip(&want) {
                // the same products in another order: round-off of a few ulps of the largest
                assert!((a - w).abs() <= 1e-12 * scale, "n {n}: {a} against {w}");
            }
            assert!(f.supernodes() <= n);
        }
    }

    #[test]
    fn the_f32_copy_solves_with_the_values_rounded_and_sums_in_f64() {
        // L stored as f32, D and the sums in f64: the solution of the factor whose L is rounded
        // to f32, to the round-off of f64 sums.
        let n = 200;
        let (p, nz, i, x) = simplicial(n, 6);
        // L's values rounded to f32, D's (each column's first entry) kept
        let mut rounded: Vec<f64> = x.iter().map(|&v| f64::from(v as f32)).collect();
        for &pj in &p[..n] {
            rounded[pj as usize] = x[pj as usize];
        }
        let l = SimplicialColumns { p: &p, nz: &nz, i: &i, x: &x };
        let lr = SimplicialColumns { p: &p, nz: &nz, i: &i, x: &rounded };
        let b: Vec<f64> = (0..n).map(|k| ((k * 31) % 17) as f64 - 8.0).collect();
        let want = reference_solve(n, &lr, &b);
        let mut f = SupernodalFactor::<f32>::from_simplicial(n, &l);
        let mut y = b.clone();
        f.solve(&mut y);
        let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, w) in y.iter().zip(&want) {
            assert!((a - w).abs() <= 1e-12 * scale, "{a} against {w}");
        }
        // D is kept in f64: 1/D_jj exact to f64, not to f32
        assert_eq!(f.d_inv[0], 1.0 / x[0]);
    }

    #[test]
    fn chains_merge_and_blocks_stay_within_the_relaxation() {
        let (p, nz, i, x) = simplicial(300, 5);
        let l = SimplicialColumns { p: &p, nz: &nz, i: &i, x: &x };
        let f = SupernodalFactor::<f64>::from_simplicial(300, &l);
        let structural: usize = nz.iter().map(|&c| c as usize - 1).sum();
        // a merged chain is what the layout is for: fewer supernodes than columns
        assert!(f.supernodes() < 300, "{} supernodes", f.supernodes());
        // every block within RELAXATION × its structure + 8, the w × w blocks' diagonals and
        // upper triangles (stored, not read) besides
        let upper: usize = (0..f.supernodes())
            .map(|k| {
                let w = f.start[k + 1] - f.start[k];
                w * (w + 1) / 2
            })
            .sum();
        let bound = RELAXATION * structural as f64 + 8.0 * f.supernodes() as f64 + upper as f64;
        assert!(f.stored() as f64 <= bound, "{} stored for {structural}", f.stored());
    }
}
