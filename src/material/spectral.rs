//! The spectral strain split ([`Split::Spectral`](super::Split)): stress, tangents, and the energies
//! released by damage, in 3D, plane stress and uniaxial stress.
//!
//! # The potential and its derivatives
//! With the integrities a_t = 1 − d_t, a_c = 1 − d_c and A(x) = a_t for x ≥ 0, a_c for x < 0:
//!
//! ```text
//!   ψ  = λ/2 A(tr ε) (tr ε)² + μ Σ_i A(ε_i) ε_i²        = a_t ψ₀⁺ + a_c ψ₀⁻
//!   σ  = λ A(tr ε) tr ε 1 + 2μ Σ_i A(ε_i) ε_i P_i           P_i = n_i ⊗ n_i
//!   D  = ∂σ/∂ε at fixed damage
//!      = λ A(tr ε) 1 ⊗ 1 + 2μ [ Σ_i A(ε_i) P_i ⊗ P_i + Σ_{i<j} s_ij G_ij ⊗ G_ij ]
//!   s_ij = (A(ε_i) ε_i − A(ε_j) ε_j) / (ε_i − ε_j)   (A(ε_i) when both lie on one side)
//!   G_ij = (n_i ⊗ n_j + n_j ⊗ n_i) / √2
//! ```
//! P_i and G_ij are an orthonormal basis of the symmetric tensors, so D is the derivative of the
//! isotropic tensor function Σ f(ε_i) P_i with f(x) = A(x) x (the divided differences s_ij on the
//! off-diagonal principal components; Miehe, CMAME 155, 1998, for the general form). ψ₀± and
//! S± = ∂ψ₀±/∂ε are the same expressions with (a_t, a_c) = (1, 0) and (0, 1). σ is homogeneous of
//! degree 1 in ε at fixed damage, so D ε = σ: D is the secant.
//!
//! In Voigt form (engineering shear strains in, tensor shear stresses out) a basis tensor B enters as
//! its tensor components b, since B : ε = bᵀ ε_voigt: D = Σ c_k b_k b_kᵀ, symmetric.
//!
//! # Condensed directions (plane stress, uniaxial stress)
//! A principal strain z whose stress must vanish (ε_zz of a layer; the two equal lateral strains of a
//! fiber) solves σ_z(z) = λ A(t) t + 2μ A(z) z = 0, t = t₀ + k z the trace (k = 1 for ε_zz, 2 for
//! the fiber's two laterals). σ_z is continuous, piecewise linear and increasing in z (slope
//! k λ A + 2μ A > 0 for d < 1), with kinks at z = 0 and t = 0: its root is found in closed form
//! ([`condensed_strain`]). Then, with D_zz = ∂σ_z/∂z = k λ A(t) + 2μ A(z) and the coupling
//! ∂σ/∂z = k λ A(t) 1 (∂σ_z/∂ε = λ A(t) 1ᵀ):
//!
//! ```text
//!   D_red = D − (k λ A(t))(λ A(t)) / D_zz 1 ⊗ 1                       (static condensation)
//!   ∂σ/∂a_t = S⁺ − k λ A(t) S_z⁺ / D_zz 1,   S_z⁺ = λ ⟨t⟩₊ + 2μ ⟨z⟩₊   (z follows the damage)
//! ```
//! (the same with S⁻ for a_c). The reduced potential min_z ψ is C¹ and its gradient is σ.
//!
//! # Damage
//! The criteria are the paper's (the driving strains of each kinematics, computed as for the trace
//! split), so d_t, d_c and their slopes come from the same history update. The consistent tangent
//! adds the damage terms: tangent = D_red − T⁺ ⊗ d_t' ∂ε_t/∂ε − T⁻ ⊗ d_c' ∂ε_c/∂ε (while loading),
//! T± = ∂σ/∂a_{t,c}. The energy released by damage is Y_t = ψ₀⁺ and Y_c = ψ₀⁻ at the end of the
//! increment; each side's dissipation is integrated as in `state.rs` (c = Y_k/κ_k²).

use nalgebra::{SMatrix, SVector, Vector3, Vector6};

