//! The energy balance of the relative motion, accumulated step by step.
//!
//! # The balance
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
//! hold for any f_int.) `balance_error = W_in − (E_k + W_damp + W_int)`. Other schemes (γ > ½,
//! HHT) dissipate numerically: their balance error measures that dissipation plus the Newton
//! tolerance.
//!
//! # Where the internal work goes
//! `W_int` is split into three physically distinct parts:
//!
//! ```text
//!   W_int = ΔE_s + D + U
//!   E_s = ½ uᵀ f_int(u)                       "strain": recoverable energy now (secant law)
//!   D   = Σ_points ∫ (Y_t ḋ_t + Y_c ḋ_c) dV     "dissipated_damage": the law's own dissipation
//!   U   = W_int − ΔE_s − D                      "unilateral": energy exchanged at crack closure
//! ```
//!
//! * `E_s`: for a secant material (σ = (1 − d) C₀ ε per side, elastic frames) ½ uᵀ f_int(u) is the
//!   sum of the points' ψ = [(1−d_t) H(tr σ̃) + (1−d_c) H(−tr σ̃)] ½ ε:C₀:ε (paper §3.1).
//! * `D`: each element reports the energy its points have dissipated up to the committed state
//!   (`Element::dissipated_energy`: the material's increments c [F(κ) − F(κ_old)] ≥ 0, exact for a
//!   radial strain path), so `D` is never negative and never decreases, whatever the path.
//! * `U`: ψ is not a function of the strain alone: where d_t ≠ d_c it jumps by
//!   ±(d_t − d_c) ½ ε:C₀:ε when tr σ̃ changes sign (a crack closing or reopening; plane-stress
//!   layers spread the jump over their smoothing band), with no work done. Closing a crack with
//!   d_t > d_c raises ψ at no cost (`U` falls), reopening it releases that energy (`U` rises): `U`
//!   has either sign. It also holds the O(Δε Δd) difference between the trapezoidal work and the
//!   exact dissipation of a step in which damage grows, and the Newton tolerance's share.
//!
//! Hence `W_in = E_k + W_damp + ΔE_s + D + U + balance_error`: the balance closes as before, and
//! the damage column is the law's dissipation, not a residual. `D` and `E_s` count from the start
//! of the time history (the state after gravity), like every other term.
//!
//! # Under IMPL-EX (`[dynamics] integration = "implex"`, `material::implex`)
//! The forces in equilibrium, hence `W_int` and `E_s` (½ uᵀ f_int at the step's end), are those
//! of the extrapolated damage with the split frozen at the last committed strain; `D` is the
//! dissipation of the committed histories, the implicit law's along the computed strain path
//! (never negative, never decreasing). The trapezoidal identity holds as before (each step ends
//! in equilibrium with the forces it used), so the balance error is still the Newton
//! tolerance's. What the extrapolation does to the work — the stress of a cracking point
//! follows the damage of the step before, so it stores more energy than the implicit law would
//! (up to the elastic energy of a whole step's strain where a crack starts) and gives it back
//! when the damage is committed — has no term of its own: it is in `U`, with the crack-closure
//! exchange. It vanishes with the step: on `implex_tests.rs`'s bar U falls from 5.2e-2 J at
//! dt = 0.02 s to 1.9e-3 J at 0.0025 s against D ≈ 0.2 J, and the job's `unilateral` against
//! the implicit run's is the measure of it.

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
    /// Energy dissipated by the material law up to now, since the model was built (gravity
    /// included): Σ over elements of `Element::dissipated_energy`.
    pub damage: f64,
    /// [`Self::damage`] at the start of the time history.
    pub damage0: f64,
}

