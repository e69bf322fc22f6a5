//! What the step driver needs from a discrete structural model, behind a small trait, so the same
//! algorithm runs on dense matrices (the SDOF/2-DOF unit tests) and on the PETSc-distributed
//! model ([`super::PetscSystem`]).
//!
//! Vectors are the rank's **owned** entries of the global vectors (the whole vector on one
//! rank); [`DynamicSystem::dot`] reduces over ranks. Fixed DOFs stay in the vectors with the
//! value 0 in every residual and every load, so they never move relative to the ground.
use crate::error::{AnalysisError, Error};
use nalgebra::{DMatrix, DVector};

/// A semi-discrete structure `M ü + C u̇ + f_int(u) = f(t)`.
pub trait DynamicSystem {
    /// Owned entries of a vector.
    fn len(&self) -> usize;
    /// True when this rank owns no entry.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Global dot product. Collective.
    fn dot(&self, a: &[f64], b: &[f64]) -> f64;
    /// Several global dot products with one reduction. Collective.
    fn dots(&self, pairs: &[(&[f64], &[f64])]) -> Vec<f64> {
        pairs.iter().map(|(a, b)| self.dot(a, b)).collect()
    }
    /// `y = M x`. Collective.
    fn mass_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error>;
    /// `y = C x`. Collective.
    fn damping_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error>;
    /// `M ι_d` for ground-motion direction `d` (ι_d: unit translation along `d` at free DOFs).
    fn mass_influence(&self, d: usize) -> &[f64];
    /// `ι_d` itself.
    fn influence(&self, d: usize) -> &[f64];
    /// The constant static load (gravity, nodal loads) on the free DOFs.
    fn static_load(&self) -> &[f64];
    /// Internal forces at total displacement `u` from the committed state (elements keep the result
    /// as their trial state), on free DOFs. Collective.
    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), Error>;
    /// Prepares solves with `J = K + c_m M + c_c C`, `K` the tangent at `u` when `tangent_at` is
    /// given (elements evaluated there), else the initial stiffness K₀. An implementation may keep
    /// a previous factorization when `J` cannot have changed. Collective.
    fn prepare(&mut self, tangent_at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), Error>;
    /// `x = J⁻¹ r` with the last prepared `J`. Collective.
    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), Error>;
    /// Whether `f_int(u) = K₀ u` for every `u` (no element has state): one solve with the
    /// Jacobian then ends a step exactly ([`super::linear_step`]).
    fn is_linear(&self) -> bool {
        false
    }
    /// `M x`, `K₀ x` and `C x`, for a linear system. Collective. When `solved` is given, `x` is
    /// the solution of `J x = solved` with the last prepared `J = K₀ + c_m M + c_c C`, and an
    /// implementation may take `K₀ x = solved − c_m M x − c_c C x` from it instead of a product
    /// (with Rayleigh damping, `M x` is then the only product). The default makes the three
    /// products.
    fn products(
        &mut self,
        x: &[f64],
        solved: Option<&[f64]>,
        mx: &mut [f64],
        kx: &mut [f64],
        cx: &mut [f64],
    ) -> Result<(), Error> {
        let _ = solved;
        self.mass_mult(x, mx)?;
        self.internal_force(x, kx)?;
        self.damping_mult(x, cx)
    }
    /// The energy the material law has dissipated up to the committed state, summed over all
    /// elements of all ranks (`Element::dissipated_energy`) [J]; 0 for a linear system. Collective.
    fn dissipated_energy(&self) -> f64 {
        0.0
    }
    /// The largest damage increment of the elements' trial states over their committed ones,
    /// over all elements of all ranks (`Element::damage_increment`); 0 for a system without
    /// damage (the default). Collective: every rank must call it at the same point (the stepper
    /// does after every converged substep while its damage control is on, a decision every rank
    /// takes alike), or the ranks that call it wait for the others forever.
    fn max_damage_increment(&self) -> f64 {
        0.0
    }
    /// IMPL-EX: the size `h` of the (sub)step the next evaluations belong to; every element
    /// extrapolates its damage histories by the ratio of `h` to the last committed step's size
    /// (`Element::set_implex_step`). Nothing for a system without damage (the default).
    fn set_implex_step(&mut self, _h: f64) {}
    /// IMPL-EX: every element's trial state settled at the strains of its last evaluation (the
    /// implicit update its frozen-split evaluations leave for later, `Element::settle_implex`),
    /// before the damage increment is measured. Nothing for a system without damage (the
    /// default).
    fn update_histories(&mut self) {}
    /// IMPL-EX: every element's settled trial states ([`DynamicSystem::update_histories`]) held
    /// as the histories of the step's next evaluations (`Element::hold_implex_histories`);
    /// returns the largest change of a point's held damage on any rank. Nothing for a system
    /// without damage (the default: 0). Collective.
    fn hold_histories(&mut self) -> f64 {
        0.0
    }
    /// Sets the size `h` of the (sub)step about to be solved, for laws whose update depends on
    /// it (viscous damage, `[dynamics] damage_relaxation_time`); nothing by default.
    fn set_step_size(&mut self, _h: f64) {}
    /// Accepts the trial state of every element.
    fn commit(&mut self);
    /// Discards the trial state of every element.
    fn revert(&mut self);
}

