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
    if !(v.is_finite() && v > 0.0) {
        return Err(invalid(format!("{what} must be finite and > 0, got {v}")));
    }
    Ok(())
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
    _kinematics: M,
    law: &PointLaw,
    path: &LoadPath<N>,
    settings: &NewtonSettings,
) -> Result<Vec<PathRecord<N>>, PathError> {
    let mut committed = DamageState::virgin(law);
    let mut eps = SVector::<f64, N>::zeros();
    let mut dissipated = 0.0;
    let mut records = Vec::with_capacity(path.len() + 1);
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
    Ok(records)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_support::{law, params};
    use crate::material::{PlaneStress, ThreeD, Uniaxial};

    /// Closed-form uniaxial stress–strain curve (SPEC §2; lateral-extension ε_eq^c = √2 ν|ε|).
    fn closed_form(law: &PointLaw, eps: f64, kappa_t: f64, kappa_c: f64) -> f64 {
        let p = params();
        if eps >= 0.0 {
            let k = kappa_t.max(p.eps0_t);
            law.e() * eps * p.eps0_t / k * (-law.b_t() * (k - p.eps0_t)).exp()
        } else {
            let k = kappa_c.max(p.eps0_c);
            law.e() * eps * ((1.0 - p.a_c) * p.eps0_c / k + p.a_c * (-p.b_c * (k - p.eps0_c)).exp())
        }
    }

    fn check_uniaxial<const N: usize>(records: &[PathRecord<N>], law: &PointLaw) {
        // The lateral components are solved by Newton to rtol = 1e-12 of E·ε, so σ_xx matches the
        // closed form to 1e-10 f_t + 1e-9 |σ_xx| (absolute part as σ_xx → 0 in the softening;
        // relative part: the lateral residual is amplified through d(ε_eq) at large strain).
        let ft = law.tensile_strength();
        let nu = law.nu();
        let (mut kt, mut kc) = (0.0f64, 0.0f64);
        for r in records {
            let eps = r.strain[0];
            kt = kt.max(eps);
            kc = kc.max(-2f64.sqrt() * nu * eps);
            let exact = closed_form(law, eps, kt, kc);
            assert!(
                (r.stress[0] - exact).abs() <= 1e-10 * ft + 1e-9 * exact.abs(),
                "step {}: {} vs {exact}",
                r.step,
                r.stress[0]
            );
            // The free components satisfy the Newton criterion ‖r‖∞ ≤ 1e-12 E max(‖ε‖∞, ε₀^t).
            let newton_tol = 1e-12 * law.e() * eps.abs().max(law.eps0_t());
            for i in 1..N {
                assert!(r.stress[i].abs() <= newton_tol, "step {} component {i}: {}", r.step, r.stress[i]);
            }
            if N >= 2 {
                assert!((r.strain[1] + nu * eps).abs() <= 1e-10 * eps.abs().max(1e-6));
            }
        }
    }

    #[test]
    fn uniaxial_tension_in_every_kinematics() {
        let law = law();
        let path1 = LoadPath::<1>::uniaxial_tension(10.0 * law.eps0_t(), 50).unwrap();
        let path3 = LoadPath::<3>::uniaxial_tension(10.0 * law.eps0_t(), 50).unwrap();
        let path6 = LoadPath::<6>::uniaxial_tension(10.0 * law.eps0_t(), 50).unwrap();
        let s = NewtonSettings::default();
        let r1 = run_path(Uniaxial, &law, &path1, &s).unwrap();
        let r3 = run_path(PlaneStress, &law, &path3, &s).unwrap();
        let r6 = run_path(ThreeD, &law, &path6, &s).unwrap();
        assert_eq!((r1.len(), r3.len(), r6.len()), (51, 51, 51));
        check_uniaxial(&r1, &law);
        check_uniaxial(&r3, &law);
        check_uniaxial(&r6, &law);
        // Same dissipation in the three (1e-9 relative: the lateral strains are Newton solutions).
        let d = r1[50].dissipated;
        assert!(d > 0.0);
        assert!((r3[50].dissipated - d).abs() <= 1e-9 * d && (r6[50].dissipated - d).abs() <= 1e-9 * d);
    }

    #[test]
    fn uniaxial_compression_in_every_kinematics() {
        let law = law();
        let s = NewtonSettings::default();
        let r1 = run_path(Uniaxial, &law, &LoadPath::uniaxial_compression(0.05, 50).unwrap(), &s).unwrap();
        let r3 = run_path(PlaneStress, &law, &LoadPath::uniaxial_compression(0.05, 50).unwrap(), &s).unwrap();
        let r6 = run_path(ThreeD, &law, &LoadPath::uniaxial_compression(0.05, 50).unwrap(), &s).unwrap();
        check_uniaxial(&r1, &law);
        check_uniaxial(&r3, &law);
        check_uniaxial(&r6, &law);
        assert!(r6[50].d_c > 0.5 && r6[50].d_t == 0.0);
    }

    #[test]
    fn cyclic_path_shows_the_unilateral_effect() {
        // Tension to 6 ε₀^t, compression to −6 ε₀^t (below the compressive onset ε₀^c/(√2ν) ≈ 7 ε₀^t):
        // every compressive state has σ = E ε exactly (d_c = 0), the tensile damage is kept.
        let law = law();
        let path = LoadPath::<3>::cyclic_tension_compression(6.0 * law.eps0_t(), 6.0 * law.eps0_t(), 3, 20).unwrap();
        assert_eq!(path.len(), 7 * 20);
        let rec = run_path(PlaneStress, &law, &path, &NewtonSettings::default()).unwrap();
        check_uniaxial(&rec, &law);
        let mut prev = &rec[0];
        for r in &rec[1..] {
            assert!(r.d_t >= prev.d_t && r.dissipated >= prev.dissipated);
            if r.strain[0] < 0.0 {
                assert_eq!(r.d_c, 0.0);
                assert!((r.stress[0] - law.e() * r.strain[0]).abs() <= 1e-10 * law.tensile_strength());
            }
            prev = r;
        }
        assert!(rec.last().map(|r| r.d_t).unwrap_or(0.0) > 0.5);
    }

    #[test]
    fn biaxial_tension_keeps_sigma_zz_free() {
        let law = law();
        let rec = run_path(
            ThreeD,
            &law,
            &LoadPath::biaxial(5.0 * law.eps0_t(), 1.0, 20).unwrap(),
            &NewtonSettings::default(),
        )
        .unwrap();
        let last = rec[20];
        // σ_zz = 0 and the shears are free (Newton tolerance, 1e-10 f_t); ε_zz = −2ν/(1−ν) ε_xx.
        for i in 2..6 {
            assert!(last.stress[i].abs() <= 1e-10 * law.tensile_strength());
        }
        let nu = law.nu();
        assert!((last.strain[2] + 2.0 * nu / (1.0 - nu) * last.strain[0]).abs() <= 1e-10 * last.strain[0]);
        assert!(last.d_t > 0.0 && last.stress[0] == last.stress[1]);
    }

    #[test]
    fn pure_shear_in_plane_stress_and_3d() {
        // γ imposed, normal stresses free: ε_xx = ε_yy = 0, κ_t = γ/2, τ = (1 − d_t) μ γ.
        let law = law();
        let g = 8.0 * law.eps0_t();
        let s = NewtonSettings::default();
        let r3 = run_path(PlaneStress, &law, &LoadPath::pure_shear::<PlaneStress>(g, 16).unwrap(), &s).unwrap();
        let r6 = run_path(ThreeD, &law, &LoadPath::pure_shear::<ThreeD>(g, 16).unwrap(), &s).unwrap();
        let (a, b) = (r3[16], r6[16]);
        assert!((a.kappa_t - g / 2.0).abs() <= 1e-15 && (b.kappa_t - g / 2.0).abs() <= 1e-15);
        let tau = (1.0 - a.d_t) * law.mu() * g;
        assert!((a.stress[2] - tau).abs() <= 1e-12 * tau && (b.stress[5] - tau).abs() <= 1e-12 * tau);
        assert_eq!(a.d_c, 0.0);
    }

    #[test]
    fn newton_failure_names_the_step() {
        // No iteration allowed: the first step with a stress-controlled component fails, typed.
        let law = law();
        let s = NewtonSettings { max_iterations: 0, rtol: 1e-12 };
        let err = run_path(PlaneStress, &law, &LoadPath::uniaxial_tension(1e-3, 5).unwrap(), &s).unwrap_err();
        assert!(matches!(err, PathError::NoConvergence { step: 1, iterations: 0, .. }), "{err:?}");
        assert!(err.to_string().contains("step 1"), "{err}");
        // Fully strain-controlled paths need no iteration.
        let path = LoadPath::<1>::uniaxial_tension(1e-3, 5).unwrap();
        assert_eq!(run_path(Uniaxial, &law, &path, &s).map(|r| r.len()), Ok(6));
    }

    #[test]
    fn invalid_paths_are_rejected() {
        assert!(matches!(LoadPath::<1>::pure_shear::<Uniaxial>(1e-3, 5), Err(PathError::InvalidPath { .. })));
        assert!(matches!(LoadPath::<1>::biaxial(1e-3, 1.0, 5), Err(PathError::InvalidPath { .. })));
        assert!(matches!(LoadPath::<3>::uniaxial_tension(1e-3, 0), Err(PathError::InvalidPath { .. })));
        assert!(matches!(LoadPath::<3>::uniaxial_tension(-1e-3, 4), Err(PathError::InvalidPath { .. })));
        assert!(matches!(LoadPath::<3>::uniaxial(&[f64::NAN], 4), Err(PathError::InvalidPath { .. })));
    }
}