use super::law::PointLaw;
use super::plane_stress::Blend;
use super::principal::principal_3d;
use super::response::Response;
use super::state::{evolve, DamageState, Evolution, Side};
use super::uniaxial::UniaxialResponse;

/// A(x): the integrity of the tensile side for x ≥ 0 (the convention of [`Side::of_trace`]), of
/// the compressive side otherwise. `a` = [a_t, a_c].
#[inline]
fn weight(a: [f64; 2], x: f64) -> f64 {
    if x >= 0.0 {
        a[0]
    } else {
        a[1]
    }
}

/// The divided difference (f(x) − f(y)) / (x − y) of f(x) = A(x) x; A(x) when x and y lie on one
/// side (no cancellation; f is linear there).
#[inline]
fn divided_difference(a: [f64; 2], x: f64, y: f64) -> f64 {
    if (x >= 0.0) == (y >= 0.0) {
        weight(a, x)
    } else {
        (weight(a, x) * x - weight(a, y) * y) / (x - y)
    }
}

/// The weights of ψ₀⁺ and ψ₀⁻.
const POSITIVE: [f64; 2] = [1.0, 0.0];
const NEGATIVE: [f64; 2] = [0.0, 1.0];

/// The pairs (i, j), i < j, of principal directions.
const PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];

/// Principal values of the strain components a kinematics carries, with the Voigt forms of their
/// eigenprojections P_i and of the shear directions G_ij (tensor shear components).
struct Spectrum<const N: usize> {
    /// Number of principal values in the N components (2 in plane stress, 3 in 3D).
    m: usize,
    values: [f64; 3],
    proj: [SVector<f64, N>; 3],
    /// G_ij in the order of [`PAIRS`] (only the first with m = 2).
    shear: [SVector<f64, N>; 3],
}

impl<const N: usize> Spectrum<N> {
    /// Σ_i A(ε_i) ε_i P_i.
    #[inline]
    fn part(&self, a: [f64; 2]) -> SVector<f64, N> {
        let mut s = SVector::<f64, N>::zeros();
        for i in 0..self.m {
            s += self.proj[i] * (weight(a, self.values[i]) * self.values[i]);
        }
        s
    }

    /// Σ_i A(ε_i) P_i ⊗ P_i + Σ_{i<j} s_ij G_ij ⊗ G_ij (module docs).
    #[inline]
    fn part_derivative(&self, a: [f64; 2]) -> SMatrix<f64, N, N> {
        let mut d = SMatrix::<f64, N, N>::zeros();
        for i in 0..self.m {
            let p = &self.proj[i];
            d += p * p.transpose() * weight(a, self.values[i]);
        }
        let n_pairs = if self.m == 3 { 3 } else { 1 };
        for (k, &(i, j)) in PAIRS.iter().enumerate().take(n_pairs) {
            let g = &self.shear[k];
            d += g * g.transpose() * divided_difference(a, self.values[i], self.values[j]);
        }
        d
    }

    /// μ Σ_i A(ε_i) ε_i² over these principal values.
    #[inline]
    fn shear_energy(&self, a: [f64; 2], mu: f64) -> f64 {
        (0..self.m).map(|i| mu * weight(a, self.values[i]) * self.values[i] * self.values[i]).sum()
    }
}

/// The in-plane spectrum of `[ε_xx, ε_yy, γ_xy]` in closed form: ε₁,₂ = c ± r, with
/// c = (ε_xx + ε_yy)/2, r = sqrt(((ε_xx − ε_yy)/2)² + (γ_xy/2)²), cos 2θ = (ε_xx − ε_yy)/(2r),
/// sin 2θ = γ_xy/(2r); P₁ = ((1 + cos 2θ)/2, (1 − cos 2θ)/2, sin 2θ/2), P₂ = I − P₁,
/// G₁₂ = (−sin 2θ, sin 2θ, cos 2θ)/√2.
#[inline]
fn plane_spectrum(strain: &Vector3<f64>) -> Spectrum<3> {
    let c = 0.5 * (strain[0] + strain[1]);
    let (d, h) = (0.5 * (strain[0] - strain[1]), 0.5 * strain[2]);
    let r = d.hypot(h);
    let (cos, sin) = if r > 0.0 { (d / r, h / r) } else { (1.0, 0.0) };
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    Spectrum {
        m: 2,
        values: [c + r, c - r, 0.0],
        proj: [
            Vector3::new(0.5 * (1.0 + cos), 0.5 * (1.0 - cos), 0.5 * sin),
            Vector3::new(0.5 * (1.0 - cos), 0.5 * (1.0 + cos), -0.5 * sin),
            Vector3::zeros(),
        ],
        shear: [Vector3::new(-sin * s2, sin * s2, cos * s2), Vector3::zeros(), Vector3::zeros()],
    }
}

