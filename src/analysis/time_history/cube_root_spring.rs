//! A one-DOF test system whose internal force is a cube root, the classical case where Newton's
//! iterates run away (the line-search tests of the gravity phase and of the time history):
//!
//! ```text
//!   f_int(u) = ∛(u − a) + ∛a,   f_int(0) = 0,   static load F = ∛a: the root at u = a
//!   Newton (statics):  u_{k+1} − a = −2 (u_k − a)
//! ```
use super::system::DynamicSystem;
use crate::error::Error;

/// The spring of the module docs with a unit mass and no damping.
pub(super) struct CubeRootSpring {
    a: f64,
    /// The static load F = ∛a.
    pub load: Vec<f64>,
    zero: Vec<f64>,
    /// The last prepared J = K(u) + c_m.
    pub jacobian: f64,
}

impl CubeRootSpring {
    /// The spring with its root at `a`.
    pub fn new(a: f64) -> Self {
        CubeRootSpring { a, load: vec![a.cbrt()], zero: vec![0.0], jacobian: 1.0 }
    }
    /// ∛(u − a) + ∛a.
    pub fn f_int(&self, u: f64) -> f64 {
        (u - self.a).cbrt() + self.a.cbrt()
    }
}

impl DynamicSystem for CubeRootSpring {
    fn len(&self) -> usize {
        1
    }
    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        a[0] * b[0]
    }
    fn mass_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        y[0] = x[0];
        Ok(())
    }
    fn damping_mult(&mut self, _x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        y[0] = 0.0;
        Ok(())
    }
    fn mass_influence(&self, _d: usize) -> &[f64] {
        &self.zero
    }
    fn influence(&self, _d: usize) -> &[f64] {
        &self.zero
    }
    fn static_load(&self) -> &[f64] {
        &self.load
    }
    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), Error> {
        f[0] = self.f_int(u[0]);
        Ok(())
    }
    fn prepare(&mut self, at: Option<&[f64]>, c_m: f64, _c_c: f64) -> Result<(), Error> {
        let u = at.map_or(0.0, |u| u[0]);
        let k = 1.0 / (3.0 * (u - self.a).abs().powf(2.0 / 3.0)).max(1e-300);
        self.jacobian = k + c_m;
        Ok(())
    }
    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), Error> {
        x[0] = r[0] / self.jacobian;
        Ok(())
    }
    fn commit(&mut self) {}
    fn revert(&mut self) {}
}
