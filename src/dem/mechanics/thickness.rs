//! The thickness function of a contact's overlap: the Winkler layer the normal law is read as
//! ([`super::contact`], "Stored energy"; [`super::crushing`]).
//!
//! For a convex overlap polygon and the contact normal `n` (tangent `t = e_z × n`), `δ(s)` is
//! the length of the polygon's section by the line `{x : t·x = s}`: the layer's thickness at the
//! tangential coordinate `s`. A convex polygon's width function is linear between the vertices'
//! coordinates `s_k` (and concave), so it is stored as its values `δ_k` there; outside
//! `[s_0, s_last]` it is zero (at an end where an edge is parallel to `n`, `δ` drops to zero
//! there: the value stored is the limit from inside).
//!
//! With a uniform plastic depth `c` (crushing), the pressure is `p(s) = κ (δ(s) − c)₊`, and the
//! contact law needs, for any level `c ≥ 0`,
//!
//! ```text
//!   S(c)  = ∫ (δ − c)₊ ds           (the force / κ)
//!   S₁(c) = ∫ (δ − c)₊ s ds         (its first moment: the pressure centroid is S₁/S)
//!   S₂(c) = ∫ (δ − c)₊² ds          (2 × the potential / κ)
//!   W(c)  = |{s : δ(s) > c}|        (the loaded width, −dS/dc)
//! ```
//!
//! exact on each linear piece: where the piece is partly below `c`, it is cut at the crossing.

/// `δ(s)` as its values at increasing coordinates (module docs).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ThicknessProfile {
    /// Tangential coordinates `s_k` (m), increasing.
    pub s: Vec<f64>,
    /// Thicknesses `δ_k ≥ 0` there (m).
    pub delta: Vec<f64>,
}

/// The integrals of the part of a profile above a level (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Clipped {
    /// `S(c) = ∫ (δ − c)₊ ds` (m²).
    pub area: f64,
    /// `S₁(c) = ∫ (δ − c)₊ s ds` (m³).
    pub first: f64,
    /// `S₂(c) = ∫ (δ − c)₊² ds` (m³).
    pub second: f64,
    /// `W(c) = |{δ > c}|` (m).
    pub width: f64,
}

impl ThicknessProfile {
    /// The largest thickness.
    pub fn max(&self) -> f64 {
        self.delta.iter().fold(0.0, |m: f64, &d| m.max(d))
    }

    /// The integrals of `(δ − c)₊` (module docs).
    pub fn clipped(&self, c: f64) -> Clipped {
        let mut out = Clipped::default();
        for k in 0..self.s.len().saturating_sub(1) {
            let (s0, s1) = (self.s[k], self.s[k + 1]);
            let (a, b) = (self.delta[k] - c, self.delta[k + 1] - c);
            if s1 <= s0 || (a <= 0.0 && b <= 0.0) {
                continue;
            }
            // The part of [s0, s1] where the linear (δ − c) is positive, and its end values.
            let (lo, hi, ya, yb) = if a >= 0.0 && b >= 0.0 {
                (s0, s1, a, b)
            } else if a > 0.0 {
                (s0, s0 + (s1 - s0) * a / (a - b), a, 0.0)
            } else {
                (s1 - (s1 - s0) * b / (b - a), s1, 0.0, b)
            };
            let h = hi - lo;
            out.width += h;
            out.area += 0.5 * h * (ya + yb);
            // ∫ y s over the piece with y linear from ya at lo to yb at hi.
            out.first += h * (ya * (2.0 * lo + hi) + yb * (lo + 2.0 * hi)) / 6.0;
            out.second += h * (ya * ya + ya * yb + yb * yb) / 3.0;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrals_of_a_trapezoid_and_of_a_tent() {
        // A strip over [−1, 1] thick 2 at the left end and 4 at the right end: δ = 3 + s.
        // Closed forms at level 0: S = 6, S₁ = ∫(3 + s) s = 2/3, S₂ = ∫(3 + s)² = 18 + 2/3.
        // At level 3: (δ − 3)₊ = s on [0, 1]: S = 1/2, S₁ = 1/3, S₂ = 1/3, W = 1.
        let p = ThicknessProfile { s: vec![-1.0, 1.0], delta: vec![2.0, 4.0] };
        let c = p.clipped(0.0);
        for (got, want) in [(c.area, 6.0), (c.first, 2.0 / 3.0), (c.second, 18.0 + 2.0 / 3.0), (c.width, 2.0)] {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        let c = p.clipped(3.0);
        for (got, want) in [(c.area, 0.5), (c.first, 1.0 / 3.0), (c.second, 1.0 / 3.0), (c.width, 1.0)] {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        // A tent of height 2 over [−1, 3] (apex at s = 1), cut at 1: a tent of height 1 over
        // [0, 2]: S = 1, S₁ = 1 (centroid at 1), S₂ = 2/3, W = 2. Above the apex: all zero.
        let t = ThicknessProfile { s: vec![-1.0, 1.0, 3.0], delta: vec![0.0, 2.0, 0.0] };
        let c = t.clipped(1.0);
        for (got, want) in [(c.area, 1.0), (c.first, 1.0), (c.second, 2.0 / 3.0), (c.width, 2.0)] {
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        assert_eq!(t.clipped(2.5), Clipped::default());
        assert_eq!(t.max(), 2.0);
    }
}
