//! The assembled mechanical model: beam stiffnesses mapped to the generalized coordinates,
//! internal forces, the global sparse matrix and the low-rank factors of element terms.
//!
//! A beam `b` between stones `i`, `j` has the 6×6 stiffness `K_b = ∂f/∂(q_i, q_j)`
//! ([`mechanics::beam_stiffness`]); with `q = G z[idx]` ([`DofMap::pair_map`]) its contribution
//! in `z` is `K_z = Gᵀ K_b G` and its internal force `f_z = K_z z[idx]` (exact: the beam law is
//! linear). The equations are the unknown rows of `Σ f_z = f_ext`; the rows of prescribed `z`
//! entries give the reactions. The global matrix is `K_uu` (unknown rows and columns), assembled
//! as an upper triangle.
use nalgebra::{SMatrix, SVector};

use super::dofs::DofMap;
use super::error::DemError;
use super::factor::{SparseColumn, UpperTriplets};
use crate::dem::mechanics::{self, BeamGeom, MechParams, Thresholds};
use crate::dem::sample::Sample;
use faer::sparse::Triplet;

/// A symmetric element term in `z`: indices and 6×6 matrix.
#[derive(Clone, Debug)]
pub struct ZTerm {
    /// The six `z` indices (may repeat for two stones of one platen).
    pub idx: [usize; 6],
    /// The matrix `Gᵀ K G`.
    pub k: SMatrix<f64, 6, 6>,
}

/// A beam's `z`-stiffness for products: its upper triangle packed row by row (21 of the 36
/// entries) with 32-bit indices, 192 bytes against a [`ZTerm`]'s 336. The products over all
/// beams (internal forces, stored energy) stream these from memory once per pass, so their time
/// follows the bytes: 27k beams of a 10k-stone sample, 9.1 MB a pass as `ZTerm`s, 5.2 MB packed.
#[derive(Clone, Debug)]
pub struct PackedTerm {
    idx: [u32; 6],
    k: [f64; 21],
}

impl PackedTerm {
    fn of(t: &ZTerm) -> PackedTerm {
        let mut k = [0.0; 21];
        let mut p = 0;
        for a in 0..6 {
            for b in a..6 {
                k[p] = t.k[(a, b)];
                p += 1;
            }
        }
        PackedTerm { idx: t.idx.map(|i| i as u32), k }
    }

    fn gather(&self, z: &[f64]) -> [f64; 6] {
        self.idx.map(|i| z[i as usize])
    }

    /// `K x` (the term is symmetric).
    fn times(&self, x: &[f64; 6]) -> [f64; 6] {
        let mut y = [0.0; 6];
        let mut p = 0;
        for a in 0..6 {
            y[a] += self.k[p] * x[a];
            p += 1;
            for b in a + 1..6 {
                y[a] += self.k[p] * x[b];
                y[b] += self.k[p] * x[a];
                p += 1;
            }
        }
        y
    }

    /// `½ xᵀ K x`.
    fn energy(&self, x: &[f64; 6]) -> f64 {
        let (mut diag, mut off) = (0.0, 0.0);
        let mut p = 0;
        for a in 0..6 {
            diag += self.k[p] * x[a] * x[a];
            p += 1;
            for b in a + 1..6 {
                off += self.k[p] * x[a] * x[b];
                p += 1;
            }
        }
        0.5 * diag + off
    }

    /// Adds `K z[idx]` to `out[idx]`.
    fn add_force(&self, z: &[f64], out: &mut [f64]) {
        let f = self.times(&self.gather(z));
        for a in 0..6 {
            out[self.idx[a] as usize] += f[a];
        }
    }
}

/// The beams of a sample, ready for assembly.
pub struct Model<'a> {
    /// The sample.
    pub sample: &'a Sample,
    /// Lattice parameters.
    pub params: MechParams,
    /// Failure thresholds (deterministic).
    pub thresholds: Thresholds,
    /// DOF map.
    pub map: DofMap,
    /// Per beam geometry.
    pub geoms: Vec<BeamGeom>,
    /// Per beam stiffness in `z`.
    pub terms: Vec<ZTerm>,
    /// The same, packed for the products over all beams ([`PackedTerm`]).
    packed: Vec<PackedTerm>,
    /// The beams with a `z` index on a platen, in beam order: the only ones whose forces reach
    /// the platens' rows ([`Self::add_platen_beam_forces`]).
    pub platen_beams: Vec<usize>,
}

