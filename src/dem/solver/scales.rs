//! The sample's fixed scales, computed once from the model: the regularization springs, the
//! continuation's masses, the moment weight and step cap of Newton's method, and the contact
//! law's round-off.
use super::system::Model;

/// The regularization spring of every unknown, relative to its diagonal with all beams intact
/// ([`super::stage`], "Regularization").
const REGULARIZATION: f64 = 1e-10;
/// `f_ε = ROUNDOFF_FACTOR · ε_mach · X · Ē t_z`: the round-off of a contact force, below which a
/// residual counts as converged ([`super::equilibrium`], module docs).
const ROUNDOFF_FACTOR: f64 = 64.0;
/// The largest move of a stone in one Newton iteration, as a fraction of the mean diameter.
const MAX_MOVE_FRACTION: f64 = 0.05;

/// Scales of one sample (module docs).
#[derive(Clone, Debug)]
pub struct Scales {
    /// The regularization spring `ε_k` of every equation.
    pub reg: Vec<f64>,
    /// Each unknown's diagonal with every beam intact (a positive fallback where it has none):
    /// the scale of the regularization springs and the continuation's masses.
    pub intact_diagonal: Vec<f64>,
    /// Mean stone diameter D̄ (m): weighs moments in the merit function.
    pub mean_diameter: f64,
    /// Largest move of a stone in one Newton iteration (m): 5 % of D̄.
    pub max_move: f64,
    /// The round-off of a contact force, `f_ε` of [`super::equilibrium`]'s convergence scale (N).
    pub roundoff_force: f64,
}

impl Scales {
    /// The scales of `model`'s sample.
    pub fn of(model: &Model<'_>) -> Scales {
        let diag = model.diagonal();
        let positive: Vec<f64> = diag.iter().copied().filter(|d| *d > 0.0).collect();
        let mean = positive.iter().sum::<f64>() / positive.len().max(1) as f64;
        let intact_diagonal: Vec<f64> = diag.iter().map(|&d| if d > 0.0 { d } else { mean.max(1.0) }).collect();
        let reg = intact_diagonal.iter().map(|d| REGULARIZATION * d).collect();
        let mean_diameter = model.sample.mean_diameter();
        let extent = model
            .sample
            .particles
            .iter()
            .flat_map(|p| p.polygon.vertices.iter())
            .fold(0.0f64, |m, v| m.max(v[0].abs()).max(v[1].abs()));
        let roundoff_force = ROUNDOFF_FACTOR * f64::EPSILON * extent * model.params.e_bar * model.params.t_z;
        Scales { reg, intact_diagonal, mean_diameter, max_move: MAX_MOVE_FRACTION * mean_diameter, roundoff_force }
    }
}
