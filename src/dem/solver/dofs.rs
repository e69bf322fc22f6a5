//! Degrees of freedom: free stones, and stones bonded to the two rigid platens (paper §2.1,
//! "Virtual tests").
//!
//! # Platens as master–slave constraints
//! Each platen `k` (0 = bottom, 1 = top) is a rigid body with master DOFs `Q_k = (U_x, U_y, Θ)`
//! about its reference point `r_k` (the midpoint of its edge: `(W/2, 0)` or `(W/2, H)`). A stone
//! `p` of the bottom (top) row is a slave, `q_p = T_p Q_k`:
//!
//! ```text
//!   q_x = U_x − Θ (c_y − r_y)          [ 1  0  −(c_y − r_y) ]
//!   q_y = U_y + Θ (c_x − r_x)    T_p = [ 0  1    c_x − r_x  ]      (linear kinematics)
//!   θ   = Θ                            [ 0  0        1      ]
//! ```
//!
//! # Numbering
//! The generalized coordinates `z` are the 3 DOFs of every non-slave stone (in particle order),
//! then the bottom platen's 3, then the top platen's 3. Each `z` entry is either an unknown
//! (equation number) or prescribed (displacement control). Force-controlled platen DOFs are
//! unknowns with a given external force. A stone's DOFs are `q_p = T_p z[idx_p]`, and an element
//! of stiffness `K` in `(q_i, q_j)` contributes `Gᵀ K G` in `z`, `G = diag(T_i, T_j)`.
use nalgebra::Matrix3;

use super::error::DemError;
use crate::dem::sample::Sample;

/// How one platen DOF is driven.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DofControl {
    /// Displacement control: the value is imposed (0 = fixed); its reaction is computed.
    Prescribed,
    /// Force control: an external force is given (0 = free); the displacement is unknown.
    Force,
}

/// The control of a platen's three DOFs `(U_x, U_y, Θ)`.
pub type PlatenControl = [DofControl; 3];

/// Where a stone's DOFs live.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Owner {
    /// Its own three `z` entries, from `base`.
    Free { base: usize },
    /// Slave of platen `platen` (0 bottom, 1 top), arm `c_p − r_k`.
    Slave { platen: usize, arm: [f64; 2] },
}

/// The map particles ↔ generalized coordinates ↔ equations.
#[derive(Clone, Debug)]
pub struct DofMap {
    owners: Vec<Owner>,
    /// Number of generalized coordinates `z`.
    pub n_z: usize,
    /// First `z` index of each platen (bottom, top).
    pub platen_base: [usize; 2],
    /// Each platen's reference point.
    pub platen_ref: [[f64; 2]; 2],
    /// Equation number of each `z` entry (`None` = prescribed).
    pub eq: Vec<Option<usize>>,
    /// The `z` entries that are equations, in equation order.
    pub unknowns: Vec<usize>,
    /// `z` indices of the prescribed platen DOFs.
    pub prescribed: Vec<usize>,
    /// `z` indices of the force-controlled platen DOFs.
    pub forced: Vec<usize>,
}