/// A dense linear system (`f_int = K u`) for tests and small models.
pub struct DenseSystem {
    /// Mass.
    pub m: DMatrix<f64>,
    /// Damping.
    pub c: DMatrix<f64>,
    /// Stiffness.
    pub k: DMatrix<f64>,
    /// Static load.
    pub f_static: Vec<f64>,
    iota: Vec<Vec<f64>>,
    m_iota: Vec<Vec<f64>>,
    lu: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    /// Factorizations done (to test reuse).
    pub factorizations: usize,
    /// Whether [`DynamicSystem::is_linear`] says so (true; false to run the Newton path).
    pub linear: bool,
    key: Option<(u64, u64)>,
}

impl DenseSystem {
    /// `M`, `C`, `K` and the influence vector of each direction (x, y, z; missing ones are zero).
    pub fn new(m: DMatrix<f64>, c: DMatrix<f64>, k: DMatrix<f64>, iota: Vec<Vec<f64>>) -> DenseSystem {
        let n = m.nrows();
        let mut iota = iota;
        iota.resize(3, vec![0.0; n]);
        let m_iota = iota.iter().map(|i| (&m * DVector::from_column_slice(i)).as_slice().to_vec()).collect();
        DenseSystem {
            m,
            c,
            k,
            f_static: vec![0.0; n],
            iota,
            m_iota,
            lu: None,
            factorizations: 0,
            linear: true,
            key: None,
        }
    }
}

fn mult(a: &DMatrix<f64>, x: &[f64], y: &mut [f64]) {
    let r = a * DVector::from_column_slice(x);
    y.copy_from_slice(r.as_slice());
}

impl DynamicSystem for DenseSystem {
    fn len(&self) -> usize {
        self.m.nrows()
    }
    fn is_linear(&self) -> bool {
        self.linear
    }
    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }
    fn mass_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        mult(&self.m, x, y);
        Ok(())
    }
    fn damping_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        mult(&self.c, x, y);
        Ok(())
    }
    fn mass_influence(&self, d: usize) -> &[f64] {
        &self.m_iota[d]
    }
    fn influence(&self, d: usize) -> &[f64] {
        &self.iota[d]
    }
    fn static_load(&self) -> &[f64] {
        &self.f_static
    }
    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), Error> {
        mult(&self.k, u, f);
        Ok(())
    }
    fn products(
        &mut self,
        x: &[f64],
        solved: Option<&[f64]>,
        mx: &mut [f64],
        kx: &mut [f64],
        cx: &mut [f64],
    ) -> Result<(), Error> {
        mult(&self.m, x, mx);
        mult(&self.c, x, cx);
        match (solved, self.key) {
            (Some(r), Some((c_m, c_c))) => {
                let (c_m, c_c) = (f64::from_bits(c_m), f64::from_bits(c_c));
                for i in 0..kx.len() {
                    kx[i] = r[i] - c_m * mx[i] - c_c * cx[i];
                }
            }
            _ => mult(&self.k, x, kx),
        }
        Ok(())
    }
    fn prepare(&mut self, _tangent_at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), Error> {
        // Linear: J depends only on the coefficients.
        let key = (c_m.to_bits(), c_c.to_bits());
        if self.key == Some(key) {
            return Ok(());
        }
        let j = &self.k + &self.m * c_m + &self.c * c_c;
        self.lu = Some(j.lu());
        self.factorizations += 1;
        self.key = Some(key);
        Ok(())
    }
    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), Error> {
        let lu = self.lu.as_ref().ok_or(AnalysisError::NotPrepared)?;
        let s = lu.solve(&DVector::from_column_slice(r)).ok_or(AnalysisError::SingularJacobian)?;
        x.copy_from_slice(s.as_slice());
        Ok(())
    }
    fn commit(&mut self) {}
    fn revert(&mut self) {}
}
