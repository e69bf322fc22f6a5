//! The mass matrix of the flat shells in their local frame (the formulation: the module docs of
//! [`super::element`], "Mass").
use nalgebra::SMatrix;

use super::element::ShellElement;
use crate::element::MassKind;

impl<const N: usize, const D: usize> ShellElement<N, D> {
    /// Mass matrix in the flat local frame: `M_ab = ∫ N_a N_b dA` times m₀ (ρ t + non-structural
    /// mass) on the translations and I_r = ρ t³/12 on the rotations; lumped, its row sums on the
    /// diagonal.
    pub(super) fn local_mass(&self, kind: MassKind) -> SMatrix<f64, D, D> {
        let m0 = self.section().mass_per_area();
        let ir = self.section().rotary_inertia_per_area();
        let dens = [m0, m0, m0, ir, ir, ir];
        let mut m = SMatrix::<f64, D, D>::zeros();
        for pt in &self.points {
            for a in 0..N {
                for b in 0..N {
                    let v = pt.weight * pt.shape[a] * pt.shape[b];
                    for (k, d) in dens.iter().enumerate() {
                        match kind {
                            MassKind::Consistent => m[(6 * a + k, 6 * b + k)] += d * v,
                            MassKind::Lumped => m[(6 * a + k, 6 * a + k)] += d * v,
                        }
                    }
                }
            }
        }
        m
    }
}
