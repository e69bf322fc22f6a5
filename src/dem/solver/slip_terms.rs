//! How much of a contact's tangential stiffness the factorized operator `M` holds, stick or slip,
//! and when a stick/slip flip reaches it ([`super::operator`], the preconditioner of
//! [`super::gmres`]).
//!
//! ```text
//!   M = K_beams + Σ_contacts (k_n b bᵀ + s_c k_t c cᵀ) + diag(ε)
//!   s_c = 1 while the held regime of contact c is stick,   s_c = s (the share) while it is slip
//! ```
//!
//! A sticking contact's tangent has `k_t c cᵀ` along its chord; a sliding one's has none (its
//! tangential force is `μ F_n` with the sign of the slip, so `∂F_t = μ sign(F_t) ∂F_n`: the slip
//! coupling, [`super::tangent`]). With `s = 1` every contact holds `k_t c cᵀ` whatever its
//! regime, so a flip never touches the factor and GMRES absorbs the difference
//! `D = K_T − M`: for a sliding contact a stiffness `k_t` along a direction where the tangent has
//! none. `A M⁻¹ = I + D M⁻¹` then has one eigenvalue per sliding contact far from 1, and GMRES's
//! iterations per Newton step grow with the sliding contacts.
//!
//! With `s < 1` the held regime follows the contact's. With CHOLMOD's updates in place a flip
//! scales the held term `t = k_t c₀ c₀ᵀ` (`c₀` the direction it entered with): stick → slip
//! is the downdate `−(1 − s) t`, slip → stick the update `(1/s − 1) t`, one rank-one column
//! each; the flips of a Newton iteration go into the factor as one multiple-rank
//! `cholmod_updown` per sign ([`super::cholmod`], passes of up to 8 columns), before the
//! iteration's other contact changes. On the Woodbury path a flip takes the held term out and
//! puts the new one in at the contact's current direction; with `s = 0` a sliding contact holds
//! no tangential term, so a flip takes it out or puts it in. A contact on the
//! Coulomb cone (it slid at the committed state and has not moved since) counts as sliding, as
//! its tangent does ([`super::tangent`], "On the cone"): counted as sticking, a contact that
//! keeps sliding flips to stick at the first Newton iteration of each equilibrium and back at
//! the second (on the 1k sample with `s = 0`, lag 0: 58,106 flips against 27,251).
//!
//! The share `s` keeps a stone held only by sliding contacts (no intact beam left) stiff along
//! the chords of its contacts in `M`: the regularization `ε` alone (10⁻¹⁰ of the stone's
//! diagonal with every beam intact, [`super::scales`]) is about ten orders of magnitude below
//! `k_t`, so with `s = 0` such a stone's block of `M` is nearly singular along its slip
//! directions.
//!
//! **Lag.** Near the Coulomb cone a contact may flip back and forth from one Newton iteration to
//! the next (chatter, [`super::equilibrium`], "Where the tolerance meets the stones' chatter").
//! A flip reaches `M` only once the contact has shown its new regime at `lag + 1` consecutive
//! Newton iterations (`lag = 0`: at once); a flip that turns back before then costs the factor
//! nothing. A contact that enters `M` enters in its current regime.
//!
//! The preconditioner changes GMRES's path only: with every linear solve converged to its
//! tolerance, the equilibria are the same within the Newton tolerance whatever `s` and `lag`.
//!
//! **Measured: why [`SlipTerms::FULL`] stays the default** (`examples/dem_profile.rs`, random
//! samples in compression to 2e-3, 2-core AMD EPYC shared with other jobs, load 4–8; the counts
//! do not depend on the load, the seconds do; docs/benchmarks.md, "DEM"). On the 1k sample
//! (689 breaks, the same breaks in the same order in every setting, the stresses at the regular
//! load points within 4·10⁻⁹ of the peak of the stored reference):
//!
//! | `share:lag` | Newton | GMRES per step | flips in / turned back | CPU s (3 paired runs) |
//! |---|---|---|---|---|
//! | `FULL` | 3,559 | 4.60 | 0 / 0 | 7.0, 7.9, 7.2 |
//! | `0.01:0` | 3,579 | 3.60 | 27,240 / 0 | 8.0, 8.9, 8.5 |
//! | `0.01:2` | 3,625 | 3.91 | 15,095 / 6,260 | |
//! | `0:0` | 3,517 | 3.13 | 27,251 / 0 | 8.1, 8.4, 8.7 |
//!
//! On the 10k sample, to 5,779 breaks (strain 0.85e-3, the late phase where sliding contacts
//! multiply; the same number of breaks at every one of the 281 progress states compared), with
//! `0.01:0` against `FULL`:
//!
//! | breaks | GMRES per Newton step | Newton per break | flips per Newton iteration |
//! |---|---|---|---|
//! | 0–1,000 | 1.75 → 1.52 | 3.20 → 3.06 | 44 |
//! | 3,000–4,000 | 4.69 → 3.54 | 3.93 → 4.03 | 33 |
//! | 4,000–5,000 | 6.70 → 4.86 | 4.73 → 4.77 | 46 |
//! | 5,000–5,500 | 9.15 → 6.78 | 4.70 → 4.73 | 36 |
//! | 0–5,779 | 5.05 → 3.84 | 3.95 → 3.97 | 38 |
//!
//! A flip costs about 1 ms (a rank-one `cholmod_updown` over 29k unknowns, 6–7 % of a
//! preconditioner solve measured in the same stretch), so to 5,779 breaks the factor updates
//! took 1,036 s against 59 s, the preconditioner solves 1,540 s against 2,004 s (wall seconds,
//! load 4–8): 1,308 CPU-s for the whole run (to 5,798 breaks) against 1,082 (to 5,779). Per
//! Newton step the solves saved pay for the flips only from about 5,000 breaks on (5,000–5,500:
//! 2.4 solves saved against 2.2 solves' worth of updates; 4,000–5,000: 1.8 against 3.3).
//! The lag keeps most of the gain for a fraction of the flips. The first 1,000 breaks of the
//! 10k sample, run one after the other at load 1.8–2.9:
//!
//! | `share:lag` | CPU s | GMRES per step | flips in / turned back | factor updates, s |
//! |---|---|---|---|---|
//! | `FULL` | 72.0 | 1.75 | 0 / 0 | 3.1 |
//! | `0.01:0` | 122.5 | 1.52 | 135,429 / 0 | 59.9 |
//! | `0.01:2` | 75.9 | 1.56 | 34,443 / 50,575 | 18.3 |
//!
//! Over 5,329 breaks of the same sample with `0.01:2` (the same breaks as `FULL` at all 274
//! progress states compared): GMRES per Newton step 1.56, 2.53, 3.27, 3.95, 5.37 per thousand
//! breaks (`FULL`: 1.75, 2.73, 3.64, 4.69, 6.70), 11–25 flips per Newton iteration, but 3–5 %
//! more Newton iterations from 2,000 breaks on (4.13 against 3.93 per break from 3,000 to
//! 4,000, 4.91 against 4.73 from 4,000 to 5,000). From 4,000 to 5,000 breaks it took 250 s;
//! `FULL`'s counts priced at this run's own cost of a solve (5.35 ms) and of its other phases
//! come to about 234 s (an estimate: `FULL`'s own run was measured at another load). Near the
//! peak (GMRES 9–12 per step with `FULL`) a lagged setting may pay; that is not measured.
//!
//! The GMRES iterations that grow with the sliding contacts are mostly not the held `k_t`: with
//! none held for sliding contacts (`0:0`, 1k sample), a Newton step with 128–255 sliding
//! contacts still takes 4.7 GMRES iterations against 1.1 with none (7.5 with `FULL`): the rest
//! of `D` (the slip coupling, the turning of the normal, the area gradient) grows with the
//! contacts as well.
use std::collections::BTreeMap;

