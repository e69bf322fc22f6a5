//! Forward-mode dual numbers over the six DOFs of a contact pair `(q_i, q_j)`: the derivatives of
//! the contact law ([`super::contact_jacobian`]).
//!
//! A [`Dual6`] is `a + Σ_k a_k ε_k` with `ε_k ε_l = 0`: arithmetic on it carries the value `a`
//! (bit for bit the `f64` operation) and the gradient `(a_k)` by the chain rule,
//!
//! ```text
//!   (a, ∇a) ± (b, ∇b) = (a ± b, ∇a ± ∇b)      (a, ∇a)(b, ∇b) = (ab, b ∇a + a ∇b)
//!   (a, ∇a)/(b, ∇b)   = (a/b, (∇a − (a/b) ∇b)/b)
//!   √(a, ∇a)          = (√a, ∇a/(2√a))         sin, cos likewise
//! ```
//!
//! Seeding `q_k + ε_k` and evaluating the law gives the exact Jacobian column by column in one
//! pass. Branches (clipping, stick or slip) are taken on the values, so the result is the
//! derivative of the branch the value lies on: the one-sided derivative at a kink, an element
//! of the generalized Jacobian of semismooth Newton (Alart & Curnier 1991; Hüeber, Stadler &
//! Wohlmuth 2008).
//!
//! Why not the `num-dual` crate: its current release needs Rust 1.89, above this crate's
//! `rust-version` (1.85), and the law needs only the arithmetic, `sqrt` and `sin_cos` of a
//! fixed six-direction dual, about a hundred lines here with no allocation and no optional
//! derivative to branch on.
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// The number of directions: the DOFs `(u_x, u_y, θ)` of the two stones of a pair.
pub const N: usize = 6;

/// A value with its gradient over the pair's six DOFs (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dual6 {
    /// The value.
    pub re: f64,
    /// Its derivatives `∂/∂q_k`.
    pub eps: [f64; N],
}

impl Dual6 {
    /// A constant (zero gradient).
    pub const fn constant(re: f64) -> Dual6 {
        Dual6 { re, eps: [0.0; N] }
    }

    /// The independent variable `k` at the value `re` (`∂/∂q_k = 1`).
    pub fn variable(re: f64, k: usize) -> Dual6 {
        let mut eps = [0.0; N];
        eps[k] = 1.0;
        Dual6 { re, eps }
    }

    fn map(self, re: f64, d: f64) -> Dual6 {
        Dual6 { re, eps: self.eps.map(|e| d * e) }
    }

    /// `√a` (the gradient is infinite at 0: callers keep away from it).
    pub fn sqrt(self) -> Dual6 {
        let r = self.re.sqrt();
        self.map(r, 0.5 / r)
    }

    /// `(sin a, cos a)`.
    pub fn sin_cos(self) -> (Dual6, Dual6) {
        let (s, c) = self.re.sin_cos();
        (self.map(s, c), self.map(c, -s))
    }

    /// `√(a² + b²)` with the value of `f64::hypot` (the gradient is infinite at 0).
    pub fn hypot(self, b: Dual6) -> Dual6 {
        let r = self.re.hypot(b.re);
        Dual6 { re: r, eps: std::array::from_fn(|k| (self.re * self.eps[k] + b.re * b.eps[k]) / r) }
    }

    /// `|a|`, the branch taken on the value's sign (the derivative of `a` at 0).
    pub fn abs(self) -> Dual6 {
        if self.re < 0.0 {
            -self
        } else {
            self
        }
    }
}

impl From<f64> for Dual6 {
    fn from(re: f64) -> Dual6 {
        Dual6::constant(re)
    }
}

impl Add for Dual6 {
    type Output = Dual6;
    fn add(self, b: Dual6) -> Dual6 {
        Dual6 { re: self.re + b.re, eps: std::array::from_fn(|k| self.eps[k] + b.eps[k]) }
    }
}

impl AddAssign for Dual6 {
    fn add_assign(&mut self, b: Dual6) {
        *self = *self + b;
    }
}