impl DofMap {
    /// The map for `sample` with platens bonded to `boundary.bottom` and `boundary.top`,
    /// controlled by `control[0]` (bottom) and `control[1]` (top).
    /// Errors: an empty bottom or top row, or a stone in both.
    pub fn new(sample: &Sample, control: [PlatenControl; 2]) -> Result<DofMap, DemError> {
        let n = sample.particles.len();
        let rows = [&sample.boundary.bottom, &sample.boundary.top];
        let refs = [[0.5 * sample.width, 0.0], [0.5 * sample.width, sample.height]];
        let mut platen_of = vec![None; n];
        for (k, row) in rows.iter().enumerate() {
            if row.is_empty() {
                let side = ["bottom", "top"][k];
                return Err(DemError::BadSample { reason: format!("no stone touches the {side} side") });
            }
            for &p in row.iter() {
                if p >= n {
                    return Err(DemError::BadSample { reason: format!("boundary stone {p} does not exist") });
                }
                if platen_of[p].is_some() {
                    return Err(DemError::BadSample {
                        reason: format!("stone {p} touches both the bottom and the top side (one course only?)"),
                    });
                }
                platen_of[p] = Some(k);
            }
        }
        let mut owners = Vec::with_capacity(n);
        let mut next = 0;
        for (p, part) in sample.particles.iter().enumerate() {
            owners.push(match platen_of[p] {
                Some(k) => {
                    let c = part.centroid;
                    Owner::Slave { platen: k, arm: [c[0] - refs[k][0], c[1] - refs[k][1]] }
                }
                None => {
                    next += 3;
                    Owner::Free { base: next - 3 }
                }
            });
        }
        let platen_base = [next, next + 3];
        let n_z = next + 6;
        let mut eq = vec![None; n_z];
        let (mut unknowns, mut prescribed, mut forced) = (Vec::new(), Vec::new(), Vec::new());
        for z in 0..n_z {
            let ctl = if z < next { DofControl::Force } else { control[(z - next) / 3][(z - next) % 3] };
            match ctl {
                DofControl::Prescribed => prescribed.push(z),
                DofControl::Force => {
                    if z >= next {
                        forced.push(z);
                    }
                    eq[z] = Some(unknowns.len());
                    unknowns.push(z);
                }
            }
        }
        Ok(DofMap { owners, n_z, platen_base, platen_ref: refs, eq, unknowns, prescribed, forced })
    }

    /// The stone whose own `z` entries include index `zi`; `None` for a platen's entries (a
    /// stone bonded to a platen has none of its own).
    pub fn stone_of(&self, zi: usize) -> Option<usize> {
        let base = zi - zi % 3;
        self.owners.iter().position(|o| matches!(o, Owner::Free { base: b } if *b == base))
    }

    /// Number of equations (unknowns).
    pub fn n_eq(&self) -> usize {
        self.unknowns.len()
    }

    /// Whether stone `p` is bonded to a platen.
    pub fn is_slave(&self, p: usize) -> bool {
        matches!(self.owners[p], Owner::Slave { .. })
    }

    /// Stone `p`'s `z` indices and the 3×3 map `T_p` with `q_p = T_p z[idx]`.
    pub fn particle_map(&self, p: usize) -> ([usize; 3], Matrix3<f64>) {
        match self.owners[p] {
            Owner::Free { base } => ([base, base + 1, base + 2], Matrix3::identity()),
            Owner::Slave { platen, arm } => {
                let b = self.platen_base[platen];
                ([b, b + 1, b + 2], Matrix3::new(1.0, 0.0, -arm[1], 0.0, 1.0, arm[0], 0.0, 0.0, 1.0))
            }
        }
    }

    /// Stone `p`'s DOFs `q_p = T_p z[idx]` (written out: this runs for every stone in every
    /// residual evaluation and failure scan).
    #[inline]
    pub fn particle_dofs(&self, p: usize, z: &[f64]) -> [f64; 3] {
        match self.owners[p] {
            Owner::Free { base } => [z[base], z[base + 1], z[base + 2]],
            Owner::Slave { platen, arm } => {
                let b = self.platen_base[platen];
                let (ux, uy, th) = (z[b], z[b + 1], z[b + 2]);
                [ux - arm[1] * th, uy + arm[0] * th, th]
            }
        }
    }

    /// Adds the generalized force `f_p` on stone `p` to `out` (in `z`): `out[idx] += T_pᵀ f_p`.
    pub fn scatter_force(&self, p: usize, f_p: [f64; 3], out: &mut [f64]) {
        let (idx, t) = self.particle_map(p);
        let g = t.transpose() * nalgebra::Vector3::from(f_p);
        for a in 0..3 {
            out[idx[a]] += g[a];
        }
    }

