//! Pseudo-transient continuation: the static equilibrium at a fixed load that Newton's method
//! does not reach.
//!
//! **Why Newton stops** (measured on the paper's wall with crushing, `examples/dem_peak.rs`).
//! Two situations, both at the compressive peak and after it:
//! * *alternation across kinks*: the return maps (crushing elastic/plastic, stick/slip) make the
//!   residual piecewise smooth; with several crushing contacts on their softening branch
//!   `F_y(κ) = σ_c L t_z (1 − κ/δ_u)` (tangent terms `−H k_n/(k_n − H)`), Newton's direction
//!   from one side of a kink is not one of descent for `½‖r‖²` and the line search takes its
//!   best trial: the iteration alternates between two states at a relative residual of
//!   1e-6..1e-4, at every increment down to 2⁻¹⁰ of the step, although an equilibrium lies
//!   close by;
//! * *snap-back*: a band of crushing contacts softening together turns the path back in the
//!   platen displacement; past the limit point the next equilibrium is on the post-peak branch,
//!   far away (a drop of the force at fixed platen displacement); likewise a break that leaves
//!   stones held only by sliding contacts.
//!
//! **The damped path.** Between two static states the stones would move dynamically and come to
//! rest, the kinetic energy damped. Its heavily damped limit is followed in a pseudo-time `τ`
//! (pseudo-transient continuation, Kelley & Keyes, SIAM J. Numer. Anal. 35 (1998) 508–523; the
//! masses as in Underwood's dynamic relaxation):
//!
//! ```text
//!   (K_T + σ_k M) Δz_k = r(z_k) ,   σ_k = 1/Δτ_k (dimensionless) ,   M = diag K₀
//! ```
//!
//! `M = diag K₀` (every beam intact: Underwood's fictitious masses; they make `σ` dimensionless
//! and damp each stone by its own stiffness); `r`, `K_T` the static problem's
//! ([`super::equilibrium`], [`super::tangent`]). A step is taken only if it releases energy:
//!
//! ```text
//!   downhill:  Δzᵀ r(z_k) > 0                         (first-order decrease of the energy)
//!   released:  ½ (r(z_k) + r(z_k + Δz))ᵀ Δz > 0       (trapezoid of the work of the
//!                                                     out-of-balance forces along the step)
//! ```
//!
//! (no energy function is needed, only forces; the second test rejects a step that overshoots a
//! valley, which a residual-norm test cannot tell from a step through an unstable region, where
//! the residual must grow). A rejected step multiplies `σ` by 4 (more damping) and is solved
//! again. No stone moves more than the trust radius `TRUST_RADIUS · D̄` in one step (the step is
//! scaled down); a step inside it halves `σ` (down to `SIGMA_MIN`), so near the equilibrium the
//! iteration is Newton's method with its fast convergence. `σ₀ = 1`.
//! **Converged only when the static residual meets the equilibrium test,
//! `‖r‖∞ ≤ tol · scale`** (the tolerance unchanged): the end state is a static equilibrium with
//! its own contact and stick/slip set, committed like any other. The friction and crushing
//! return maps run from the committed state, as in every increment. Beams are judged at the end
//! state (the event loop breaks any with `P ≥ 1` there, one at a time).
//!
//! The linear solve is GMRES on `K_T + σM` preconditioned by the factorization of the symmetric
//! operator with the shift `σM` in place of the regularization, refactorized when `σ` has moved
//! by more than a factor 2 since the last factorization (contact terms entering or leaving in
//! between are Woodbury terms, as in Newton's method); afterwards the unshifted operator is
//! refactorized. It is a fallback: one continuation costs up to `MAX_ITERATIONS` factorizations
//! of a small wall, more than Newton's method, and runs only where Newton's method failed at the
//! smallest increment.
use super::equilibrium::Refactor;
use super::error::DemError;
use super::events::{LoadPoint, Solver};
use super::gmres::gmres;
use super::tangent::Tangent;
use super::trace::NewtonStep;

/// The initial shift `σ₀` (a step as stiff again as the intact lattice's diagonal).
const SIGMA_0: f64 = 1.0;
/// Bounds of the shift.
const SIGMA_MIN: f64 = 1e-12;
const SIGMA_MAX: f64 = 1e8;
/// The trust radius: the largest move of a stone in one iteration, as a fraction of the mean
/// stone diameter D̄.
const TRUST_RADIUS: f64 = 2e-4;
/// Iterations of one continuation.
pub(super) const MAX_ITERATIONS: usize = 600;

