//! The mass and the weight of the whole model, which every structural run prints after its setup:
//!
//! ```text
//!   m_d = Σ_elements ι_dᵀ M_e ι_d + Σ point masses_d        W = Σ_elements f_g,e + Σ m_p g
//! ```
//!
//! ι_d the unit translation along d at every node of the element (support nodes included, unlike
//! the modal analysis's `total_mass`, the mass that moves with the free DOFs), `f_g,e` the
//! element's self-weight load under the job's `[gravity]` (zero without it). Translation-invariant
//! element masses make `m_d` the same for the lumped and the consistent matrix.
use super::Discretization;
use crate::element::MassKind;
use crate::model::StructuralModel;
use crate::parallel::Context;
use mpi::traits::CommunicatorCollectives;

/// The model's mass per direction [kg] and the resultant of its weight [N].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ModelMass {
    /// Mass along x, y, z [kg].
    pub mass: [f64; 3],
    /// The self-weight resultant (x, y, z) [N]: elements and point masses under `[gravity]`.
    pub weight: [f64; 3],
}

impl ModelMass {
    /// Collective. Summed over the owned elements of every rank (and the point masses, on the
    /// ranks that own their nodes).
    pub fn of(ctx: &Context, disc: &Discretization, model: &StructuralModel) -> ModelMass {
        let mut local = [0.0; 6];
        let mut me = nalgebra::DMatrix::zeros(12, 12);
        let mut fe = nalgebra::DVector::zeros(12);
        let g = model.gravity.unwrap_or([0.0; 3]);
        for e in &disc.elements {
            e.mass(MassKind::Lumped, &mut me);
            e.gravity_load(g, &mut fe);
            let nodes = me.nrows() / 6;
            for d in 0..3 {
                for a in 0..nodes {
                    local[d] += (0..nodes).map(|b| me[(6 * a + d, 6 * b + d)]).sum::<f64>();
                    local[3 + d] += fe[6 * a + d];
                }
            }
        }
        for &(n, diag) in &model.point_masses {
            if disc.dofs.owner[n] == disc.dofs.rank {
                for d in 0..3 {
                    local[d] += diag[d];
                    local[3 + d] += diag[d] * g[d];
                }
            }
        }
        let mut total = [0.0; 6];
        ctx.comm.all_reduce_into(&local[..], &mut total[..], mpi::collective::SystemOperation::sum());
        ModelMass { mass: [total[0], total[1], total[2]], weight: [total[3], total[4], total[5]] }
    }

    /// The log line: the mass (one number when the three directions agree) and the weight.
    pub fn line(&self) -> String {
        let [mx, my, mz] = self.mass;
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
        let mass = if same(mx, my) && same(my, mz) {
            format!("{mx:.6e} kg ({:.4} t)", mx / 1e3)
        } else {
            format!("x {mx:.6e}, y {my:.6e}, z {mz:.6e} kg")
        };
        let w = self.weight.iter().map(|v| v * v).sum::<f64>().sqrt();
        let weight = if w == 0.0 {
            "no [gravity]".to_string()
        } else {
            format!(
                "{w:.6e} N ({:.4} kN), resultant ({:.6e}, {:.6e}, {:.6e}) N",
                w / 1e3,
                self.weight[0],
                self.weight[1],
                self.weight[2]
            )
        };
        format!("model: mass {mass} (every element and point mass, support nodes included); weight {weight}")
    }
}
