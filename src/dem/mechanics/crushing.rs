//! Crushing: an optional compressive failure of the lattice (an extension of SPEC §1, off unless
//! `[mechanics] crushing_stress` is set).
//!
//! SPEC §1's model has no compressive failure: the failure index (eq. 2) only falls under
//! compression and the contact penalty (eq. 3) carries any pressure, so a wall of stacked rigid
//! stones never reaches a compressive peak. As in lattice and DEM models of quasi-brittle
//! materials with a compressive cut-off (e.g. Schlangen & van Mier's lattice with a compressive
//! strength, or the bonded-particle and rigid-block models whose joints have a compressive cap
//! with softening, Lourenço & Rots' interface "cap"), two mechanisms share one crushing stress
//! `σ_c` (Pa):
//!
//! **Beams.** A beam crushes (breaks, failure mode "crushing") when its mean compressive stress
//! reaches `σ_c`:
//!
//! ```text
//!   P_c = −F_N/(A σ_c) = −Ē ε/σ_c ≥ 1 ,   ε = δn/ℓ
//! ```
//!
//! `ε` is linear in the particle DOFs, so along an increment `ε(λ) = ε₀ + λΔε` the crossing is
//! `λ = (−σ_c/Ē − ε₀)/Δε` (closed form, as the solver's event scheme needs).
//!
//! **Contacts.** The contact of SPEC eq. 3 becomes elastic–plastic with linear softening in the
//! normal direction. With `k = Ē t_z/ℓ_c`, the chord (contact width) `L`, `k_n = k L` and the
//! plastic penetration `δ_p` (history, m):
//!
//! ```text
//!   F_n     = k (S_r − L δ_p) ≥ 0                       (for a flat contact S_r = L δ: k_n (δ − δ_p))
//!   F_y(δ_p) = σ_c L t_z (1 − δ_p/δ_u)₊ ,  δ_u = 2 G_c/σ_c
//! ```
//!
//! so the contact pressure `F_n/(L t_z)` never exceeds `σ_c`, and the area under the softening
//! branch, per unit contact area, is the crushing fracture energy `G_c` (J/m²). Return map
//! (backward Euler from the committed `δ_p`): trial `F_tr = k (S_r − L δ_p,old)`; if
//! `F_tr ≤ F_y(δ_p,old)` the step is elastic, otherwise, with the softening stiffness
//! `H = σ_c L t_z/δ_u`,
//!
//! ```text
//!   Δδ_p = (F_tr − F_y(δ_p,old)) / (k_n − H) ,   F_n = F_y(δ_p,old + Δδ_p) = F_tr − k_n Δδ_p
//! ```
//!
//! and past `δ_u` the contact carries nothing (`F_n = 0`, `δ_p = S_r/L`). `k_n > H`, i.e.
//! `δ_u > σ_c ℓ_c/Ē` (the plastic penetration at full crushing exceeds the elastic one at the
//! peak), is required, otherwise a single contact snaps back; it is checked at every contact.
//! The dissipated energy of a step is the area under the (linear) yield line,
//! `½ (F_y(δ_p,old) + F_y(δ_p,new)) Δδ_p` (exact for a constant width); the elastic energy stays
//! `F_n²/(2 k_n)`.
//!
//! A beam that crushes leaves its pair to this contact law: the stones then overlap by about the
//! beam's shortening, so the contact starts at (about) the yield force and the pair softens on
//! further compression: this is what gives the wall a compressive peak and a brittle post-peak.

use super::error::{positive, MechanicsError};

/// The crushing parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crushing {
    /// Crushing stress `σ_c` (Pa).
    pub stress: f64,
    /// Crushing fracture energy `G_c` (J/m² of contact area), the area under the softening line.
    pub energy: f64,
}

impl Crushing {
    /// Checks both values (finite, > 0).
    pub fn validate(&self) -> Result<(), MechanicsError> {
        positive("crushing_stress", self.stress)?;
        positive("crushing_energy", self.energy)?;
        Ok(())
    }

    /// `δ_u = 2 G_c/σ_c` (m): the plastic penetration at which a contact carries nothing.
    pub fn ultimate_penetration(&self) -> f64 {
        2.0 * self.energy / self.stress
    }

