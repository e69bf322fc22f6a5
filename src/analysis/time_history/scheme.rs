//! The time-integration scheme: Newmark's family and Hilber–Hughes–Taylor α.
//!
//! Newmark (Newmark 1959; Hughes, *The Finite Element Method*, §9.1):
//!
//! ```text
//!   u_{n+1} = u_n + h v_n + h² [(½ − β) a_n + β a_{n+1}]
//!   v_{n+1} = v_n + h [(1 − γ) a_n + γ a_{n+1}]
//! ```
//!
//! so that, with `u_{n+1}` the unknown,
//!
//! ```text
//!   a_{n+1} = (u_{n+1} − u_n − h v_n) / (β h²) − (1/(2β) − 1) a_n
//!   v_{n+1} = γ/(β h) (u_{n+1} − u_n) + (1 − γ/β) v_n + h (1 − γ/(2β)) a_n
//! ```
//!
//! HHT-α (Hilber, Hughes & Taylor 1977), α ∈ [−1/3, 0], β = (1 − α)²/4, γ = ½ − α, weights the
//! equation of motion between the two ends of the step (α = 0 is Newmark):
//!
//! ```text
//!   M a_{n+1} + (1 + α)(C v_{n+1} + f_int(u_{n+1})) − α (C v_n + f_int(u_n))
//!       = (1 + α) f_{n+1} − α f_n
//! ```
//!
//! The Jacobian of the residual with respect to `u_{n+1}` is
//! `(1 + α) [K_t + c_m M + c_c C]` with `c_m = 1/((1 + α) β h²)` and `c_c = γ/(β h)`.
//! Average acceleration (β = ¼, γ = ½) is unconditionally stable, conserves energy exactly in
//! linear free vibration and lengthens the period by `T̄/T = Ω / (2 arctan(Ω/2))`, `Ω = ω h`.

/// Newmark/HHT parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scheme {
    /// Newmark β.
    pub beta: f64,
    /// Newmark γ.
    pub gamma: f64,
    /// HHT α ∈ [−1/3, 0] (0 for Newmark).
    pub alpha: f64,
}

impl Default for Scheme {
    /// Average acceleration: β = ¼, γ = ½, α = 0.
    fn default() -> Self {
        Scheme { beta: 0.25, gamma: 0.5, alpha: 0.0 }
    }
}

impl Scheme {
    /// HHT with its usual β, γ for a given α.
    pub fn hht(alpha: f64) -> Scheme {
        Scheme { beta: (1.0 - alpha) * (1.0 - alpha) / 4.0, gamma: 0.5 - alpha, alpha }
    }

    /// `(c_m, c_c)`: the Jacobian is `(1 + α)(K_t + c_m M + c_c C)` for a step `h`.
    pub fn jacobian_coefficients(&self, h: f64) -> (f64, f64) {
        (1.0 / ((1.0 + self.alpha) * self.beta * h * h), self.gamma / (self.beta * h))
    }

    /// `a_{n+1}` and `v_{n+1}` from `u_{n+1}`, element-wise (the formulas of the module docs).
    #[allow(clippy::too_many_arguments)]
    pub fn kinematics(&self, h: f64, un: &[f64], vn: &[f64], an: &[f64], u: &[f64], v: &mut [f64], a: &mut [f64]) {
        let (b, g) = (self.beta, self.gamma);
        let c1 = 1.0 / (b * h * h);
        let c2 = 1.0 / (b * h);
        let c3 = 1.0 / (2.0 * b) - 1.0;
        let d1 = g / (b * h);
        let d2 = 1.0 - g / b;
        let d3 = h * (1.0 - g / (2.0 * b));
        for i in 0..u.len() {
            let du = u[i] - un[i];
            a[i] = c1 * du - c2 * vn[i] - c3 * an[i];
            v[i] = d1 * du + d2 * vn[i] + d3 * an[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinematics_satisfy_the_newmark_relations() {
        // Any (u_n, v_n, a_n, u_{n+1}): the returned a, v satisfy both defining equations exactly.
        let s = Scheme { beta: 0.3, gamma: 0.6, alpha: 0.0 };
        let h = 0.01;
        let (un, vn, an, u) = ([1.0], [2.0], [3.0], [1.05]);
        let (mut v, mut a) = ([0.0], [0.0]);
        s.kinematics(h, &un, &vn, &an, &u, &mut v, &mut a);
        let u_back = un[0] + h * vn[0] + h * h * ((0.5 - s.beta) * an[0] + s.beta * a[0]);
        let v_back = vn[0] + h * ((1.0 - s.gamma) * an[0] + s.gamma * a[0]);
        assert!((u_back - u[0]).abs() < 1e-14);
        assert!((v_back - v[0]).abs() < 1e-12);
    }

    #[test]
    fn hht_parameters() {
        // Hilber, Hughes & Taylor (1977): β = (1 − α)²/4, γ = ½ − α.
        let s = Scheme::hht(-0.1);
        assert!((s.beta - 0.3025).abs() < 1e-15 && (s.gamma - 0.6).abs() < 1e-15);
    }
}
