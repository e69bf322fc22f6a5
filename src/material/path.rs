//! A material-point driver: a strain/stress path under mixed control, solved step by step with
//! Newton's method on the consistent tangent. Used for identification (the law's response on the
//! virtual tests' paths) and to check the law.
//!
//! # Mixed control
//! Every step gives, for each strain component i, either an imposed strain ε_i (set `E`) or an
//! imposed stress σ_i (set `S`, e.g. 0 for a free lateral face). The unknowns are ε_S; Newton solves
//!
//! ```text
//!   r_S(ε) = σ_S(ε) − σ̄_S = 0,     J = ∂σ_S/∂ε_S (the block of the tangent),   ε_S ← ε_S − J⁻¹ r_S
//! ```
//! starting from the previous converged strain with the new ε_E imposed, against the committed
//! history. Convergence: ‖r_S‖∞ ≤ rtol · max(E · max(‖ε‖∞, ε₀^t), ‖σ̄‖∞). When the tangent
//! iteration does not converge in `max_iterations` (e.g. crossing the stress jump at tr σ̃ = 0, see
//! [`response`](super::response)), the step continues with the secant matrix for as many iterations
//! again (slower but more robust); failing that, [`PathError::NoConvergence`] names the step.
//! Converged steps commit the trial history and add their dissipation.

use nalgebra::{SMatrix, SVector};

use super::law::PointLaw;
use super::response::StressState;
use super::state::DamageState;

/// What is imposed on one strain component during a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// Imposed total strain (engineering shear for shear components).
    Strain(f64),
    /// Imposed stress (Pa); `Stress(0.0)` leaves the component free.
    Stress(f64),
}

/// Errors of path construction and of the driver.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// A path constructor was given unusable arguments.
    #[error("invalid load path: {reason}")]
    InvalidPath {
        /// What is wrong.
        reason: String,
    },
    /// Newton's method did not reach the tolerance in a step.
    #[error(
        "material-point driver: step {step} did not converge after {iterations} iterations \
         (residual {residual:e} Pa > tolerance {tolerance:e} Pa)"
    )]
    NoConvergence {
        /// The step (1-based; step 0 is the initial state).
        step: usize,
        /// Iterations done (tangent and secant).
        iterations: usize,
        /// The last residual ‖r_S‖∞ (Pa).
        residual: f64,
        /// The tolerance (Pa).
        tolerance: f64,
    },
    /// The law returned a non-finite stress (the iteration diverged).
    #[error("material-point driver: non-finite stress at step {step}, iteration {iteration}")]
    NonFinite {
        /// The step (1-based).
        step: usize,
        /// The iteration.
        iteration: usize,
    },
}

/// A sequence of steps, each with one [`Control`] per strain component.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadPath<const N: usize> {
    steps: Vec<[Control; N]>,
}

fn invalid(reason: impl Into<String>) -> PathError {
    PathError::InvalidPath { reason: reason.into() }
}

fn check_steps(n: usize) -> Result<(), PathError> {
    if n == 0 {
        return Err(invalid("the number of steps must be at least 1"));
    }
    Ok(())
}

fn check_positive(what: &str, v: f64) -> Result<(), PathError> {
    crate::bounds::positive(v).map(drop).map_err(|b| invalid(format!("{what}: {b}")))
}

impl<const N: usize> LoadPath<N> {
    /// A path from explicit steps.
    pub fn new(steps: Vec<[Control; N]>) -> Self {
        LoadPath { steps }
    }

    /// The steps.
    pub fn steps(&self) -> &[[Control; N]] {
        &self.steps
    }

    /// Number of steps.
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    /// Whether the path has no step.
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// Steps imposing `imposed` (index, value at s = 1) proportionally, s = k/n for k = 1..=n from
    /// `start` (values at s = 0), every other component stress-free.
    fn ramp(start: &[(usize, f64)], end: &[(usize, f64)], n: usize, out: &mut Vec<[Control; N]>) {
        for k in 1..=n {
            let s = k as f64 / n as f64;
            let mut c = [Control::Stress(0.0); N];
            for (&(i, a), &(_, b)) in start.iter().zip(end) {
                c[i] = Control::Strain(a + s * (b - a));
            }
            out.push(c);
        }
    }