    /// The beam crushing index `P_c = −Ē ε/σ_c` (crushes at `P_c ≥ 1`).
    pub fn beam_index(&self, e_bar: f64, eps: f64) -> f64 {
        -e_bar * eps / self.stress
    }

    /// The smallest `λ ∈ [0, 1]` with `P_c(ε₀ + λΔε) = 1`, or `None` if the beam does not crush
    /// on `[0, 1]`; `Some(0.0)` if it is already at or past crushing.
    pub fn beam_lambda(&self, e_bar: f64, eps0: f64, deps: f64) -> Option<f64> {
        let eps_c = -self.stress / e_bar;
        if eps0 <= eps_c {
            return Some(0.0);
        }
        if deps < 0.0 && eps0 + deps <= eps_c {
            return Some(((eps_c - eps0) / deps).clamp(0.0, 1.0));
        }
        None
    }

    /// The yield force `F_y = σ_c L t_z (1 − δ_p/δ_u)₊` of a contact of width `width` (m).
    pub fn yield_force(&self, width: f64, t_z: f64, delta_p: f64) -> f64 {
        self.stress * width * t_z * (1.0 - delta_p / self.ultimate_penetration()).max(0.0)
    }

    /// The normal return map (see the module docs) for the overlap area `s_r`, the contact width
    /// `width`, the lattice modulus `e_bar`, the contact length `l_c`, the thickness `t_z`
    /// (`k = Ē t_z/ℓ_c`), and the committed plastic penetration `delta_p_old`.
    /// Errors: a snap-back at the contact (`k L ≤ H`, i.e. `δ_u ≤ σ_c ℓ_c/Ē`).
    pub fn update(
        &self,
        s_r: f64,
        width: f64,
        e_bar: f64,
        l_c: f64,
        t_z: f64,
        delta_p_old: f64,
    ) -> Result<CrushUpdate, MechanicsError> {
        let k = e_bar * t_z / l_c;
        let k_n = k * width;
        let trial = k * (s_r - width * delta_p_old);
        let elastic = CrushUpdate { f_n: trial.max(0.0), delta_p: delta_p_old, dissipation: 0.0, plastic: false };
        if trial <= 0.0 || width <= 0.0 {
            return Ok(elastic);
        }
        let f_y0 = self.yield_force(width, t_z, delta_p_old);
        if trial <= f_y0 {
            return Ok(elastic);
        }
        let d_u = self.ultimate_penetration();
        let h = self.stress * width * t_z / d_u;
        if k_n <= h {
            // k L ≤ σ_c L t_z/δ_u  ⇔  G_c ≤ σ_c² t_z/(2k) = σ_c² ℓ_c/(2 Ē).
            return Err(MechanicsError::CrushingSnapBack {
                energy: self.energy,
                l_c,
                minimum: self.stress * self.stress * l_c / (2.0 * e_bar),
            });
        }
        let dd = (trial - f_y0) / (k_n - h);
        if delta_p_old < d_u && delta_p_old + dd < d_u {
            let f_n = trial - k_n * dd;
            let f_y1 = self.yield_force(width, t_z, delta_p_old + dd);
            return Ok(CrushUpdate { f_n, delta_p: delta_p_old + dd, dissipation: 0.5 * (f_y0 + f_y1) * dd, plastic: true });
        }
        // Fully crushed: nothing carried, every further penetration plastic.
        let delta_p = s_r / width;
        let dissipation = 0.5 * f_y0 * (d_u - delta_p_old).max(0.0);
        Ok(CrushUpdate { f_n: 0.0, delta_p, dissipation, plastic: true })
    }
}