impl<'a> Model<'a> {
    /// Builds the geometry and `z`-stiffness of every beam. Errors: invalid parameters or beams.
    pub fn new(sample: &'a Sample, params: &MechParams, map: DofMap) -> Result<Model<'a>, DemError> {
        params.validate().map_err(DemError::Params)?;
        let mut geoms = Vec::with_capacity(sample.beams.len());
        let mut terms = Vec::with_capacity(sample.beams.len());
        for (k, b) in sample.beams.iter().enumerate() {
            let err = |source| DemError::Beam { beam: k, i: b.i, j: b.j, source };
            let g =
                BeamGeom { ell: b.length, n: b.normal, r_i: b.arm_i, r_j: b.arm_j, area: b.area, inertia: b.inertia };
            g.validate().map_err(err)?;
            let (idx, gm) = map.pair_map(b.i, b.j);
            let kz = gm.transpose() * mechanics::beam_stiffness(&g, params) * gm;
            geoms.push(g);
            terms.push(ZTerm { idx, k: (kz + kz.transpose()) * 0.5 });
        }
        let on_platen = |k: usize| map.platen_base.iter().any(|&b| (b..b + 3).contains(&k));
        let platen_beams = (0..terms.len()).filter(|&b| terms[b].idx.iter().any(|&k| on_platen(k))).collect();
        if map.n_z > u32::MAX as usize {
            return Err(DemError::InvalidParameter {
                field: "sample size",
                value: format!("{} coordinates", map.n_z),
                expected: "at most 2^32 coordinates",
            });
        }
        let packed = terms.iter().map(PackedTerm::of).collect();
        Ok(Model { sample, params: *params, thresholds: params.thresholds(), map, geoms, terms, packed, platen_beams })
    }

    /// Stones `(q_i, q_j)` of beam `b` for coordinates `z`.
    pub fn beam_dofs(&self, b: usize, z: &[f64]) -> ([f64; 3], [f64; 3]) {
        let beam = &self.sample.beams[b];
        (self.map.particle_dofs(beam.i, z), self.map.particle_dofs(beam.j, z))
    }

    /// `z[idx]` of a term.
    pub fn gather(idx: &[usize; 6], z: &[f64]) -> SVector<f64, 6> {
        SVector::<f64, 6>::from_fn(|a, _| z[idx[a]])
    }

    /// Adds the internal forces of the intact beams to `out` (length `n_z`).
    pub fn add_beam_forces(&self, intact: &[bool], z: &[f64], out: &mut [f64]) {
        for (t, _) in self.packed.iter().zip(intact).filter(|(_, &ok)| ok) {
            t.add_force(z, out);
        }
    }

    /// Adds the internal forces of the intact beams that reach a platen to `out`: the platens'
    /// rows of [`Self::add_beam_forces`] bit for bit (the same terms added in the same order;
    /// the other rows get only these beams' part).
    pub fn add_platen_beam_forces(&self, intact: &[bool], z: &[f64], out: &mut [f64]) {
        for &b in self.platen_beams.iter().filter(|&&b| intact[b]) {
            self.packed[b].add_force(z, out);
        }
    }

    /// Adds the internal force of beam `b` to `out` (the same product as
    /// [`Self::add_beam_forces`]'s, so that a released beam's force cancels its own part there).
    pub fn add_beam_force(&self, b: usize, z: &[f64], out: &mut [f64]) {
        self.packed[b].add_force(z, out);
    }

    /// Elastic energy `½ z_bᵀ K_z z_b` of beam `b`.
    pub fn beam_energy(&self, b: usize, z: &[f64]) -> f64 {
        let t = &self.packed[b];
        t.energy(&t.gather(z))
    }

    /// Scatters a `z`-space 6×6 term (times `scale`) into upper triplets in equation space.
    pub fn push_term(&self, idx: &[usize; 6], k: &SMatrix<f64, 6, 6>, scale: f64, out: &mut UpperTriplets) {
        for a in 0..6 {
            let Some(r) = self.map.eq[idx[a]] else { continue };
            for b in 0..6 {
                let Some(c) = self.map.eq[idx[b]] else { continue };
                if r <= c {
                    out.push(Triplet::new(r, c, scale * k[(a, b)]));
                }
            }
        }
    }

    /// The upper triangle of `K_uu` from all beams (broken ones as explicit zeros, so the
    /// structure never changes), plus the diagonal `reg`, plus `extra` terms.
    pub fn assemble(&self, intact: &[bool], reg: &[f64], extra: &[ZTerm]) -> UpperTriplets {
        let mut t = Vec::with_capacity(self.terms.len() * 21 + reg.len());
        for (term, &ok) in self.terms.iter().zip(intact) {
            self.push_term(&term.idx, &term.k, if ok { 1.0 } else { 0.0 }, &mut t);
        }
        for e in extra {
            self.push_term(&e.idx, &e.k, 1.0, &mut t);
        }
        for (r, &v) in reg.iter().enumerate() {
            t.push(Triplet::new(r, r, v));
        }
        t
    }

    /// The diagonal of `K_uu` with all beams intact.
    pub fn diagonal(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.map.n_eq()];
        for t in &self.terms {
            for a in 0..6 {
                for b in 0..6 {
                    if let (Some(r), Some(c)) = (self.map.eq[t.idx[a]], self.map.eq[t.idx[b]]) {
                        if r == c {
                            d[r] += t.k[(a, b)];
                        }
                    }
                }
            }
        }
        d
    }