    /// ε_xx driven piecewise linearly from 0 through `targets`, `steps_per_segment` steps each,
    /// all other components stress-free (uniaxial stress).
    pub fn uniaxial(targets: &[f64], steps_per_segment: usize) -> Result<Self, PathError> {
        check_steps(steps_per_segment)?;
        if targets.is_empty() || targets.iter().any(|t| !t.is_finite()) {
            return Err(invalid(format!("uniaxial targets must be finite and non-empty, got {targets:?}")));
        }
        let mut steps = Vec::with_capacity(targets.len() * steps_per_segment);
        let mut from = 0.0;
        for &t in targets {
            Self::ramp(&[(0, from)], &[(0, t)], steps_per_segment, &mut steps);
            from = t;
        }
        Ok(LoadPath { steps })
    }

    /// Monotonic uniaxial tension ε_xx: 0 → `max_strain` (> 0) in `n_steps`, lateral stress free.
    pub fn uniaxial_tension(max_strain: f64, n_steps: usize) -> Result<Self, PathError> {
        check_positive("max_strain", max_strain)?;
        Self::uniaxial(&[max_strain], n_steps)
    }

    /// Monotonic uniaxial compression ε_xx: 0 → −`max_shortening` (give the magnitude, > 0) in
    /// `n_steps`, lateral stress free.
    pub fn uniaxial_compression(max_shortening: f64, n_steps: usize) -> Result<Self, PathError> {
        check_positive("max_shortening", max_shortening)?;
        Self::uniaxial(&[-max_shortening], n_steps)
    }

    /// Cyclic uniaxial tension–compression with amplitudes growing linearly over `cycles` cycles:
    /// 0 → +a_t/n → −a_c/n → +2a_t/n → … → +a_t → −a_c → 0, `steps_per_segment` steps per branch.
    pub fn cyclic_tension_compression(
        tension_amplitude: f64,
        compression_amplitude: f64,
        cycles: usize,
        steps_per_segment: usize,
    ) -> Result<Self, PathError> {
        check_positive("tension_amplitude", tension_amplitude)?;
        check_positive("compression_amplitude", compression_amplitude)?;
        check_steps(cycles)?;
        let mut targets = Vec::with_capacity(2 * cycles + 1);
        for k in 1..=cycles {
            let s = k as f64 / cycles as f64;
            targets.push(s * tension_amplitude);
            targets.push(-s * compression_amplitude);
        }
        targets.push(0.0);
        Self::uniaxial(&targets, steps_per_segment)
    }

    /// Proportional biaxial strain: ε_xx = s·`max_strain_xx`, ε_yy = `ratio`·ε_xx imposed, the other
    /// components stress-free (σ_zz = 0 in 3D; shear free). Needs at least two components.
    pub fn biaxial(max_strain_xx: f64, ratio: f64, n_steps: usize) -> Result<Self, PathError> {
        if N < 2 {
            return Err(invalid("a biaxial path needs the yy component (not the uniaxial kinematics)"));
        }
        check_steps(n_steps)?;
        if !(max_strain_xx.is_finite() && ratio.is_finite()) || max_strain_xx == 0.0 {
            return Err(invalid(format!(
                "biaxial strain must be finite and non-zero and the ratio finite, got {max_strain_xx}, {ratio}"
            )));
        }
        let mut steps = Vec::with_capacity(n_steps);
        Self::ramp(&[(0, 0.0), (1, 0.0)], &[(0, max_strain_xx), (1, ratio * max_strain_xx)], n_steps, &mut steps);
        Ok(LoadPath { steps })
    }

    /// Pure shear: γ_xy: 0 → `max_gamma` (engineering shear) imposed, normal stresses (and the other
    /// shears) zero. The kinematics `M` gives the index of γ_xy; the uniaxial one has none.
    pub fn pure_shear<M: StressState<N>>(max_gamma: f64, n_steps: usize) -> Result<Self, PathError> {
        let Some(i) = M::SHEAR_XY else {
            return Err(invalid("a pure-shear path needs the xy shear component (not the uniaxial kinematics)"));
        };
        check_steps(n_steps)?;
        if !max_gamma.is_finite() || max_gamma == 0.0 {
            return Err(invalid(format!("max_gamma must be finite and non-zero, got {max_gamma}")));
        }
        let mut steps = Vec::with_capacity(n_steps);
        Self::ramp(&[(i, 0.0)], &[(i, max_gamma)], n_steps, &mut steps);
        Ok(LoadPath { steps })
    }

