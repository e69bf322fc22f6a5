//! [`DamageState`]: the history of one material point, the active [`Side`] of the unilateral split,
//! and the evolution of the history over one strain update.
//!
//! # Optional viscous regularization (Duvaut–Lions on the history)
//! Rate independent (the default, paper §3.1): κ = max(κ_old, ε_eq). With a relaxation time τ the
//! history relaxes towards the rate-independent value, κ̇ = ⟨ε_eq − κ⟩₊ / τ, integrated by
//! backward Euler over an increment Δt (r = Δt/τ, [`PointLaw::with_relaxation`]):
//!
//! ```text
//!   loading (ε_eq > κ_old):  κ = (κ_old + r ε_eq) / (1 + r),   ∂κ/∂ε_eq = r / (1 + r)
//!   dissipated:              c [F(κ) − F(κ_old)],  c = y / κ²    (Y = y at the end of the step)
//! ```
//! r = ∞ gives κ = ε_eq and c = y/ε_eq², the rate-independent update exactly; as Δt → 0 at fixed
//! τ the update converges to the viscous solution. r = 0 freezes the history: κ = κ_old, no
//! damage term in the tangent, nothing dissipated ([`PointLaw::with_frozen_history`], the stress
//! of an IMPL-EX step). d = d(κ) keeps its closed form, so the state
//! layout, the output and the checkpoints are unchanged. The viscous law lets the stress exceed
//! the rate-independent envelope for a time of order τ: it delays localization and snap-back in
//! quasi-static runs, at the price of a response that depends on τ and on the loading rate.

use serde::{Deserialize, Serialize};

use super::law::PointLaw;

/// Which damage variable the current strain activates, from the sign of tr σ̃ (σ̃ = C₀:ε).
///
/// Convention at tr σ̃ = 0 exactly: **tension** (H(0) = 1 on the tensile side, 0 on the compressive
/// side), so a purely deviatoric strain (pure shear) is resisted with 1 − d_t and damages d_t, as
/// shear cracking does in masonry. Choosing 0 on both sides would give zero stress in pure shear.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Side {
    /// tr σ̃ ≥ 0: σ = (1 − d_t) C₀:ε, ε_eq^t = ε_eq(ε), ε_eq^c = 0.
    Tension,
    /// tr σ̃ < 0: σ = (1 − d_c) C₀:ε, ε_eq^c = ε_eq(ε), ε_eq^t = 0.
    Compression,
}

impl Side {
    /// The active side for the trace of the effective stress (Pa); NaN gives `Compression`.
    #[inline]
    pub fn of_trace(tr_sigma_tilde: f64) -> Side {
        if tr_sigma_tilde >= 0.0 {
            Side::Tension
        } else {
            Side::Compression
        }
    }
}

/// The history of one material point: κ_t, κ_c and the damages they give.
///
/// `Default` is the virgin state with κ = 0: every update clamps κ below at ε₀, so the default and
/// [`DamageState::virgin`] (κ = ε₀) give identical responses; the trial state returned by an update
/// always has κ ≥ ε₀. `d_t = d_t(κ_t)` and `d_c = d_c(κ_c)` always; they are stored for output and
/// so that readers need not evaluate the law.
///
/// Flat layout for checkpoints: [`DamageState::to_array`] = `[kappa_t, kappa_c, d_t, d_c]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DamageState {
    /// History of the tensile equivalent strain, κ_t = max(ε₀^t, max over time ε_eq^t).
    pub kappa_t: f64,
    /// History of the compressive equivalent strain, κ_c = max(ε₀^c, max over time ε_eq^c).
    pub kappa_c: f64,
    /// Tensile damage d_t(κ_t) ∈ [0, 1).
    pub d_t: f64,
    /// Compressive damage d_c(κ_c) ∈ [0, 1).
    pub d_c: f64,
}

impl DamageState {
    /// Number of values in the flat layout.
    pub const N_VALUES: usize = 4;

    /// The undamaged state with κ_t = ε₀^t and κ_c = ε₀^c.
    pub fn virgin(law: &PointLaw) -> Self {
        DamageState { kappa_t: law.eps0_t(), kappa_c: law.eps0_c(), d_t: 0.0, d_c: 0.0 }
    }

    /// κ of one side.
    #[inline]
    pub fn kappa(&self, side: Side) -> f64 {
        match side {
            Side::Tension => self.kappa_t,
            Side::Compression => self.kappa_c,
        }
    }

    /// d of one side.
    #[inline]
    pub fn damage(&self, side: Side) -> f64 {
        match side {
            Side::Tension => self.d_t,
            Side::Compression => self.d_c,
        }
    }

    /// `[kappa_t, kappa_c, d_t, d_c]`, for checkpoints.
    pub fn to_array(&self) -> [f64; 4] {
        [self.kappa_t, self.kappa_c, self.d_t, self.d_c]
    }

    /// The inverse of [`DamageState::to_array`].
    pub fn from_array(a: [f64; 4]) -> Self {
        DamageState { kappa_t: a[0], kappa_c: a[1], d_t: a[2], d_c: a[3] }
    }
}

/// The outcome of one history update at a material point.
#[derive(Clone, Copy, Debug)]
pub(super) struct Evolution {
    /// The trial state.
    pub state: DamageState,
    /// 1 − d of the active side (the factor of C₀:ε in the stress).
    pub integrity: f64,
    /// ∂d/∂ε_eq of the active side: d'(κ) when loading, 0 otherwise.
    pub dd_deq: f64,
    /// Energy per volume dissipated by the update (J/m³), ≥ 0.
    pub dissipation: f64,
    /// Whether the active κ grew (ε_eq > committed κ).
    pub loading: bool,
}

