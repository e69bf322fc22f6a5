//! A radix-2 complex fast Fourier transform (iterative Cooley–Tukey), enough for spectral
//! matching of records of a few thousand samples without an external crate.
//!
//! Forward: `X_k = Σ_n x_n e^{−2πi kn/N}`; inverse: `x_n = (1/N) Σ_k X_k e^{+2πi kn/N}`.
use super::error::SeismicError;
use std::f64::consts::PI;

/// A complex number (re, im).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Complex {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Complex {
    fn mul(self, o: Complex) -> Complex {
        Complex { re: self.re * o.re - self.im * o.im, im: self.re * o.im + self.im * o.re }
    }
}

/// Transforms `x` in place (forward, or inverse with the 1/N factor). `x.len()` must be a power of two.
pub fn fft_in_place(x: &mut [Complex], inverse: bool) -> Result<(), SeismicError> {
    let n = x.len();
    if !n.is_power_of_two() {
        return Err(SeismicError::invalid("FFT length", format!("{n} is not a power of two")));
    }
    // Bit-reversal permutation.
    let bits = n.trailing_zeros();
    for i in 0..n {
        let j = if bits == 0 { 0 } else { i.reverse_bits() >> (usize::BITS - bits) };
        if j > i {
            x.swap(i, j);
        }
    }
    let sign = if inverse { 1.0 } else { -1.0 };
    let mut len = 2;
    while len <= n {
        let ang = sign * 2.0 * PI / len as f64;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let w = Complex { re: (ang * k as f64).cos(), im: (ang * k as f64).sin() };
                let a = x[start + k];
                let b = x[start + k + len / 2].mul(w);
                x[start + k] = Complex { re: a.re + b.re, im: a.im + b.im };
                x[start + k + len / 2] = Complex { re: a.re - b.re, im: a.im - b.im };
            }
        }
        len *= 2;
    }
    if inverse {
        let f = 1.0 / n as f64;
        x.iter_mut().for_each(|c| {
            c.re *= f;
            c.im *= f;
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_naive_dft_and_inverts() {
        let n = 64;
        let x: Vec<Complex> =
            (0..n).map(|i| Complex { re: ((i * 7) % 11) as f64 - 5.0, im: ((i * 3) % 5) as f64 }).collect();
        let mut y = x.clone();
        fft_in_place(&mut y, false).unwrap();
        for (k, yk) in y.iter().enumerate() {
            let mut s = Complex::default();
            for (j, xj) in x.iter().enumerate() {
                let a = -2.0 * PI * (k * j) as f64 / n as f64;
                s.re += xj.re * a.cos() - xj.im * a.sin();
                s.im += xj.re * a.sin() + xj.im * a.cos();
            }
            // O(N log N) round-off on sums of size ~300: 1e-10 absolute.
            assert!((s.re - yk.re).abs() < 1e-10 && (s.im - yk.im).abs() < 1e-10, "k = {k}");
        }
        fft_in_place(&mut y, true).unwrap();
        for (a, b) in x.iter().zip(&y) {
            assert!((a.re - b.re).abs() < 1e-12 && (a.im - b.im).abs() < 1e-12);
        }
        assert!(fft_in_place(&mut [Complex::default(); 6], false).is_err());
    }
}