    /// Shear under a held compression, the lab's cyclic shear test at a point: σ_yy ramped to
    /// −`vertical_stress` (> 0, Pa) in `preload_steps` with γ_xy held at 0, then γ_xy driven
    /// piecewise linearly through `targets`, `steps_per_segment` each, with σ_yy held; every other
    /// component stress-free (σ_xx = 0: the wall's sides are free).
    pub fn shear_under_compression<M: StressState<N>>(
        vertical_stress: f64,
        targets: &[f64],
        steps_per_segment: usize,
        preload_steps: usize,
    ) -> Result<Self, PathError> {
        let Some(i) = M::SHEAR_XY.filter(|_| N >= 3) else {
            return Err(invalid("a shear path under compression needs the yy and xy components (plane stress or 3D)"));
        };
        check_positive("vertical_stress", vertical_stress)?;
        check_steps(steps_per_segment)?;
        check_steps(preload_steps)?;
        if targets.is_empty() || targets.iter().any(|t| !t.is_finite()) {
            return Err(invalid(format!("shear targets must be finite and non-empty, got {targets:?}")));
        }
        let mut steps = Vec::with_capacity(preload_steps + targets.len() * steps_per_segment);
        for k in 1..=preload_steps {
            let mut c = [Control::Stress(0.0); N];
            c[1] = Control::Stress(-vertical_stress * k as f64 / preload_steps as f64);
            c[i] = Control::Strain(0.0);
            steps.push(c);
        }
        let mut from = 0.0;
        for &t in targets {
            for k in 1..=steps_per_segment {
                let mut c = [Control::Stress(0.0); N];
                c[1] = Control::Stress(-vertical_stress);
                c[i] = Control::Strain(from + (t - from) * k as f64 / steps_per_segment as f64);
                steps.push(c);
            }
            from = t;
        }
        Ok(LoadPath { steps })
    }
}

/// Solve `a x = b` by Gaussian elimination with partial pivoting (N ≤ 6 here, no allocation);
/// `None` if a pivot is zero or not finite.
fn solve_dense<const N: usize>(mut a: SMatrix<f64, N, N>, mut b: SVector<f64, N>) -> Option<SVector<f64, N>> {
    for col in 0..N {
        let (p, _) =
            (col..N).map(|i| (i, a[(i, col)].abs())).fold(
                (col, -1.0),
                |best, cur| {
                    if cur.1 > best.1 {
                        cur
                    } else {
                        best
                    }
                },
            );
        let pivot = a[(p, col)];
        if pivot == 0.0 || !pivot.is_finite() {
            return None;
        }
        a.swap_rows(p, col);
        b.swap_rows(p, col);
        for i in col + 1..N {
            let f = a[(i, col)] / a[(col, col)];
            for j in col..N {
                a[(i, j)] -= f * a[(col, j)];
            }
            b[i] -= f * b[col];
        }
    }
    for col in (0..N).rev() {
        let mut s = b[col];
        for j in col + 1..N {
            s -= a[(col, j)] * b[j];
        }
        b[col] = s / a[(col, col)];
    }
    Some(b)
}

/// Newton settings of the driver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Tangent iterations per step (then as many secant iterations).
    pub max_iterations: usize,
    /// Relative tolerance on the stress residual (module docs).
    pub rtol: f64,
}

impl Default for NewtonSettings {
    /// 25 iterations, rtol = 1e-12.
    fn default() -> Self {
        NewtonSettings { max_iterations: 25, rtol: 1e-12 }
    }
}

/// The converged state after one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathRecord<const N: usize> {
    /// Step number; 0 is the initial (virgin, zero-strain) state.
    pub step: usize,
    /// Total strain (engineering shear).
    pub strain: [f64; N],
    /// Stress (Pa).
    pub stress: [f64; N],
    /// Tensile damage.
    pub d_t: f64,
    /// Compressive damage.
    pub d_c: f64,
    /// Tensile history variable κ_t.
    pub kappa_t: f64,
    /// Compressive history variable κ_c.
    pub kappa_c: f64,
    /// Energy per volume dissipated since the start (J/m³).
    pub dissipated: f64,
    /// Newton iterations the step took.
    pub iterations: usize,
}