impl<'a> Solver<'a> {
    /// Finds the static equilibrium at `load` (plus `extra`, over `z`) from the current `z` by
    /// pseudo-transient continuation (module docs); leaves the contacts of the equilibrium in
    /// [`Self::contacts`]. Errors: [`DemError::NoConvergence`] after `MAX_ITERATIONS`.
    pub(super) fn continuation(&mut self, load: &LoadPoint, extra: Option<&[f64]>, t: f64) -> Result<(), DemError> {
        let map = &self.model.map;
        for (k, &zi) in map.prescribed.iter().enumerate() {
            self.z[zi] = load.prescribed[k];
        }
        let mut f_ext = extra.map_or_else(|| vec![0.0; map.n_z], |x| x.to_vec());
        for (k, &zi) in map.forced.iter().enumerate() {
            f_ext[zi] += load.forces[k];
        }
        let unknowns = map.unknowns.clone();
        let n_eq = map.n_eq();
        // M = diag K₀ (with a positive fallback for DOFs without a beam).
        let mass = self.intact_diagonal.clone();
        let events = self.broken.len();
        if let Some(tr) = self.trace.as_mut() {
            tr.begin(self.stage, t, events, "continuation");
        }
        self.n_continuations += 1;
        let z0 = self.z.clone();
        let mut ev = self.evaluate(&z0, &f_ext)?;
        let mut sigma = SIGMA_0;
        let mut factored: Option<f64> = None;
        let mut result = Err(());
        for _ in 0..MAX_ITERATIONS {
            if ev.relative <= self.opts.tol {
                result = Ok(());
                break;
            }
            self.profile.continuation_iterations += 1;
            // The shifted symmetric operator as preconditioner.
            if factored.is_none_or(|s| sigma > 2.0 * s || sigma < 0.5 * s) {
                self.needs_factor = true;
            }
            self.sync_operator(&ev.contacts)?;
            if self.needs_factor || (self.factor.rank() > 0 && !self.factor.is_accurate()) {
                let diagonal: Vec<f64> = self.reg.iter().zip(&mass).map(|(r, m)| r + sigma * m).collect();
                self.pending_refactor = None;
                self.refactorize_with(Some(Refactor::Continuation), &diagonal)?;
                factored = Some(sigma);
            }
            let tangent = Tangent::new(
                &self.model,
                &self.intact,
                &self.reg,
                &ev.contacts,
                &self.z,
                &self.z_commit,
                &self.committed_ft,
                &mut self.jacobians,
            )?;
            let mut dz = vec![0.0; n_eq];
            let factor = &mut self.factor;
            let info = gmres(
                &mut dz,
                &ev.r,
                |v, o| {
                    tangent.apply(v, o);
                    for ((o, v), m) in o.iter_mut().zip(v).zip(&mass) {
                        *o += sigma * m * v;
                    }
                },
                |v| factor.solve(v),
                1e-8,
                60,
                240,
            )
            .map_err(|e| DemError::Factorization { event: events, reason: e.0 })?;
            drop(tangent);
            self.n_solves += info.iterations;
            if !info.converged && self.factor.rank() > 0 {
                self.needs_factor = true;
            }
            // Downhill: the step must do positive work with the out-of-balance forces,
            // Δzᵀ r > 0 (first-order decrease of the energy); else the shifted operator is not
            // positive along it: more shift, same state.
            let work: f64 = dz.iter().zip(&ev.r).map(|(d, r)| d * r).sum();
            let downhill = work > 0.0;
            let cap = if downhill { self.cap_continuation(&mut dz) } else { 0.0 };
            if let Some(tr) = self.trace.as_mut() {
                tr.step(NewtonStep {
                    relative: ev.relative,
                    merit: ev.merit,
                    contacts: ev.contacts.len(),
                    sliding: ev.contacts.iter().filter(|a| !a.sticks()).count(),
                    crushing: ev.contacts.iter().filter(|a| a.crush.is_some_and(|c| c.plastic)).count(),
                    set_changes: 0,
                    gmres_iterations: info.iterations,
                    linear_converged: info.converged,
                    cap,
                    alpha: if downhill { 1.0 } else { 0.0 },
                    shift: sigma,
                });
            }
            if !downhill {
                sigma = (4.0 * sigma).clamp(SIGMA_MIN, SIGMA_MAX);
                continue;
            }
            let mut z = self.z.clone();
            for (e, &zi) in unknowns.iter().enumerate() {
                z[zi] += dz[e];
            }
            let trial = self.evaluate(&z, &f_ext)?;
            // The work of the out-of-balance forces along the step (trapezoid), the energy the
            // step releases: ½ (r_k + r_{k+1})ᵀ Δz > 0, else the step overshot a valley.
            let released = 0.5 * (work * cap + dz.iter().zip(&trial.r).map(|(d, r)| d * r).sum::<f64>());
            if released <= 0.0 {
                if let Some(st) =
                    self.trace.as_mut().and_then(|tr| tr.attempts.back_mut()).and_then(|a| a.steps.last_mut())
                {
                    st.alpha = 0.0;
                }
                sigma = (4.0 * sigma).clamp(SIGMA_MIN, SIGMA_MAX);
                continue;
            }
            ev = trial;
            self.z = z;
            // A step inside the trust radius: less shift (towards Newton's method); a capped
            // step keeps it.
            if cap >= 1.0 {
                sigma = (0.5 * sigma).max(SIGMA_MIN);
            }
        }
        if let Some(tr) = self.trace.as_mut() {
            tr.end(ev.relative, result.is_ok());
        }
        // Back to the unshifted operator.
        self.needs_factor = true;
        self.pending_refactor = Some(Refactor::Continuation);
        match result {
            Ok(()) => {
                self.contacts = ev.contacts;
                Ok(())
            }
            Err(()) => Err(DemError::NoConvergence {
                stage: self.stage,
                load: t,
                event: events,
                iterations: MAX_ITERATIONS,
                residual: ev.relative,
                unbonded: self.unbonded_stones(),
            }),
        }
    }

    /// Scales `dz` so that no stone moves more than the trust radius `TRUST_RADIUS · D̄`
    /// (translation, or rotation × D̄); returns the scale (1: inside).
    fn cap_continuation(&self, dz: &mut [f64]) -> f64 {
        let map = &self.model.map;
        let big = map
            .unknowns
            .iter()
            .zip(dz.iter())
            .map(|(&zi, d)| if zi % 3 == 2 { d.abs() * self.mean_diameter } else { d.abs() })
            .fold(0.0f64, f64::max);
        let radius = TRUST_RADIUS * self.mean_diameter;
        if big > radius {
            let s = radius / big;
            dz.iter_mut().for_each(|d| *d *= s);
            return s;
        }
        1.0
    }
}