/// Update the history of the active `side` with the equivalent strain `eps_eq` of the current strain
/// and its free energy density `y` = ½ ε:C₀:ε (J/m³); the other side keeps its committed history.
///
/// Loading (`eps_eq > κ_old`, κ_old = max(committed κ, ε₀)): κ = ε_eq, d = d(κ), and the dissipated
/// energy is c [F(κ) − F(κ_old)] with c = y / ε_eq² ([`damage`](super::damage) module docs): exact
/// for a radial strain increment, hence for any step size under monotonic uniaxial loading.
#[inline]
pub(super) fn evolve(law: &PointLaw, side: Side, eps_eq: f64, y: f64, committed: &DamageState) -> Evolution {
    let mut state = DamageState {
        kappa_t: committed.kappa_t.max(law.eps0_t()),
        kappa_c: committed.kappa_c.max(law.eps0_c()),
        ..*committed
    };
    let kappa_old = state.kappa(side);
    let loading = eps_eq > kappa_old;
    let r = law.relaxation();
    // κ and ∂κ/∂ε_eq: rate independent for r = ∞, Duvaut–Lions otherwise (module docs).
    let (kappa, dk) = match (loading, r.is_finite()) {
        (false, _) => (kappa_old, 0.0),
        (true, false) => (eps_eq, 1.0),
        (true, true) => ((kappa_old + r * eps_eq) / (1.0 + r), r / (1.0 + r)),
    };
    let dv = law.damage(side, kappa);
    let (dd_deq, dissipation) = if loading {
        let c = y / (kappa * kappa);
        (dv.slope * dk, law.dissipation(side, c, kappa_old, kappa))
    } else {
        (0.0, 0.0)
    };
    match side {
        Side::Tension => {
            state.kappa_t = kappa;
            state.d_t = dv.d;
        }
        Side::Compression => {
            state.kappa_c = kappa;
            state.d_c = dv.d;
        }
    }
    Evolution { state, integrity: dv.integrity, dd_deq, dissipation, loading }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::plane_stress::{self, PlaneStress};
    use crate::material::test_support::{fd_tangent, law, rel_diff};
    use nalgebra::Vector3;

    #[test]
    fn without_a_relaxation_time_the_update_is_rate_independent() {
        // with_relaxation(dt, None) gives r = ∞: bitwise the same law and the same update.
        let base = law();
        let v = base.with_relaxation(0.3, None);
        assert_eq!(v, base);
        assert_eq!(base.relaxation(), f64::INFINITY);
        let eps = 7.0 * base.eps0_t();
        let a = evolve(&base, Side::Tension, eps, 0.5 * base.e() * eps * eps, &DamageState::default());
        assert_eq!(a.state.kappa_t, eps);
    }

    #[test]
    fn held_strain_relaxes_to_the_rate_independent_history_as_backward_euler_predicts() {
        // ε_eq = e held, κ₀ = ε₀: the backward-Euler recursion κ_{n+1} = (κ_n + r e)/(1 + r) has
        // the closed form κ_n = e − (e − ε₀)/(1 + r)^n (module docs). 1e-14 relative, round-off.
        let base = law();
        let (tau, dt) = (0.05, 0.01);
        let v = base.with_relaxation(dt, Some(tau));
        let r = dt / tau;
        assert!((v.relaxation() - r).abs() < 1e-15);
        let e = 9.0 * base.eps0_t();
        let y = 0.5 * base.e() * e * e;
        let mut st = DamageState::default();
        let mut dissipated = 0.0;
        for n in 1..=200 {
            let evo = evolve(&v, Side::Tension, e, y, &st);
            let exact = e - (e - base.eps0_t()) / (1.0 + r).powi(n);
            assert!((evo.state.kappa_t - exact).abs() <= 1e-14 * e, "step {n}: {} vs {exact}", evo.state.kappa_t);
            assert!(evo.dissipation >= 0.0);
            dissipated += evo.dissipation;
            st = evo.state;
        }
        // After 200 steps (40 τ) the history is the rate-independent one to e^{-40}-ish.
        let plain = evolve(&base, Side::Tension, e, y, &DamageState::default());
        assert!((st.d_t - plain.state.d_t).abs() < 1e-12);
        // The energy dissipated at fixed strain is Y Δd with Y = y (Y = y at the end of each step
        // and d' positive: bounded by y [d(e) − 0] and positive).
        assert!(
            dissipated > 0.0 && dissipated <= y * plain.state.d_t * (1.0 + 1e-12),
            "{dissipated} vs {}",
            y * plain.state.d_t
        );
    }

    #[test]
    fn viscous_tangent_matches_finite_differences() {
        // Plane stress with r = 0.5, loading states on both sides and in the switch band:
        // central differences, step 1e-7 ‖ε‖∞, tolerance 1e-6 norm-wise relative (as the
        // rate-independent checks in plane_stress.rs).
        let v = law().with_relaxation(0.5, Some(1.0));
        let strains = [
            Vector3::new(6.0e-4, -1.0e-4, 2.0e-4),
            Vector3::new(-3.0e-3, 0.4e-3, 0.5e-3),
            Vector3::new(-2.0e-3, -1.5e-3, 0.1e-3),
            Vector3::new(1.0e-3, -1.05e-3, 0.3e-3),
        ];
        for eps in strains {
            let r = plane_stress::update(&v, &eps, &DamageState::default());
            assert!(r.loading, "{eps:?} should load");
            let fd = fd_tangent::<3, PlaneStress>(&v, &eps, &DamageState::default(), 1e-7 * eps.amax());
            let err = rel_diff(r.tangent.as_slice(), fd.as_slice());
            assert!(err <= 1e-6, "{eps:?}: {err:e}");
        }
    }
}