/// The tangential terms of the preconditioner: the share of `k_t c cᵀ` a sliding contact keeps
/// and the lag of flips (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlipTerms {
    /// `s ∈ [0, 1]`: the share of `k_t` a contact whose held regime is slip keeps in `M`
    /// (1: every contact keeps `k_t c cᵀ`, stick or slip; 0: sliding contacts keep none).
    pub share: f64,
    /// Consecutive Newton iterations a contact shows its new regime before the flip reaches `M`,
    /// after the first (0: at once). Irrelevant when `share` is 1.
    pub lag: usize,
}

impl SlipTerms {
    /// Every contact keeps `k_t c cᵀ`, stick or slip: flips never touch the factor.
    pub const FULL: SlipTerms = SlipTerms { share: 1.0, lag: 0 };
    /// Only sticking contacts hold `k_t c cᵀ`, and every flip reaches `M` at once.
    pub const STICK_ONLY: SlipTerms = SlipTerms { share: 0.0, lag: 0 };

    /// Whether the held terms follow the contacts' regimes (`share < 1`).
    pub fn follows_regime(&self) -> bool {
        self.share < 1.0
    }

    /// The tangential stiffness a contact of tangential stiffness `k_t` holds in `M` while its
    /// held regime is stick or slip.
    pub fn held_stiffness(&self, k_t: f64, sticks: bool) -> f64 {
        if sticks || !self.follows_regime() {
            k_t
        } else {
            self.share * k_t
        }
    }