/// The spectrum of a Voigt strain `[ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy]` (symmetric eigen solver).
#[inline]
fn spectrum_3d(strain: &Vector6<f64>) -> Spectrum<6> {
    let (values, vectors) = principal_3d(strain);
    let n = |i: usize| vectors.column(i).into_owned();
    let proj = |v: Vector3<f64>| Vector6::new(v.x * v.x, v.y * v.y, v.z * v.z, v.y * v.z, v.x * v.z, v.x * v.y);
    let s2 = std::f64::consts::SQRT_2;
    let shear = |u: Vector3<f64>, v: Vector3<f64>| {
        Vector6::new(
            s2 * u.x * v.x,
            s2 * u.y * v.y,
            s2 * u.z * v.z,
            (u.y * v.z + u.z * v.y) / s2,
            (u.x * v.z + u.z * v.x) / s2,
            (u.x * v.y + u.y * v.x) / s2,
        )
    };
    Spectrum {
        m: 3,
        values: [values[0], values[1], values[2]],
        proj: [proj(n(0)), proj(n(1)), proj(n(2))],
        shear: [shear(n(0), n(1)), shear(n(0), n(2)), shear(n(1), n(2))],
    }
}

/// The root z of σ_z(z) = λ A(t₀ + k z)(t₀ + k z) + 2μ A(z) z (module docs): exact on each of
/// the three linear pieces between the kinks z = 0 and z = −t₀/k.
#[inline]
pub(super) fn condensed_strain(lambda: f64, mu: f64, a: [f64; 2], t0: f64, k: f64) -> f64 {
    let g = |z: f64| {
        let t = t0 + k * z;
        lambda * weight(a, t) * t + 2.0 * mu * weight(a, z) * z
    };
    let kink = -t0 / k;
    let (b1, b2) = if kink < 0.0 { (kink, 0.0) } else { (0.0, kink) };
    let (g1, g2) = (g(b1), g(b2));
    // A side with no integrity left (d = 1 to round-off) has a flat piece: every z on it is a
    // root, and the kink is taken.
    if g1 >= 0.0 {
        // Left of both kinks: z < 0 and t < 0, slope (k λ + 2μ) a_c.
        let slope = (k * lambda + 2.0 * mu) * a[1];
        if slope > 0.0 {
            b1 - g1 / slope
        } else {
            b1
        }
    } else if g2 <= 0.0 {
        // Right of both kinks: z ≥ 0 and t ≥ 0, slope (k λ + 2μ) a_t.
        let slope = (k * lambda + 2.0 * mu) * a[0];
        if slope > 0.0 {
            b2 - g2 / slope
        } else {
            b2
        }
    } else {
        b1 - g1 * (b2 - b1) / (g2 - g1)
    }
}

/// λ/2 ⟨t⟩±² on the side `a` selects.
#[inline]
fn volumetric_energy(a: [f64; 2], lambda: f64, t: f64) -> f64 {
    0.5 * lambda * weight(a, t) * t * t
}

/// Both sides' history updates for the driving strains `[ε_t, ε_c]`, with unit energy (the
/// dissipation is linear in Y: it is scaled by ψ₀± once the stress is known).
#[inline]
pub(super) fn evolve_both(law: &PointLaw, driving: [f64; 2], committed: &DamageState) -> (Evolution, Evolution) {
    let t = evolve(law, Side::Tension, driving[0], 1.0, committed);
    let c = evolve(law, Side::Compression, driving[1], 1.0, &t.state);
    (t, c)
}

