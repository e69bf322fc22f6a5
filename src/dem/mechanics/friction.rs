//! Coulomb friction at a contact (paper §2.1, eq. 5): elastic predictor, return map.
//!
//! In 2D the tangential force is a scalar `F_t` along `t_c = e_z × n_c`, with the sign convention
//! of the internal forces ([`super::contact`]): `F_t` is the resistance to the slip `g_t` of j
//! relative to i, so the contact pushes j with `−F_t t_c` and i with `+F_t t_c`. For a slip
//! increment `Δg_t` ([`super::contact::Contact::tangential_increment`], rotations included):
//!
//! ```text
//!   F_trial = F_t,old + k_t Δg_t
//!   stick   if |F_trial| ≤ μ F_n :  F_t = F_trial,            Δg_p = 0,   dF_t/dΔg_t = k_t
//!   slip    otherwise            :  F_t = μ F_n sign(F_trial),
//!                                   Δg_p = (F_trial − F_t)/k_t,           dF_t/dΔg_t = 0,
//!                                   dF_t/dF_n = μ sign(F_trial)
//! ```
//!
//! The dissipated energy of the increment is `F_t Δg_p = μ F_n |Δg_p| ≥ 0` (backward-Euler
//! integration of the plastic slip). Default `k_t = k_n` of the contact
//! ([`super::MechParams::kt_over_kn`] = 1).

use nalgebra::SMatrix;

use super::contact::Contact;
use super::error::{non_negative, positive, MechanicsError};

/// Whether the contact sticks or slides at the end of the increment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SlipState {
    /// Elastic (no sliding): `|F_t| < μ F_n` or on the cone without exceeding it.
    Stick,
    /// Sliding on the Coulomb cone: `|F_t| = μ F_n`.
    Slip,
}

/// The result of one friction update.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrictionUpdate {
    /// The new tangential force `F_t` (N, signed along `t_c`): store it as the next `F_t,old`.
    pub f_t: f64,
    /// Stick or slip.
    pub state: SlipState,
    /// The plastic (sliding) part of the slip increment, `Δg_p` (m, signed).
    pub slip: f64,
    /// Dissipated energy of the increment, `μ F_n |Δg_p|` (J, ≥ 0).
    pub dissipation: f64,
    /// `∂F_t/∂Δg_t`: `k_t` when sticking, 0 when sliding.
    pub tangent: f64,
    /// `∂F_t/∂F_n`: 0 when sticking, `μ sign(F_t)` when sliding.
    pub d_ft_d_fn: f64,
}

/// The return map. Errors: `k_t` not finite and > 0; `mu` or `f_n` not finite and ≥ 0.
pub fn friction_update(f_t_old: f64, dg_t: f64, k_t: f64, mu: f64, f_n: f64) -> Result<FrictionUpdate, MechanicsError> {
    positive("k_t", k_t)?;
    non_negative("mu", mu)?;
    non_negative("f_n", f_n)?;
    let trial = f_t_old + k_t * dg_t;
    let limit = mu * f_n;
    if trial.abs() <= limit {
        return Ok(FrictionUpdate {
            f_t: trial,
            state: SlipState::Stick,
            slip: 0.0,
            dissipation: 0.0,
            tangent: k_t,
            d_ft_d_fn: 0.0,
        });
    }
    let sign = trial.signum();
    let f_t = sign * limit;
    let slip = (trial - f_t) / k_t;
    Ok(FrictionUpdate {
        f_t,
        state: SlipState::Slip,
        slip,
        dissipation: limit * slip.abs(),
        tangent: 0.0,
        d_ft_d_fn: mu * sign,
    })
}

/// The 6×6 tangent of the internal friction forces `F_t c` (frozen contact geometry):
/// stick `k_t c cᵀ` (symmetric); slip `μ sign(F_t) k_n c bᵀ` (the coupling through the penalty
/// normal law, not symmetric; drop it for a symmetric solver: zero tangential stiffness).
pub fn friction_stiffness(contact: &Contact, update: &FrictionUpdate) -> SMatrix<f64, 6, 6> {
    let c = contact.tangential_direction();
    match update.state {
        SlipState::Stick => c * c.transpose() * update.tangent,
        SlipState::Slip => c * contact.normal_direction().transpose() * (update.d_ft_d_fn * contact.k_n),
    }
}

#[cfg(test)]
mod tests {
    use super::super::contact::contact;
    use super::super::MechParams;
    use super::*;
    use crate::dem::polygon::Polygon;