    /// Whether `share` lies in `[0, 1]`.
    pub fn is_valid(&self) -> bool {
        (0.0..=1.0).contains(&self.share)
    }
}

impl Default for SlipTerms {
    fn default() -> Self {
        SlipTerms::FULL
    }
}

/// What the operator's sync does with a contact's tangential term.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Held {
    /// Hold the term in this regime (`true`: stick); it is the regime already held.
    Keep(bool),
    /// The contact is new to `M`, or its held regime flips to this one: the term (re)enters.
    Enter(bool),
}

/// The regime each contact's tangential term holds in `M` and how long the contact has shown
/// the other one (module docs, "Lag").
#[derive(Clone, Debug, Default)]
pub(super) struct HeldRegimes {
    /// By pair: the held regime (`true`: stick) and the consecutive Newton iterations the
    /// contact has shown the other one.
    pairs: BTreeMap<(usize, usize), (bool, usize)>,
    /// Flips that reached `M`, and flips that turned back before the lag was over.
    pub flips: [usize; 2],
}

impl HeldRegimes {
    /// The contact `(i, j)`, now sticking or not, at a Newton iteration: which regime its term
    /// holds after it.
    pub fn observe(&mut self, pair: (usize, usize), sticks: bool, lag: usize) -> Held {
        let Some((held, waited)) = self.pairs.get_mut(&pair) else {
            self.pairs.insert(pair, (sticks, 0));
            return Held::Enter(sticks);
        };
        if *held == sticks {
            if *waited > 0 {
                self.flips[1] += 1;
            }
            *waited = 0;
            return Held::Keep(sticks);
        }
        *waited += 1;
        if *waited > lag {
            (*held, *waited) = (sticks, 0);
            self.flips[0] += 1;
            Held::Enter(sticks)
        } else {
            Held::Keep(*held)
        }
    }

    /// Forgets the pairs for which `live` is false (contacts that left `M`).
    pub fn retain(&mut self, mut live: impl FnMut(&(usize, usize)) -> bool) {
        self.pairs.retain(|k, _| live(k));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flip_reaches_the_operator_after_the_lag_and_chatter_never() {
        // lag 2: a contact entering sliding enters so; it sticks at iterations 1, 2 (waiting)
        // and 3 (the flip enters); then chatters slip/stick (every flip turns back: none
        // enters, each counted as absorbed).
        let mut h = HeldRegimes::default();
        let p = (3, 8);
        assert_eq!(h.observe(p, false, 2), Held::Enter(false));
        assert_eq!(h.observe(p, true, 2), Held::Keep(false));
        assert_eq!(h.observe(p, true, 2), Held::Keep(false));
        assert_eq!(h.observe(p, true, 2), Held::Enter(true));
        for _ in 0..3 {
            assert_eq!(h.observe(p, false, 2), Held::Keep(true));
            assert_eq!(h.observe(p, true, 2), Held::Keep(true));
        }
        assert_eq!(h.flips, [1, 3]);
        // lag 0: every flip at once.
        assert_eq!(h.observe(p, false, 0), Held::Enter(false));
        h.retain(|_| false);
        assert_eq!(h.observe(p, true, 0), Held::Enter(true));
    }

    #[test]
    fn the_share_scales_sliding_contacts_only() {
        let s = SlipTerms { share: 1e-2, lag: 1 };
        assert_eq!(s.held_stiffness(5.0, true), 5.0);
        assert_eq!(s.held_stiffness(5.0, false), 5e-2);
        assert_eq!(SlipTerms::FULL.held_stiffness(5.0, false), 5.0);
        assert_eq!(SlipTerms::STICK_ONLY.held_stiffness(5.0, false), 0.0);
        assert!(!SlipTerms { share: 1.5, lag: 0 }.is_valid());
    }
}