    /// Low-rank factors of a PSD `z` term in equation space: `R K_z Rᵀ = Σ u uᵀ`, from the
    /// eigen-decomposition `K_z = Σ λ v vᵀ` (`u = √λ R v`, eigenvalues below 1e-12 λ_max dropped);
    /// each `u` has at most six non-zeros.
    pub fn factors(&self, term: &ZTerm) -> Vec<SparseColumn> {
        let eig = nalgebra::SymmetricEigen::new(term.k);
        let lmax = eig.eigenvalues.iter().fold(0.0f64, |m, &l| m.max(l));
        let mut cols = Vec::new();
        for (k, &l) in eig.eigenvalues.iter().enumerate() {
            if l <= 1e-12 * lmax || l <= 0.0 {
                continue;
            }
            let mut u: SparseColumn = Vec::with_capacity(6);
            for a in 0..6 {
                if let Some(r) = self.map.eq[term.idx[a]] {
                    let v = l.sqrt() * eig.eigenvectors[(a, k)];
                    match u.iter_mut().find(|(i, _)| *i == r) {
                        Some(e) => e.1 += v, // a platen's DOF shared by two slave stones
                        None => u.push((r, v)),
                    }
                }
            }
            if !u.is_empty() {
                cols.push(u);
            }
        }
        cols
    }

    /// A rank-1 term `w wᵀ` in `z` for a pair direction `d` (in `(q_i, q_j)`) of stiffness `k`:
    /// `w = √k Gᵀ d`.
    pub fn rank_one(&self, i: usize, j: usize, d: &SVector<f64, 6>, k: f64) -> ZTerm {
        let (idx, g) = self.map.pair_map(i, j);
        let w = g.transpose() * d * k.max(0.0).sqrt();
        ZTerm { idx, k: w * w.transpose() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_terms_give_the_dense_products() {
        // A symmetric 6×6 term with entries of mixed sizes (k_ab = (a + 1)(b + 1) 10^(a−b) +
        // δ_ab 50, indices repeating one coordinate as two slave stones of a platen do): K x and
        // ½ xᵀ K x from the packed upper triangle equal the dense products to 1e-14 of their size.
        let k = SMatrix::<f64, 6, 6>::from_fn(|a, b| {
            let s = ((a + 1) * (b + 1)) as f64 * 10f64.powi(a.min(b) as i32 - a.max(b) as i32);
            s + if a == b { 50.0 } else { 0.0 }
        });
        let t = ZTerm { idx: [3, 7, 1, 3, 0, 9], k };
        let z: Vec<f64> = (0..10).map(|i| (0.7 * i as f64).sin() - 0.2).collect();
        let p = PackedTerm::of(&t);
        let x = Model::gather(&t.idx, &z);
        let dense = k * x;
        let packed = p.times(&p.gather(&z));
        for a in 0..6 {
            assert!((packed[a] - dense[a]).abs() <= 1e-14 * dense.amax(), "row {a}: {} vs {}", packed[a], dense[a]);
        }
        let e = 0.5 * x.dot(&dense);
        assert!((p.energy(&p.gather(&z)) - e).abs() <= 1e-14 * e.abs(), "energy");
        let mut out = vec![0.0; 10];
        p.add_force(&z, &mut out);
        let mut expected = [0.0; 10];
        for a in 0..6 {
            expected[t.idx[a]] += dense[a];
        }
        for i in 0..10 {
            assert!((out[i] - expected[i]).abs() <= 1e-14 * dense.amax(), "coordinate {i}");
        }
    }
}