/// The vectors of one converged step that its energy terms need (owned entries): the increment,
/// the loads, damping and internal forces at both ends, and the end's u, v and `M v`.
pub struct StepVectors<'a> {
    /// `Δu = u_{n+1} − u_n`.
    pub du: &'a [f64],
    /// `f_n`, `f_{n+1}`.
    pub f: [&'a [f64]; 2],
    /// `C v_n`, `C v_{n+1}`.
    pub cv: [&'a [f64]; 2],
    /// `f_int,n`, `f_int,n+1`.
    pub fi: [&'a [f64]; 2],
    /// `u_{n+1}`, `v_{n+1}` and `M v_{n+1}` (none when that product failed: the kinetic energy
    /// is then left as it was).
    pub u: &'a [f64],
    /// See `u`.
    pub v: &'a [f64],
    /// See `u`.
    pub mv: Option<&'a [f64]>,
}

impl EnergyBalance {
    /// Number of values of [`Self::to_array`].
    pub const N_VALUES: usize = 8;

    /// Collective (one reduction). Adds a step's trapezoidal works (module docs) and sets the
    /// strain and kinetic energies at its end.
    pub fn add_step<S: super::system::DynamicSystem + ?Sized>(&mut self, sys: &S, s: StepVectors) {
        let du = s.du;
        let mut pairs = vec![(du, s.f[0]), (du, s.f[1]), (du, s.cv[0]), (du, s.cv[1]), (du, s.fi[0]), (du, s.fi[1])];
        pairs.push((s.u, s.fi[1]));
        if let Some(mv) = s.mv {
            pairs.push((s.v, mv));
        }
        let d = sys.dots(&pairs);
        self.input += 0.5 * (d[0] + d[1]);
        self.damping += 0.5 * (d[2] + d[3]);
        self.internal_work += 0.5 * (d[4] + d[5]);
        self.strain = 0.5 * d[6];
        if s.mv.is_some() {
            self.kinetic = 0.5 * d[7];
        }
    }

    /// Energy dissipated by the damage law since the start, `D − D₀` (≥ 0, non-decreasing).
    pub fn dissipated(&self) -> f64 {
        self.damage - self.damage0
    }

    /// Energy exchanged at unilateral switches (crack closure and reopening), the part of the
    /// internal work that is neither recoverable nor dissipated: `W_int − ΔE_s − D` (module docs).
    pub fn unilateral(&self) -> f64 {
        self.internal_work - (self.strain - self.strain0) - self.dissipated()
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
    pub fn to_array(&self) -> [f64; Self::N_VALUES] {
        [
            self.input,
            self.kinetic,
            self.internal_work,
            self.damping,
            self.strain,
            self.strain0,
            self.damage,
            self.damage0,
        ]
    }

    /// From [`Self::to_array`].
    pub fn from_array(a: [f64; Self::N_VALUES]) -> EnergyBalance {
        EnergyBalance {
            input: a[0],
            kinetic: a[1],
            internal_work: a[2],
            damping: a[3],
            strain: a[4],
            strain0: a[5],
            damage: a[6],
            damage0: a[7],
        }
    }

    /// The CSV header of [`Self::csv_row`]: `input = kinetic + damping + strain +
    /// dissipated_damage + unilateral + balance_error`, `internal_work = strain +
    /// dissipated_damage + unilateral`.
    pub const CSV_HEADER: &'static str =
        "step,time,input,kinetic,strain,damping,dissipated_damage,unilateral,internal_work,balance_error,relative_error";

    /// One CSV row.
    pub fn csv_row(&self, step: usize, t: f64) -> String {
        format!(
            "{step},{t:.10e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.6e},{:.6e}",
            self.input,
            self.kinetic,
            self.strain - self.strain0,
            self.damping,
            self.dissipated(),
            self.unilateral(),
            self.internal_work,
            self.error(),
            self.relative_error()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::EnergyBalance;

    #[test]
    fn the_columns_add_up_to_the_input() {
        // Arbitrary values: W_in = E_k + W_damp + ΔE_s + D + U + error by construction of U.
        let e = EnergyBalance {
            input: 10.0,
            kinetic: 1.5,
            internal_work: 6.0,
            damping: 2.0,
            strain: 7.0,
            strain0: 4.0,
            damage: 5.0,
            damage0: 2.5,
        };
        assert_eq!(e.dissipated(), 2.5);
        assert_eq!(e.unilateral(), 6.0 - 3.0 - 2.5);
        let sum = e.kinetic + e.damping + (e.strain - e.strain0) + e.dissipated() + e.unilateral() + e.error();
        assert!((sum - e.input).abs() < 1e-14, "{sum}");
        assert_eq!(EnergyBalance::from_array(e.to_array()), e);
        let row = e.csv_row(3, 0.1);
        assert_eq!(row.split(',').count(), EnergyBalance::CSV_HEADER.split(',').count());
    }
}