    #[test]
    fn block_on_a_block_sticks_then_slides_at_mu_n() {
        // A unit block j on a wide block i = [−1, 2]×[0, 1], overlap p = 1e-3 (the normal load N):
        // S = 1e-3, ℓ_c = 1, Ē = 1e6, t_z = 1 → N = F_n = 1000 N, k_n = Ē L/ℓ_c = 1e6 N/m (L = 1),
        // k_t = k_n, μ = 0.6 → μN = 600 N, reached after an elastic slip of 6e-4 m. Pushed along +x
        // by steps of 1.3e-4 m (slip g_t = −x since t_c = e_z × e_y = −e_x): steps 1–4 stick with
        // |F_t| = k_t · 1.3e-4 · k; step 5 slides 6.5e-4 − 6e-4 = 5e-5 m, later steps 1.3e-4 m each;
        // dissipation μN × sliding. All by hand; tolerance 1e-9 relative (N from polygon clipping).
        let p = MechParams { e_bar: 1e6, t_z: 1.0, mu: 0.6, ..MechParams::default() };
        let pi = Polygon::rectangle(-1.0, 0.0, 2.0, 1.0);
        let pj0 = Polygon::rectangle(0.0, 0.999, 1.0, 1.999);
        let (ci, cj0) = ([0.5, 0.5], [0.5, 1.499]);
        let (step, mut x, mut f_t, mut total) = (1.3e-4, 0.0, 0.0, 0.0);
        for k in 1..=8 {
            let pj = pj0.moved(cj0, [x, 0.0], 0.0);
            let c = contact(&pi, &pj, ci, [cj0[0] + x, cj0[1]], 1.0, 1.0, &p).unwrap().unwrap();
            assert!((c.f_n - 1000.0).abs() < 1e-9 * 1000.0, "N = {}", c.f_n);
            assert!((c.k_n - 1e6).abs() < 1e-9 * 1e6 && (c.normal[1] - 1.0).abs() < 1e-12);
            let dg = c.tangential_increment([0.0; 3], [step, 0.0, 0.0]);
            assert!((dg + step).abs() < 1e-15);
            let u = friction_update(f_t, dg, c.k_n * p.kt_over_kn, p.mu, c.f_n).unwrap();
            let elastic = step * k as f64;
            if elastic < 6e-4 {
                assert_eq!(u.state, SlipState::Stick);
                assert!((u.f_t + 1e6 * elastic).abs() < 1e-9 * 1e6 * elastic);
                assert_eq!(u.dissipation, 0.0);
            } else {
                assert_eq!(u.state, SlipState::Slip);
                assert!((u.f_t + 600.0).abs() < 1e-9 * 600.0);
                let sliding = if k == 5 { 5e-5 } else { step };
                assert!((u.slip.abs() - sliding).abs() < 1e-9 * sliding, "step {k}: {}", u.slip);
                assert!((u.dissipation - 600.0 * sliding).abs() < 1e-9 * 600.0 * sliding);
                assert_eq!(u.tangent, 0.0);
            }
            // The force on j (minus the internal one) opposes the push: along −x, magnitude |F_t|.
            let (_, fj) = c.tangential_forces(u.f_t);
            assert!((-fj[0] + u.f_t.abs()).abs() < 1e-9 * u.f_t.abs() && fj[1].abs() < 1e-12);
            f_t = u.f_t;
            total += u.dissipation;
            x += step;
        }
        // Total: μN (8 · 1.3e-4 − 6e-4) = 600 · 4.4e-4 = 0.264 J.
        assert!((total - 0.264).abs() < 1e-9);
    }

    #[test]
    fn stick_stiffness_is_the_derivative_and_bad_input_is_an_error() {
        // Stick: F_t = F_old + k_t Δg exactly; tangent k_t; the 6×6 tangent times Δq gives
        // ΔF_t c (exact for the linear predictor, tolerance 1e-12 relative).
        let p = MechParams { e_bar: 1e6, ..MechParams::default() };
        let pi = Polygon::rectangle(0.0, 0.0, 1.0, 1.0);
        let pj = Polygon::rectangle(0.2, 0.99, 0.9, 1.5);
        let c = contact(&pi, &pj, [0.5, 0.5], [0.55, 1.245], 1.0, 0.7, &p).unwrap().unwrap();
        let dq = ([1e-7, 2e-8, -3e-7], [-2e-7, 1e-8, 4e-7]);
        let dg = c.tangential_increment(dq.0, dq.1);
        let u = friction_update(5.0, dg, c.k_n, 0.6, c.f_n).unwrap();
        assert_eq!(u.state, SlipState::Stick);
        let k = friction_stiffness(&c, &u);
        let df = k * super::super::beam::stack(dq.0, dq.1);
        let (a, b) = c.tangential_forces(u.f_t - 5.0);
        let want = [a[0], a[1], a[2], b[0], b[1], b[2]];
        for r in 0..6 {
            assert!((df[r] - want[r]).abs() <= 1e-12 * df.abs().max());
        }
        assert!(friction_update(0.0, 1.0, 0.0, 0.6, 1.0).is_err());
        assert!(friction_update(0.0, 1.0, 1.0, -0.1, 1.0).is_err());
        // Frictionless: always sliding at F_t = 0, dissipating nothing.
        let u = friction_update(0.0, 1e-3, 1.0, 0.0, 10.0).unwrap();
        assert!(u.state == SlipState::Slip && u.f_t == 0.0 && u.dissipation == 0.0);
    }
}
