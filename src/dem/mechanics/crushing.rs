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
//! normal direction. With `k = Ē t_z/ℓ_c`, the overlap area `S_r`, the chord (contact width) `L`,
//! `k_n = k L`, the plastic overlap area `A_p` and the accumulated plastic penetration `κ`
//! (history):
//!
//! ```text
//!   F_n      = k (S_r − A_p) ≥ 0                      (for a flat contact S_r = L δ: k_n (δ − A_p/L))
//!   F_y(κ)   = σ_c L t_z (1 − κ/δ_u)₊ ,  δ_u = 2 G_c/σ_c ,   dκ = dA_p/L
//! ```
//!
//! so the contact pressure `F_n/(L t_z)` never exceeds `σ_c`, and the area under the softening
//! branch, per unit contact area, is the crushing fracture energy `G_c` (J/m²). Return map
//! (backward Euler from the committed `A_p`, `κ`): trial `F_tr = k (S_r − A_p,old)`; if
//! `F_tr ≤ F_y(κ_old)` the step is elastic, otherwise, with the softening stiffness
//! `H = σ_c L t_z/δ_u`,
//!
//! ```text
//!   Δκ = (F_tr − F_y(κ_old)) / (k_n − H) ,   A_p = A_p,old + L Δκ ,   F_n = F_y(κ_old + Δκ) = F_tr − k_n Δκ
//! ```
//!
//! and past `δ_u` the contact carries nothing (`F_n = 0`, `A_p = S_r`). `k_n > H`, i.e.
//! `δ_u > σ_c ℓ_c/Ē` (the plastic penetration at full crushing exceeds the elastic one at the
//! peak), is required, otherwise a single contact snaps back; it is checked at every contact.
//! The dissipated energy of a step is the area under the (linear) yield line,
//! `½ (F_y(κ_old) + F_y(κ_new)) Δκ`; the elastic energy stays `F_n²/(2 k_n)`.
//!
//! **Why the plastic state is an area.** The normal force acts through the gradient of the
//! overlap area (`dS_r = L dδ` for an approach `dδ`), so the work of a step is `F_n dS_r/L`. With
//! the stored energy `U = k S_e²/(2L)`, `S_e = S_r − A_p`, and the dissipation `F_n dA_p/L`:
//!
//! ```text
//!   F_n dS_r/L − dU − F_n dA_p/L = F_n δ_e dL/(2L) ,   δ_e = S_e/L
//! ```
//!
//! the same unbooked term as an elastic contact whose width changes (the elastic law of SPEC
//! eq. 3 is not a potential one when `L` varies). A plastic penetration `δ_p` as the history,
//! `F_n = k (S_r − L δ_p)`, leaves `F_n (δ_e + 2δ_p) dL/(2L)`, which grows with the crushing.
//! Measured on the 16 samples of `jobs/wall-compression.toml` to ε = 3e-3: the energy balance
//! at the end within 0.33–1.07 % of the work with the area, 0.41–1.77 % with `δ_p`.
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

    /// The yield force `F_y = σ_c L t_z (1 − κ/δ_u)₊` of a contact of width `width` (m) at the
    /// accumulated plastic penetration `kappa`.
    pub fn yield_force(&self, width: f64, t_z: f64, kappa: f64) -> f64 {
        self.stress * width * t_z * (1.0 - kappa / self.ultimate_penetration()).max(0.0)
    }

    /// The normal return map (see the module docs) for the overlap area `s_r`, the contact width
    /// `width`, the lattice modulus `e_bar`, the contact length `l_c`, the thickness `t_z`
    /// (`k = Ē t_z/ℓ_c`), and the committed plastic state `old`.
    /// Errors: a snap-back at the contact (`k L ≤ H`, i.e. `δ_u ≤ σ_c ℓ_c/Ē`).
    pub fn update(
        &self,
        s_r: f64,
        width: f64,
        e_bar: f64,
        l_c: f64,
        t_z: f64,
        old: PlasticState,
    ) -> Result<CrushUpdate, MechanicsError> {
        let k = e_bar * t_z / l_c;
        let k_n = k * width;
        let trial = k * (s_r - old.area);
        let elastic = CrushUpdate { f_n: trial.max(0.0), state: old, dissipation: 0.0, plastic: false };
        if trial <= 0.0 || width <= 0.0 {
            return Ok(elastic);
        }
        let f_y0 = self.yield_force(width, t_z, old.kappa);
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
        let dk = (trial - f_y0) / (k_n - h);
        if old.kappa < d_u && old.kappa + dk < d_u {
            let f_n = trial - k_n * dk;
            let f_y1 = self.yield_force(width, t_z, old.kappa + dk);
            let state = PlasticState { area: old.area + width * dk, kappa: old.kappa + dk };
            return Ok(CrushUpdate { f_n, state, dissipation: 0.5 * (f_y0 + f_y1) * dk, plastic: true });
        }
        // Fully crushed: nothing carried, every further penetration plastic.
        let state = PlasticState { area: s_r, kappa: old.kappa + (s_r - old.area) / width };
        let dissipation = 0.5 * f_y0 * (d_u - old.kappa).max(0.0);
        Ok(CrushUpdate { f_n: 0.0, state, dissipation, plastic: true })
    }
}