    /// The `z` indices and `G = diag(T_i, T_j)` of a pair element.
    pub fn pair_map(&self, i: usize, j: usize) -> ([usize; 6], nalgebra::SMatrix<f64, 6, 6>) {
        let (ii, ti) = self.particle_map(i);
        let (jj, tj) = self.particle_map(j);
        let mut g = nalgebra::SMatrix::<f64, 6, 6>::zeros();
        g.fixed_view_mut::<3, 3>(0, 0).copy_from(&ti);
        g.fixed_view_mut::<3, 3>(3, 3).copy_from(&tj);
        ([ii[0], ii[1], ii[2], jj[0], jj[1], jj[2]], g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::sample::{CoursedLayout, SampleConfig, SampleLayout};

    fn wall() -> Sample {
        let cfg = SampleConfig {
            layout: SampleLayout::Coursed(CoursedLayout {
                width: 1.0,
                height: 1.2,
                n_courses: 4,
                n_per_course: 3,
                jitter: 0.1,
                stagger: 1.0,
                size_variability: 0.0,
            }),
            thickness: 1.0,
            seed: 3,
            alpha: 0.8,
            facet_tolerance: 0.02,
            tiny_facets: Default::default(),
        };
        Sample::build(&cfg).unwrap()
    }

    #[test]
    fn every_own_entry_names_its_stone() {
        // Each free stone's three z entries name it; the platens' six entries name none, and no
        // entry names a slave stone.
        let s = wall();
        let map = DofMap::new(&s, [[DofControl::Prescribed; 3]; 2]).unwrap();
        let mut named = 0;
        for zi in 0..map.n_z {
            match map.stone_of(zi) {
                Some(p) => {
                    assert!(!map.is_slave(p));
                    let mut z = vec![0.0; map.n_z];
                    z[zi] = 1.0;
                    assert_eq!(map.particle_dofs(p, &z)[zi % 3], 1.0, "entry {zi}, stone {p}");
                    named += 1;
                }
                None => assert!(zi >= map.platen_base[0], "entry {zi}"),
            }
        }
        assert_eq!(named, map.n_z - 6);
    }

    #[test]
    fn slaves_follow_the_platen_rigidly() {
        // A top-platen rotation Θ about (W/2, H) moves a slave centroid c by Θ e_z × (c − r):
        // the same as kinematics::rigid_motion_dofs (exact identity, tolerance 1e-15).
        let s = wall();
        use DofControl::*;
        let map = DofMap::new(&s, [[Prescribed; 3], [Prescribed, Force, Force]]).unwrap();
        assert_eq!(map.n_eq(), 3 * (s.particles.len() - s.boundary.bottom.len() - s.boundary.top.len()) + 2);
        assert_eq!(map.forced, vec![map.platen_base[1] + 1, map.platen_base[1] + 2]);
        let mut z = vec![0.0; map.n_z];
        let b = map.platen_base[1];
        z[b] = 1e-3;
        z[b + 1] = -2e-3;
        z[b + 2] = 5e-4;
        for &p in &s.boundary.top {
            let c = s.particles[p].centroid;
            let want = crate::dem::mechanics::kinematics::rigid_motion_dofs([0.5, 1.2], [1e-3, -2e-3], 5e-4, c);
            let got = map.particle_dofs(p, &z);
            for a in 0..3 {
                assert!((got[a] - want[a]).abs() < 1e-15);
            }
        }
        for &p in &s.boundary.bottom {
            assert_eq!(map.particle_dofs(p, &z), [0.0; 3]);
        }
    }

    #[test]
    fn particle_dofs_equal_the_map() {
        // q_p = T_p z[idx] for every stone, free and slave, against the matrix product
        // (round-off only: 1e-15 of the largest entry).
        let s = wall();
        use DofControl::*;
        let map = DofMap::new(&s, [[Prescribed; 3], [Prescribed, Force, Force]]).unwrap();
        let z: Vec<f64> = (0..map.n_z).map(|k| 1e-3 * ((k as f64) * 0.77).sin()).collect();
        for p in 0..s.particles.len() {
            let (idx, t) = map.particle_map(p);
            let want = t * nalgebra::Vector3::new(z[idx[0]], z[idx[1]], z[idx[2]]);
            let got = map.particle_dofs(p, &z);
            for a in 0..3 {
                assert!((got[a] - want[a]).abs() <= 1e-15 * 1e-3, "stone {p}: {got:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn empty_row_is_an_error() {
        let mut s = wall();
        s.boundary.top.clear();
        assert!(matches!(DofMap::new(&s, [[DofControl::Prescribed; 3]; 2]), Err(DemError::BadSample { .. })));
    }
}
