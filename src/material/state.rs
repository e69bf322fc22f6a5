//! [`DamageState`]: the history of one material point, the active [`Side`] of the unilateral split,
//! and the evolution of the history over one strain update.

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
    let kappa = if loading { eps_eq } else { kappa_old };
    let dv = law.damage(side, kappa);
    let (dd_deq, dissipation) = if loading {
        let c = y / (eps_eq * eps_eq);
        (dv.slope, law.dissipation(side, c, kappa_old, kappa))
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
