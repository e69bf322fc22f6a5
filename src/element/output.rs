//! Element-level scratch: the result buffers an element writes into.
//!
//! Assembly keeps one [`ElementOutput`] per element size (12 DOF for a 2-node beam, 18 and 24 for
//! 3- and 4-node shells) and hands it to every element of that size, so evaluating an element never
//! allocates. [`ElementOutput::prepare`] reallocates only when the size changes.

use nalgebra::{DMatrix, DVector};

/// What [`Element::evaluate`](super::Element::evaluate) is asked to compute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EvalRequest {
    /// Internal force only (residual check, line search, explicit steps).
    Force,
    /// Internal force and consistent tangent stiffness (Newton iteration).
    ForceAndTangent,
    /// Internal force and the secant stiffness (damage: the damaged elastic matrix
    /// (1 − d) C₀ at every point, positive definite; elastic elements: their stiffness), for
    /// secant iterations through softening. `k_t` then holds the secant matrix.
    ForceAndSecant,
}

impl EvalRequest {
    /// Whether a stiffness matrix (tangent or secant) is wanted.
    pub fn wants_tangent(self) -> bool {
        matches!(self, EvalRequest::ForceAndTangent | EvalRequest::ForceAndSecant)
    }

    /// Whether the matrix wanted is the secant one.
    pub fn wants_secant(self) -> bool {
        matches!(self, EvalRequest::ForceAndSecant)
    }
}

/// The internal force and tangent of one element, in global axes, node-major (6 DOF per node).
#[derive(Clone, Debug)]
pub struct ElementOutput {
    /// Internal force f_int(u_e), length `n_dofs`.
    pub f_int: DVector<f64>,
    /// Tangent K_t = ∂f_int/∂u_e, `n_dofs × n_dofs`; meaningful only when [`Self::has_tangent`].
    pub k_t: DMatrix<f64>,
    /// Set by the element: `true` when `k_t` holds the tangent of the last evaluation.
    pub has_tangent: bool,
}

impl ElementOutput {
    /// Buffers for an element with `n_dofs` degrees of freedom, zeroed.
    pub fn new(n_dofs: usize) -> Self {
        Self { f_int: DVector::zeros(n_dofs), k_t: DMatrix::zeros(n_dofs, n_dofs), has_tangent: false }
    }

    /// Number of DOF the buffers are sized for.
    pub fn n_dofs(&self) -> usize {
        self.f_int.len()
    }

    /// Size the buffers for `n_dofs` (no allocation when already that size), zero the force and mark
    /// the tangent invalid. Elements call this at the start of `evaluate`.
    pub fn prepare(&mut self, n_dofs: usize) {
        if self.f_int.len() != n_dofs {
            self.f_int = DVector::zeros(n_dofs);
            self.k_t = DMatrix::zeros(n_dofs, n_dofs);
        } else {
            self.f_int.fill(0.0);
        }
        self.has_tangent = false;
    }
}

/// Size `m` as `n × n` (allocating only on a size change) and zero it.
pub(crate) fn prepare_matrix(m: &mut DMatrix<f64>, n: usize) {
    if m.nrows() != n || m.ncols() != n {
        *m = DMatrix::zeros(n, n);
    } else {
        m.fill(0.0);
    }
}

/// Size `v` to length `n` (allocating only on a size change) and zero it.
pub(crate) fn prepare_vector(v: &mut DVector<f64>, n: usize) {
    if v.len() != n {
        *v = DVector::zeros(n);
    } else {
        v.fill(0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prepare_keeps_buffer_when_size_unchanged() {
        let mut out = ElementOutput::new(12);
        out.f_int[3] = 1.0;
        out.has_tangent = true;
        let ptr = out.k_t.as_ptr();
        out.prepare(12);
        assert_eq!(out.k_t.as_ptr(), ptr, "same size must not reallocate");
        assert_eq!(out.f_int[3], 0.0);
        assert!(!out.has_tangent);
        out.prepare(24);
        assert_eq!(out.n_dofs(), 24);
        assert_eq!(out.k_t.shape(), (24, 24));
    }
}
