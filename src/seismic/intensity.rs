//! Intensity measures of a record: PGA, PGV, PGD, Arias intensity, significant duration D5–95.
//!
//! The acceleration is linear between samples, so velocity and displacement are integrated
//! exactly for that interpolation (starting from rest, `v_0 = u_0 = 0`):
//!
//! ```text
//! v_{i+1} = v_i + Δt (a_i + a_{i+1}) / 2
//! u_{i+1} = u_i + Δt v_i + Δt² (2 a_i + a_{i+1}) / 6
//! ```
//!
//! Arias intensity `I_A = π/(2g) ∫ a² dt` (Arias 1970), with `∫ a²` over a step exactly
//! `Δt (a_i² + a_i a_{i+1} + a_{i+1}²)/3`. The Husid curve `H(t) = ∫_0^t a²/∫_0^T a²`; the
//! significant duration D5–95 (Trifunac & Brady 1975) is the time between `H = 0.05` and `H = 0.95`,
//! each found by linear interpolation of `H` between samples.
//!
//! PGV and PGD of an uncorrected record include any baseline drift: correct first
//! ([`super::baseline`]) or filter ([`super::filter`]) for meaningful values.
use super::record::Record;
use super::units::STANDARD_GRAVITY;

/// Velocity [m/s] and displacement [m] histories from rest, exact for piecewise-linear acceleration.
pub fn integrate(accel: &[f64], dt: f64) -> (Vec<f64>, Vec<f64>) {
    let n = accel.len();
    let mut v = vec![0.0; n];
    let mut u = vec![0.0; n];
    for i in 1..n {
        let (a0, a1) = (accel[i - 1], accel[i]);
        v[i] = v[i - 1] + dt * (a0 + a1) / 2.0;
        u[i] = u[i - 1] + dt * v[i - 1] + dt * dt * (2.0 * a0 + a1) / 6.0;
    }
    (v, u)
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0_f64, |m, a| m.max(a.abs()))
}

/// Summary of a record's intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intensity {
    /// Peak ground acceleration [m/s²].
    pub pga: f64,
    /// Peak ground velocity [m/s].
    pub pgv: f64,
    /// Peak ground displacement [m].
    pub pgd: f64,
    /// Arias intensity [m/s].
    pub arias: f64,
    /// Time at which 5% of the Arias intensity is reached [s].
    pub t5: f64,
    /// Time at which 95% of the Arias intensity is reached [s].
    pub t95: f64,
}

impl Intensity {
    /// Significant duration D5–95 [s].
    pub fn d5_95(&self) -> f64 {
        self.t95 - self.t5
    }
}

/// Peak ground acceleration [m/s²].
pub fn pga(r: &Record) -> f64 {
    max_abs(&r.accel)
}

/// The normalised Husid curve `H(t_i)` (0 … 1; all zeros for a zero record).
pub fn husid(r: &Record) -> Vec<f64> {
    let mut h = vec![0.0; r.accel.len()];
    for i in 1..r.accel.len() {
        let (a0, a1) = (r.accel[i - 1], r.accel[i]);
        h[i] = h[i - 1] + r.dt * (a0 * a0 + a0 * a1 + a1 * a1) / 3.0;
    }
    let total = h.last().copied().unwrap_or(0.0);
    if total > 0.0 {
        h.iter_mut().for_each(|x| *x /= total);
    }
    h
}

fn crossing(h: &[f64], dt: f64, level: f64) -> f64 {
    match h.iter().position(|&x| x >= level) {
        None => (h.len().max(1) - 1) as f64 * dt,
        Some(0) => 0.0,
        Some(i) => {
            let (h0, h1) = (h[i - 1], h[i]);
            let f = if h1 > h0 { (level - h0) / (h1 - h0) } else { 0.0 };
            (i as f64 - 1.0 + f) * dt
        }
    }
}

/// All intensity measures of a record.
pub fn intensity(r: &Record) -> Intensity {
    let (v, u) = integrate(&r.accel, r.dt);
    let mut a2 = 0.0;
    for w in r.accel.windows(2) {
        a2 += r.dt * (w[0] * w[0] + w[0] * w[1] + w[1] * w[1]) / 3.0;
    }
    let h = husid(r);
    Intensity {
        pga: pga(r),
        pgv: max_abs(&v),
        pgd: max_abs(&u),
        arias: std::f64::consts::PI / (2.0 * STANDARD_GRAVITY) * a2,
        t5: crossing(&h, r.dt, 0.05),
        t95: crossing(&h, r.dt, 0.95),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn sine_pulse_measures_match_closed_forms() {
        // a = A sin(2π t / T0) on [0, T0]: v = A T0/(2π) (1 − cos), PGV = A T0/π at t = T0/2;
        // u = A T0/(2π) (t − T0/(2π) sin) so PGD = u(T0) = A T0²/(2π);
        // ∫a² = A² T0/2, so I_A = π/(2g) A² T0/2.
        let (a, t0, n) = (2.0, 1.0, 20_000);
        let dt = t0 / n as f64;
        let acc: Vec<f64> = (0..=n).map(|i| a * (2.0 * PI * i as f64 * dt / t0).sin()).collect();
        let r = Record::new("pulse", dt, acc, "m/s^2", "test").unwrap();
        let im = intensity(&r);
        // Sampling/interpolation errors are O(dt²): 1e-6 relative is loose enough.
        assert!((im.pga - a).abs() < 1e-6 * a);
        assert!((im.pgv - a * t0 / PI).abs() < 1e-6 * a * t0 / PI, "{}", im.pgv);
        let pgd = a * t0 * t0 / (2.0 * PI);
        assert!((im.pgd - pgd).abs() < 1e-6 * pgd, "{}", im.pgd);
        let ia = PI / (2.0 * STANDARD_GRAVITY) * a * a * t0 / 2.0;
        assert!((im.arias - ia).abs() < 1e-6 * ia);
    }

    #[test]
    fn d5_95_of_a_constant_amplitude_record_is_ninety_percent_of_it() {
        // a = 1 on [2, 12] s, 0 elsewhere: H grows linearly over the 10 s, D5–95 = 9 s
        // (up to the one-step ramps at the edges: tolerance 2 dt).
        let dt = 0.01;
        let acc: Vec<f64> = (0..2001).map(|i| if (200..=1200).contains(&i) { 1.0 } else { 0.0 }).collect();
        let im = intensity(&Record::new("box", dt, acc, "", "").unwrap());
        assert!((im.d5_95() - 9.0).abs() < 2.0 * dt, "{}", im.d5_95());
        assert!((im.t5 - 2.5).abs() < 2.0 * dt, "{}", im.t5);
    }
}