impl Sub for Dual6 {
    type Output = Dual6;
    fn sub(self, b: Dual6) -> Dual6 {
        Dual6 { re: self.re - b.re, eps: std::array::from_fn(|k| self.eps[k] - b.eps[k]) }
    }
}

impl Neg for Dual6 {
    type Output = Dual6;
    fn neg(self) -> Dual6 {
        Dual6 { re: -self.re, eps: self.eps.map(|e| -e) }
    }
}

impl Mul for Dual6 {
    type Output = Dual6;
    /// The product rule, (a b)' = a' b + a b': a sum inside a product by design.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn mul(self, b: Dual6) -> Dual6 {
        Dual6 { re: self.re * b.re, eps: std::array::from_fn(|k| self.eps[k] * b.re + self.re * b.eps[k]) }
    }
}

impl Mul<f64> for Dual6 {
    type Output = Dual6;
    fn mul(self, b: f64) -> Dual6 {
        Dual6 { re: self.re * b, eps: self.eps.map(|e| e * b) }
    }
}

impl Mul<Dual6> for f64 {
    type Output = Dual6;
    fn mul(self, b: Dual6) -> Dual6 {
        Dual6 { re: self * b.re, eps: b.eps.map(|e| self * e) }
    }
}

impl Div for Dual6 {
    type Output = Dual6;
    /// The quotient rule, (a / b)' = (a' − (a/b) b') / b: a difference and a product by design.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, b: Dual6) -> Dual6 {
        let q = self.re / b.re;
        Dual6 { re: q, eps: std::array::from_fn(|k| (self.eps[k] - q * b.eps[k]) / b.re) }
    }
}

impl Div<f64> for Dual6 {
    type Output = Dual6;
    fn div(self, b: f64) -> Dual6 {
        Dual6 { re: self.re / b, eps: self.eps.map(|e| e / b) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_a_composite_match_the_closed_form() {
        // f(x, y) = sin(x) √(x² + y²) / (1 + x y) at (0.7, −0.4), derivatives by hand:
        // with r = √(x² + y²), d = 1 + x y:
        //   ∂f/∂x = [cos x r + sin x x/r]/d − f y/d ,   ∂f/∂y = [sin x y/r]/d − f x/d.
        // Tolerance 1e-15 relative (a few roundings of order-one numbers).
        let (x0, y0) = (0.7f64, -0.4f64);
        let (x, y) = (Dual6::variable(x0, 0), Dual6::variable(y0, 4));
        let (s, _) = x.sin_cos();
        let f = s * (x * x + y * y).sqrt() / (Dual6::constant(1.0) + x * y);
        let (r, d) = ((x0 * x0 + y0 * y0).sqrt(), 1.0 + x0 * y0);
        let fv = x0.sin() * r / d;
        let fx = (x0.cos() * r + x0.sin() * x0 / r) / d - fv * y0 / d;
        let fy = (x0.sin() * y0 / r) / d - fv * x0 / d;
        assert!((f.re - fv).abs() <= 1e-15 * fv.abs());
        assert!((f.eps[0] - fx).abs() <= 1e-15 * fx.abs(), "{} vs {fx}", f.eps[0]);
        assert!((f.eps[4] - fy).abs() <= 1e-15 * fy.abs(), "{} vs {fy}", f.eps[4]);
        assert_eq!([f.eps[1], f.eps[2], f.eps[3], f.eps[5]], [0.0; 4]);
        // The value is the f64 computation itself, bit for bit.
        assert_eq!(f.re, x0.sin() * (x0 * x0 + y0 * y0).sqrt() / (1.0 + x0 * y0));
        assert_eq!((-x).abs().eps[0], 1.0);
        // hypot: ∂√(x² + y²)/∂x = x/r, the value f64::hypot's.
        let h = x.hypot(y);
        assert_eq!(h.re, x0.hypot(y0));
        assert!((h.eps[0] - x0 / r).abs() <= 1e-15 && (h.eps[4] - y0 / r).abs() <= 1e-15);
    }
}