/// The result of one contact crushing update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrushUpdate {
    /// Normal force `F_n` (N, ≥ 0).
    pub f_n: f64,
    /// New plastic penetration `δ_p` (m).
    pub delta_p: f64,
    /// Energy dissipated by the step (J).
    pub dissipation: f64,
    /// Whether the step was plastic.
    pub plastic: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: Crushing = Crushing { stress: 5e6, energy: 2e3 };

    #[test]
    fn beam_crossing_by_hand() {
        // Ē = 2.5e9, σ_c = 5e6 → ε_c = −2e-3. ε₀ = −1e-3, Δε = −4e-3 → λ = 0.25 (exact to 1e-15).
        let l = C.beam_lambda(2.5e9, -1e-3, -4e-3).unwrap();
        assert!((l - 0.25).abs() < 1e-15);
        assert!((C.beam_index(2.5e9, -1e-3 - 0.25 * 4e-3) - 1.0).abs() < 1e-12);
        assert_eq!(C.beam_lambda(2.5e9, -1e-3, -0.5e-3), None);
        assert_eq!(C.beam_lambda(2.5e9, -1e-3, 4e-3), None);
        assert_eq!(C.beam_lambda(2.5e9, -3e-3, 1e-3), Some(0.0));
    }

    #[test]
    fn flat_contact_plateau_softening_and_energy() {
        // Flat contact: width L = 0.1 m, t_z = 1, ℓ_c = 0.2 m, Ē = 2.5e9 → k = 1.25e10 N/m²,
        // k_n = 1.25e9 N/m. σ_c L t_z = 5e5 N reached at δ = 4e-4 m. δ_u = 2 G_c/σ_c = 8e-4 m,
        // H = 5e5/8e-4 = 6.25e8 N/m. Penetration δ → S_r = L δ. Closed forms (tolerance 1e-9
        // relative): F = k_n δ up to 4e-4; then F = 5e5 (1 − δ_p/δ_u) with
        // δ_p = (k_n δ − 5e5)/(k_n − H); zero once δ_p ≥ δ_u, i.e. δ ≥ δ_u (F = 0 there);
        // dissipated = ∫ F_y dδ_p = 5e5 (δ_p − δ_p²/(2 δ_u)); total G_c L t_z = 200 J.
        let (l, e, lc, tz) = (0.1, 2.5e9, 0.2, 1.0);
        let (kn, h, du) = (1.25e9, 6.25e8, 8e-4);
        let (mut dp, mut diss) = (0.0, 0.0);
        for s in 1..=200 {
            let d = 1e-5 * s as f64;
            let u = C.update(l * d, l, e, lc, tz, dp).unwrap();
            dp = u.delta_p;
            diss += u.dissipation;
            let want_dp = ((kn * d - 5e5) / (kn - h)).max(0.0);
            if d <= 4e-4 {
                assert!((u.f_n - kn * d).abs() <= 1e-9 * kn * d, "δ = {d}: {}", u.f_n);
                assert!(dp <= 1e-15, "no plastic penetration below the yield (round-off at δ = 4e-4): {dp}");
            } else if want_dp < du {
                let f = 5e5 * (1.0 - want_dp / du);
                assert!((u.f_n - f).abs() <= 1e-9 * 5e5, "δ = {d}: {} vs {f}", u.f_n);
                assert!((dp - want_dp).abs() <= 1e-12);
                let w = 5e5 * (dp - dp * dp / (2.0 * du));
                assert!((diss - w).abs() <= 1e-9 * 200.0, "δ = {d}: {diss} vs {w}");
            } else {
                assert_eq!(u.f_n, 0.0);
            }
            assert!(u.f_n <= 5e5 * (1.0 + 1e-12), "the pressure never exceeds σ_c");
        }
        assert!((diss - 200.0).abs() < 1e-9 * 200.0, "G_c L t_z = 200 J: {diss}");
        // Unloading is elastic from the plastic penetration: back by 1e-5 from δ = 5e-4.
        let mut dp = 0.0;
        for d in [4e-4, 5e-4] {
            dp = C.update(l * d, l, e, lc, tz, dp).unwrap().delta_p;
        }
        let u = C.update(l * 4.9e-4, l, e, lc, tz, dp).unwrap();
        assert!(!u.plastic && (u.f_n - kn * (4.9e-4 - dp)).abs() < 1e-9 * 5e5);
        // Snap-back at the contact is an error: δ_u ≤ σ_c ℓ_c/Ē.
        let brittle = Crushing { stress: 5e6, energy: 50.0 };
        assert!(brittle.update(l * 5e-4, l, e, lc, tz, 0.0).is_err());
    }
}