/// The consistent tangent D_red − T⁺ ⊗ d_t' g_t − T⁻ ⊗ d_c' g_c (module docs), `g` the
/// gradients of the driving strains.
#[inline]
fn with_damage_terms<const N: usize>(
    secant: &SMatrix<f64, N, N>,
    ts: [&SVector<f64, N>; 2],
    evo: [&Evolution; 2],
    g: [SVector<f64, N>; 2],
) -> SMatrix<f64, N, N> {
    let mut tangent = *secant;
    for k in 0..2 {
        if evo[k].loading {
            tangent -= ts[k] * (g[k] * evo[k].dd_deq).transpose();
        }
    }
    tangent
}

/// A plane-stress layer point (module docs) with the kinematics `k` of
/// [`plane_stress::update`](super::plane_stress::update), the driving strains `[ε_t, ε_c]` and the
/// point's own share of them (1 locally; nonlocal averages otherwise).
#[inline]
pub(super) fn plane_stress(
    law: &PointLaw,
    strain: &Vector3<f64>,
    k: &Blend,
    driving: [f64; 2],
    self_share: f64,
    committed: &DamageState,
) -> Response<3> {
    let (t, c) = evolve_both(law, driving, committed);
    let a = [t.integrity, c.integrity];
    let (lambda, mu) = (law.lambda(), law.mu());
    let sp = plane_spectrum(strain);
    let z = condensed_strain(lambda, mu, a, strain[0] + strain[1], 1.0);
    let tr = strain[0] + strain[1] + z;
    let one = Vector3::new(1.0, 1.0, 0.0);
    let ones = one * one.transpose();
    let lam = lambda * weight(a, tr);
    // ∂σ_z/∂ε over D_zz; D_zz = 0 only where both pieces at z have lost all integrity (then λA = 0).
    let d_zz = lam + 2.0 * mu * weight(a, z);
    let cond = if d_zz > 0.0 { lam / d_zz } else { 0.0 };
    let secant = ones * (lam - lam * cond) + sp.part_derivative(a) * (2.0 * mu);
    let stress = one * (lambda * weight(a, tr) * tr) + sp.part(a) * (2.0 * mu);
    let side_stress = |w: [f64; 2]| {
        let s = one * (lambda * weight(w, tr) * tr) + sp.part(w) * (2.0 * mu);
        let s_z = lambda * weight(w, tr) * tr + 2.0 * mu * weight(w, z) * z;
        s - one * (cond * s_z)
    };
    let (t_plus, t_minus) = (side_stress(POSITIVE), side_stress(NEGATIVE));
    let psi = |w: [f64; 2]| volumetric_energy(w, lambda, tr) + sp.shear_energy(w, mu) + mu * weight(w, z) * z * z;
    let g_t = (k.grad * k.w + k.dx * (k.eq * k.dw)) * self_share;
    let g_c = (k.grad * (1.0 - k.w) - k.dx * (k.eq * k.dw)) * self_share;
    Response {
        stress,
        secant,
        tangent: with_damage_terms(&secant, [&t_plus, &t_minus], [&t, &c], [g_t, g_c]),
        state: c.state,
        dissipation: psi(POSITIVE) * t.dissipation + psi(NEGATIVE) * c.dissipation,
        side: k.side,
        loading: t.loading || c.loading,
    }
}