/// The plastic state of a crushing contact (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlasticState {
    /// Plastic overlap area `A_p` (m²): the part of the overlap that carries no force.
    pub area: f64,
    /// Accumulated plastic penetration `κ = ∫ dA_p/L` (m): drives the softening.
    pub kappa: f64,
}

/// The result of one contact crushing update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrushUpdate {
    /// Normal force `F_n` (N, ≥ 0).
    pub f_n: f64,
    /// New plastic state.
    pub state: PlasticState,
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
        let (mut st, mut diss) = (PlasticState::default(), 0.0);
        for s in 1..=200 {
            let d = 1e-5 * s as f64;
            let u = C.update(l * d, l, e, lc, tz, st).unwrap();
            st = u.state;
            let dp = st.kappa;
            assert!((st.area - l * dp).abs() <= 1e-15, "flat contact: A_p = L κ");
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
        let mut st = PlasticState::default();
        for d in [4e-4, 5e-4] {
            st = C.update(l * d, l, e, lc, tz, st).unwrap().state;
        }
        let u = C.update(l * 4.9e-4, l, e, lc, tz, st).unwrap();
        assert!(!u.plastic && (u.f_n - kn * (4.9e-4 - st.kappa)).abs() < 1e-9 * 5e5);
        // Snap-back at the contact is an error: δ_u ≤ σ_c ℓ_c/Ē.
        let brittle = Crushing { stress: 5e6, energy: 50.0 };
        assert!(brittle.update(l * 5e-4, l, e, lc, tz, PlasticState::default()).is_err());
    }

    #[test]
    fn widening_contact_books_only_the_elastic_width_term() {
        // A contact crushed while its chord widens, L: 0.05 → 0.15 m, overlap S_r = L δ with the
        // penetration δ: 0 → 5e-4 m (into the softening branch, δ_u = 8e-4 m), in 20,000 steps.
        // The force works through the area gradient, dW = F dS_r/L (midpoint values). The
        // module docs' identity: W − ΔU − D = ∫ F δ_e dL/(2L), δ_e = (S_r − A_p)/L, the term an
        // elastic contact leaves too. Tolerance: 1 % of that term (the midpoint rule's error
        // over 20,000 steps is far below); the δ_p law's extra ∫ F δ_p dL/L is 21 % of it on
        // this path, so the test tells the two laws apart.
        let (e, lc, tz) = (2.5e9, 0.2, 1.0);
        let n = 20_000;
        let path = |t: f64| {
            let l = 0.05 + 0.1 * t;
            (l * 5e-4 * t, l)
        };
        let (mut st, mut diss, mut work, mut term) = (PlasticState::default(), 0.0, 0.0, 0.0);
        let (mut f0, mut u0) = (0.0, 0.0);
        let (mut s0, mut l0) = path(0.0);
        for k in 1..=n {
            let (s1, l1) = path(k as f64 / n as f64);
            let u = C.update(s1, l1, e, lc, tz, st).unwrap();
            let (fm, lm) = (0.5 * (f0 + u.f_n), 0.5 * (l0 + l1));
            work += fm * (s1 - s0) / lm;
            diss += u.dissipation;
            let de = 0.5 * ((s0 - st.area) / l0 + (s1 - u.state.area) / l1);
            term += fm * de * (l1 - l0) / (2.0 * lm);
            st = u.state;
            f0 = u.f_n;
            u0 = 0.5 * u.f_n * u.f_n / (e * tz / lc * l1);
            s0 = s1;
            l0 = l1;
        }
        assert!(st.kappa > 1e-4 && st.kappa < 8e-4, "on the softening branch: κ = {}", st.kappa);
        let imbalance = work - u0 - diss;
        assert!(term > 0.0 && (imbalance - term).abs() <= 1e-2 * term, "W − ΔU − D = {imbalance:e}, ∫F δ_e dL/2L = {term:e}");
    }
}