/// Run `path` on one material point of `law` with the kinematics `kinematics` (e.g.
/// [`PlaneStress`](super::PlaneStress)), from the virgin state at zero strain. Returns one record
/// per step, with the initial state first.
pub fn run_path<const N: usize, M: StressState<N>>(
    kinematics: M,
    law: &PointLaw,
    path: &LoadPath<N>,
    settings: &NewtonSettings,
) -> Result<Vec<PathRecord<N>>, PathError> {
    let mut records = Vec::with_capacity(path.len() + 1);
    run_path_into(kinematics, law, path, settings, &mut records)?;
    Ok(records)
}

/// [`run_path`] appending each converged step's record to `records` (cleared first), so that a
/// path that stops keeps the states it reached.
pub fn run_path_into<const N: usize, M: StressState<N>>(
    _kinematics: M,
    law: &PointLaw,
    path: &LoadPath<N>,
    settings: &NewtonSettings,
    records: &mut Vec<PathRecord<N>>,
) -> Result<(), PathError> {
    let mut committed = DamageState::virgin(law);
    let mut eps = SVector::<f64, N>::zeros();
    let mut dissipated = 0.0;
    records.clear();
    records.push(PathRecord {
        step: 0,
        strain: [0.0; N],
        stress: [0.0; N],
        d_t: 0.0,
        d_c: 0.0,
        kappa_t: committed.kappa_t,
        kappa_c: committed.kappa_c,
        dissipated,
        iterations: 0,
    });
    for (k, controls) in path.steps().iter().enumerate() {
        let step = k + 1;
        let mut target = SVector::<f64, N>::zeros();
        let mut free = [false; N];
        for (i, c) in controls.iter().enumerate() {
            match *c {
                Control::Strain(v) => eps[i] = v,
                Control::Stress(v) => {
                    target[i] = v;
                    free[i] = true;
                }
            }
        }
        let max_iter = settings.max_iterations;
        let mut iteration = 0;
        let (resp, iterations) = loop {
            let resp = M::evaluate(law, &eps, &committed);
            if !resp.stress.iter().all(|s| s.is_finite()) {
                return Err(PathError::NonFinite { step, iteration });
            }
            let mut r = SVector::<f64, N>::zeros();
            for i in 0..N {
                if free[i] {
                    r[i] = resp.stress[i] - target[i];
                }
            }
            let residual = r.amax();
            let scale = (law.e() * eps.amax().max(law.eps0_t())).max(target.amax());
            let tolerance = settings.rtol * scale;
            if residual <= tolerance {
                break (resp, iteration);
            }
            if iteration >= 2 * max_iter {
                return Err(PathError::NoConvergence { step, iterations: iteration, residual, tolerance });
            }
            let mut jac: SMatrix<f64, N, N> = if iteration < max_iter { resp.tangent } else { resp.secant };
            for i in 0..N {
                for j in 0..N {
                    if !free[i] || !free[j] {
                        jac[(i, j)] = if i == j { 1.0 } else { 0.0 };
                    }
                }
            }
            match solve_dense(jac, r) {
                Some(delta) if delta.iter().all(|v| v.is_finite()) => eps -= delta,
                // A singular tangent: jump to the secant iterations (singular secant: d = 1).
                _ if iteration < max_iter => iteration = max_iter - 1,
                _ => return Err(PathError::NoConvergence { step, iterations: iteration, residual, tolerance }),
            }
            iteration += 1;
        };
        committed = resp.state;
        dissipated += resp.dissipation;
        let mut strain = [0.0; N];
        let mut stress = [0.0; N];
        for i in 0..N {
            strain[i] = eps[i];
            stress[i] = resp.stress[i];
        }
        records.push(PathRecord {
            step,
            strain,
            stress,
            d_t: committed.d_t,
            d_c: committed.d_c,
            kappa_t: committed.kappa_t,
            kappa_c: committed.kappa_c,
            dissipated,
            iterations,
        });
    }
    Ok(())
}

#[cfg(test)]
#[path = "path_tests.rs"]
mod tests;