/// A 3D point (Voigt `[xx, yy, zz, yz, xz, xy]`): the equivalent strain `eq` with its gradient
/// drives the side of tr σ̃, as with the paper's split.
#[inline]
pub(super) fn three_d(
    law: &PointLaw,
    strain: &Vector6<f64>,
    side: Side,
    eq: f64,
    grad: &Vector6<f64>,
    committed: &DamageState,
) -> Response<6> {
    let tension = side == Side::Tension;
    let driving = if tension { [eq, 0.0] } else { [0.0, eq] };
    let (t, c) = evolve_both(law, driving, committed);
    let a = [t.integrity, c.integrity];
    let (lambda, mu) = (law.lambda(), law.mu());
    let sp = spectrum_3d(strain);
    let tr = strain[0] + strain[1] + strain[2];
    let one = Vector6::new(1.0, 1.0, 1.0, 0.0, 0.0, 0.0);
    let secant = one * one.transpose() * (lambda * weight(a, tr)) + sp.part_derivative(a) * (2.0 * mu);
    let side_stress = |w: [f64; 2]| one * (lambda * weight(w, tr) * tr) + sp.part(w) * (2.0 * mu);
    let (s_plus, s_minus) = (side_stress(POSITIVE), side_stress(NEGATIVE));
    let psi = |w: [f64; 2]| volumetric_energy(w, lambda, tr) + sp.shear_energy(w, mu);
    let (g_t, g_c) = if tension { (*grad, Vector6::zeros()) } else { (Vector6::zeros(), *grad) };
    Response {
        stress: side_stress(a),
        secant,
        tangent: with_damage_terms(&secant, [&s_plus, &s_minus], [&t, &c], [g_t, g_c]),
        state: c.state,
        dissipation: psi(POSITIVE) * t.dissipation + psi(NEGATIVE) * c.dissipation,
        side,
        loading: t.loading || c.loading,
    }
}

/// A fiber in uniaxial stress at axial strain `strain`: its two lateral principal strains z from
/// σ₂₂ = 0 (k = 2 in the module docs); `eq` = r |ε| with `deq` = dε_eq/dε drives the side of ε.
#[inline]
pub(super) fn uniaxial(
    law: &PointLaw,
    strain: f64,
    side: Side,
    eq: f64,
    deq: f64,
    committed: &DamageState,
) -> UniaxialResponse {
    let tension = side == Side::Tension;
    let driving = if tension { [eq, 0.0] } else { [0.0, eq] };
    let (t, c) = evolve_both(law, driving, committed);
    let a = [t.integrity, c.integrity];
    let (lambda, mu) = (law.lambda(), law.mu());
    let z = condensed_strain(lambda, mu, a, strain, 2.0);
    let tr = strain + 2.0 * z;
    let lam = lambda * weight(a, tr);
    let d_zz = 2.0 * lam + 2.0 * mu * weight(a, z);
    let cond = if d_zz > 0.0 { lam / d_zz } else { 0.0 };
    let secant = lam + 2.0 * mu * weight(a, strain) - 2.0 * lam * cond;
    let axial = |w: [f64; 2]| lambda * weight(w, tr) * tr + 2.0 * mu * weight(w, strain) * strain;
    let side_stress = |w: [f64; 2]| {
        let s_z = lambda * weight(w, tr) * tr + 2.0 * mu * weight(w, z) * z;
        axial(w) - 2.0 * cond * s_z
    };
    let psi = |w: [f64; 2]| {
        volumetric_energy(w, lambda, tr) + mu * (weight(w, strain) * strain * strain + 2.0 * weight(w, z) * z * z)
    };
    let (g_t, g_c) = if tension { (deq, 0.0) } else { (0.0, deq) };
    let mut tangent = secant;
    if t.loading {
        tangent -= side_stress(POSITIVE) * t.dd_deq * g_t;
    }
    if c.loading {
        tangent -= side_stress(NEGATIVE) * c.dd_deq * g_c;
    }
    UniaxialResponse {
        stress: axial(a),
        secant,
        tangent,
        state: c.state,
        dissipation: psi(POSITIVE) * t.dissipation + psi(NEGATIVE) * c.dissipation,
        side,
        loading: t.loading || c.loading,
    }
}

/// The free energy density ψ (J/m³) of the spectral split at a 3D strain and given damages (for
/// checks and post-processing; the updates return its derivatives).
pub fn free_energy_3d(law: &PointLaw, strain: &Vector6<f64>, d_t: f64, d_c: f64) -> f64 {
    let a = [1.0 - d_t, 1.0 - d_c];
    let tr = strain[0] + strain[1] + strain[2];
    volumetric_energy(a, law.lambda(), tr) + spectrum_3d(strain).shear_energy(a, law.mu())
}

#[cfg(test)]
#[path = "spectral_tests.rs"]
mod tests;
