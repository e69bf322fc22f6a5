//! The energy balance of the relative motion, accumulated step by step.
//!
//! Dotting the equation of motion `M a + C v + f_int = f` averaged over a step with the step's
//! displacement increment `Δu` gives, for average acceleration (`Δu = h (v_n + v_{n+1})/2`,
//! `Δv = h (a_n + a_{n+1})/2`), exactly
//!
//! ```text
//!   ΔE_k + ΔW_damp + ΔW_int = ΔW_in,   E_k = ½ vᵀ M v,
//!   ΔW_damp = Δuᵀ (C v_n + C v_{n+1})/2,  ΔW_int = Δuᵀ (f_int,n + f_int,n+1)/2,
//!   ΔW_in = Δuᵀ (f_n + f_{n+1})/2,  f = f_static − Σ_d M ι_d a_g,d(t)
//! ```
//!
//! (Hughes, *The Finite Element Method*, §9.3, for the linear case; the trapezoidal sums make it
//! hold for any f_int.) For a secant material (σ = (1 − d) C₀ ε, elastic frames) the recoverable
//! strain energy is `E_s = ½ uᵀ f_int(u)`, so the energy dissipated by damage is
//! `W_int − (E_s − E_s,0)`. Other schemes (γ > ½, HHT) dissipate numerically: their balance error
//! measures that dissipation plus the Newton tolerance.

/// Accumulated energies [J], from the start of the time history.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyBalance {
    /// Work of the external forces (ground motion and static loads) on the relative motion.
    pub input: f64,
    /// Kinetic energy of the relative motion, ½ vᵀ M v.
    pub kinetic: f64,
    /// Work of the internal forces, ∫ f_int · du.
    pub internal_work: f64,
    /// Energy dissipated by viscous damping.
    pub damping: f64,
    /// Recoverable strain energy ½ uᵀ f_int(u) now.
    pub strain: f64,
    /// Recoverable strain energy at the start.
    pub strain0: f64,
}

impl EnergyBalance {
    /// Energy dissipated by damage (and any other inelastic process): `W_int − (E_s − E_s,0)`.
    pub fn dissipated(&self) -> f64 {
        self.internal_work - (self.strain - self.strain0)
    }

    /// `W_in − (E_k + W_damp + W_int)`.
    pub fn error(&self) -> f64 {
        self.input - (self.kinetic + self.damping + self.internal_work)
    }

    /// The error over the largest magnitude among the terms (0 when all vanish).
    pub fn relative_error(&self) -> f64 {
        let scale = self.input.abs().max(self.kinetic.abs() + self.damping.abs() + self.internal_work.abs());
        if scale > 0.0 {
            self.error().abs() / scale
        } else {
            0.0
        }
    }

    /// The values as f64s, for checkpoints.
    pub fn to_array(&self) -> [f64; 6] {
        [self.input, self.kinetic, self.internal_work, self.damping, self.strain, self.strain0]
    }

    /// From [`Self::to_array`].
    pub fn from_array(a: [f64; 6]) -> EnergyBalance {
        EnergyBalance { input: a[0], kinetic: a[1], internal_work: a[2], damping: a[3], strain: a[4], strain0: a[5] }
    }

    /// The CSV header of [`Self::csv_row`].
    pub const CSV_HEADER: &'static str = "step,time,input,kinetic,strain,damping,dissipated_damage,internal_work,balance_error,relative_error";

    /// One CSV row.
    pub fn csv_row(&self, step: usize, t: f64) -> String {
        format!(
            "{step},{t:.10e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.6e},{:.6e}",
            self.input,
            self.kinetic,
            self.strain - self.strain0,
            self.damping,
            self.dissipated(),
            self.internal_work,
            self.error(),
            self.relative_error()
        )
    }
}
