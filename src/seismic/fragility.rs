//! Lognormal fragility functions, P(limit passed | IM = x) = Φ(ln(x / θ) / β), fitted to the
//! intensities at which the records of an incremental dynamic analysis pass a limit (Baker 2015,
//! "Efficient analytical fragility function fitting using dynamic structural analysis",
//! Earthquake Spectra 31(1)):
//!
//! * every record passed the limit at a known intensity: the method of moments on ln IM, ln θ
//!   the mean of ln xᵢ and β their sample standard deviation (n − 1), Baker's estimator for IDA;
//! * some records did not pass it up to the highest intensity run (right-censored, Baker's
//!   truncated IDA) or passed it already at the lowest (left-censored): maximum likelihood, each
//!   censored record contributing P(X > x_c) = 1 − Φ(z_c) or P(X ≤ x_c) = Φ(z_c) where a passed
//!   one contributes the density.
//!
//! The likelihood is maximized by Newton's method in (a, b) = (ln θ / β, 1 / β), where it is
//! concave (the censored normal's log-likelihood, Olsen 1978), from the moments of the passages.
use serde::Serialize;

/// One record's passage of a limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Passage {
    /// Passed at this intensity.
    At(f64),
    /// Not passed up to this intensity (the highest run).
    Above(f64),
    /// Passed at or below this intensity (the lowest run).
    AtOrBelow(f64),
}

/// How a fit was made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimator {
    /// Mean and sample standard deviation of ln IM.
    Moments,
    /// Maximum likelihood with censored records.
    CensoredMaximumLikelihood,
}

/// A lognormal fragility function.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FragilityFit {
    /// Median θ [the intensity's unit].
    pub median: f64,
    /// Dispersion β (none from a single passage).
    pub beta: Option<f64>,
    /// How it was made.
    pub estimator: Estimator,
}

impl FragilityFit {
    /// P(passed | IM = x): a step at the median where β = 0 (passages all at one intensity);
    /// none without a dispersion (a single passage).
    pub fn probability(&self, x: f64) -> Option<f64> {
        self.beta.map(|b| {
            if b > 0.0 {
                normal_cdf((x / self.median).ln() / b)
            } else {
                f64::from(u8::from(x >= self.median))
            }
        })
    }
}

/// The fit to `passages`: moments without censoring (a median alone from one passage), maximum
/// likelihood with it (at least two distinct passed intensities); `None` otherwise.
pub fn fit_fragility(passages: &[Passage]) -> Option<FragilityFit> {
    let at: Vec<f64> =
        passages.iter().filter_map(|p| if let Passage::At(x) = p { Some(x.ln()) } else { None }).collect();
    if at.len() == passages.len() {
        let (mean, std) = moments(&at)?;
        return Some(FragilityFit { median: mean.exp(), beta: std, estimator: Estimator::Moments });
    }
    let distinct = at.iter().any(|y| (y - at[0]).abs() > 1e-12);
    if at.len() < 2 || !distinct {
        return None;
    }
    let (mu, beta) = maximum_likelihood(passages)?;
    Some(FragilityFit { median: mu.exp(), beta: Some(beta), estimator: Estimator::CensoredMaximumLikelihood })
}

/// Mean and sample standard deviation (none below two values) of `y`.
fn moments(y: &[f64]) -> Option<(f64, Option<f64>)> {
    if y.is_empty() {
        return None;
    }
    let n = y.len() as f64;
    let mean = y.iter().sum::<f64>() / n;
    let std = (y.len() > 1).then(|| (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt());
    Some((mean, std))
}

/// The log-likelihood of (a, b) = (μ/β, 1/β), its gradient and Hessian (the constant −Σ ln xᵢ √2π
/// of the passed records left out).
fn log_likelihood(passages: &[Passage], a: f64, b: f64) -> (f64, [f64; 2], [[f64; 2]; 2]) {
    let (mut l, mut g, mut h) = (0.0, [0.0; 2], [[0.0; 2]; 2]);
    for p in passages {
        // z = b y − a; dz/da = −1, dz/db = y.
        let (y, kind) = match *p {
            Passage::At(x) => (x.ln(), 0),
            Passage::Above(x) => (x.ln(), 1),
            Passage::AtOrBelow(x) => (x.ln(), 2),
        };
        let z = b * y - a;
        // ℓ(z), dℓ/dz, d²ℓ/dz² of the record's term; the passed one has the extra ln b.
        let (lz, d1, d2) = match kind {
            0 => {
                l += b.ln();
                g[1] += 1.0 / b;
                h[1][1] -= 1.0 / (b * b);
                (-0.5 * z * z, -z, -1.0)
            }
            1 => {
                let m = mills(z);
                (ln_upper_tail(z), -m, -m * (m - z))
            }
            _ => {
                let m = mills(-z);
                (ln_upper_tail(-z), m, -m * (m + z))
            }
        };
        l += lz;
        let dz = [-1.0, y];
        for i in 0..2 {
            g[i] += d1 * dz[i];
            for j in 0..2 {
                h[i][j] += d2 * dz[i] * dz[j];
            }
        }
    }
    (l, g, h)
}

/// (μ, β) maximizing the likelihood of `passages`: Newton's method with backtracking in
/// (a, b) = (μ/β, 1/β), from the moments of the passed records.
fn maximum_likelihood(passages: &[Passage]) -> Option<(f64, f64)> {
    let at: Vec<f64> =
        passages.iter().filter_map(|p| if let Passage::At(x) = p { Some(x.ln()) } else { None }).collect();
    let (mean, std) = moments(&at)?;
    let beta0 = std.unwrap_or(0.3).max(0.05);
    let (mut a, mut b) = (mean / beta0, 1.0 / beta0);
    for _ in 0..200 {
        let (l, g, h) = log_likelihood(passages, a, b);
        let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
        if !(det.is_finite() && det > 0.0 && h[0][0] < 0.0) {
            return None;
        }
        // δ = −H⁻¹ g (H negative definite: an ascent direction).
        let da = -(h[1][1] * g[0] - h[0][1] * g[1]) / det;
        let db = -(-h[1][0] * g[0] + h[0][0] * g[1]) / det;
        let mut t = 1.0;
        while b + t * db <= 0.0 || log_likelihood(passages, a + t * da, b + t * db).0 < l - 1e-14 * l.abs() {
            t *= 0.5;
            if t < 1e-12 {
                return None;
            }
        }
        a += t * da;
        b += t * db;
        if (t * da).abs() <= 1e-13 * a.abs().max(1.0) && (t * db).abs() <= 1e-13 * b {
            break;
        }
    }
    Some((a / b, 1.0 / b))
}

/// The standard normal distribution function Φ(z) (to 1.2e-7 relative, from `erfc`).
pub fn normal_cdf(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// ln(1 − Φ(z)), by the asymptotic series of the Mills ratio far in the tail.
fn ln_upper_tail(z: f64) -> f64 {
    if z > 8.0 {
        -0.5 * z * z - 0.5 * (2.0 * std::f64::consts::PI).ln() + mills_ratio_tail(z).ln()
    } else {
        (0.5 * erfc(z / std::f64::consts::SQRT_2)).ln()
    }
}

/// φ(z) / (1 − Φ(z)), the inverse Mills ratio.
fn mills(z: f64) -> f64 {
    if z > 8.0 {
        1.0 / mills_ratio_tail(z)
    } else {
        let phi = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
        phi / (0.5 * erfc(z / std::f64::consts::SQRT_2))
    }
}

/// (1 − Φ(z)) / φ(z) for z > 8: 1/z (1 − 1/z² + 3/z⁴ − 15/z⁶ + 105/z⁸ − 945/z¹⁰), the
/// asymptotic series (Abramowitz and Stegun 26.2.12), within 2e-7 relative there (the next term).
fn mills_ratio_tail(z: f64) -> f64 {
    let w = 1.0 / (z * z);
    (1.0 - w * (1.0 - 3.0 * w * (1.0 - 5.0 * w * (1.0 - 7.0 * w * (1.0 - 9.0 * w))))) / z
}

/// The complementary error function, by the Chebyshev fit of Press et al., Numerical Recipes
/// (2nd ed., 1992), §6.2 `erfcc`: fractional error below 1.2e-7 everywhere.
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let c = [
        -1.26551223,
        1.00002368,
        0.37409196,
        0.09678418,
        -0.18628806,
        0.27886807,
        -1.13520398,
        1.48851587,
        -0.82215223,
        0.17087277,
    ];
    let poly = c.iter().rev().fold(0.0, |acc, &k| acc * t + k);
    let ans = t * (-z * z + poly).exp();
    if x >= 0.0 {
        ans
    } else {
        2.0 - ans
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Φ against Abramowitz and Stegun Table 26.1: Φ(0) = 0.5, Φ(1) = 0.8413447461,
    /// Φ(-1.96) = 0.0249978952, Φ(3) = 0.9986501020; tolerance 2e-7 (the erfc fit's 1.2e-7).
    #[test]
    fn the_normal_distribution_function_matches_the_tables() {
        for (z, want) in [(0.0, 0.5), (1.0, 0.8413447461), (-1.96, 0.0249978952), (3.0, 0.9986501020)] {
            let got = normal_cdf(z);
            assert!((got - want).abs() < 2e-7 * want, "Phi({z}) = {got}, tables {want}");
        }
        // The tail's series meets the fit at z = 8, where 1 − Φ(8) = 6.220960574e-16.
        assert!((ln_upper_tail(8.0 + 1e-9) - ln_upper_tail(8.0 - 1e-9)).abs() < 1e-6);
        assert!((ln_upper_tail(8.0 + 1e-9) - 6.220960574e-16f64.ln()).abs() < 1e-6);
    }

    /// Without censoring: θ the geometric mean, β the sample standard deviation of ln x: e and e³
    /// give θ = e², β = √2; P at the median is 1/2, at θ e^β it is Φ(1) = 0.8413447461.
    #[test]
    fn the_method_of_moments_on_two_passages() {
        let e = std::f64::consts::E;
        let f = fit_fragility(&[Passage::At(e), Passage::At(e.powi(3))]).unwrap();
        assert_eq!(f.estimator, Estimator::Moments);
        assert!((f.median - e * e).abs() < 1e-12 && (f.beta.unwrap() - 2f64.sqrt()).abs() < 1e-12, "{f:?}");
        // Φ to the erfc fit's 1.2e-7 relative: 1e-7 at 1/2.
        assert!((f.probability(f.median).unwrap() - 0.5).abs() < 1e-7);
        let x = f.median * f.beta.unwrap().exp();
        assert!((f.probability(x).unwrap() - 0.8413447461).abs() < 2e-7);
        let one = fit_fragility(&[Passage::At(2.0)]).unwrap();
        assert_eq!((one.median, one.beta, one.probability(3.0)), (2.0, None, None));
        let same = fit_fragility(&[Passage::At(2.0), Passage::At(2.0)]).unwrap();
        assert_eq!((same.beta, same.probability(1.9), same.probability(2.0)), (Some(0.0), Some(0.0), Some(1.0)));
    }

    /// Maximum likelihood without censoring has a closed form: μ the mean of ln x, β the
    /// population standard deviation (n in the denominator).
    #[test]
    fn maximum_likelihood_without_censoring_is_the_closed_form() {
        let xs = [0.8, 1.1, 1.3, 2.0, 2.6];
        let y: Vec<f64> = xs.iter().map(|x: &f64| x.ln()).collect();
        let mean = y.iter().sum::<f64>() / 5.0;
        let pop = (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 5.0).sqrt();
        let p: Vec<Passage> = xs.iter().map(|&x| Passage::At(x)).collect();
        let (mu, beta) = maximum_likelihood(&p).unwrap();
        assert!((mu - mean).abs() < 1e-10 && (beta - pop).abs() < 1e-10, "{mu} {beta} against {mean} {pop}");
    }

    /// The log-likelihood in (μ, β), written here from the densities directly (ln of the
    /// lognormal density of a passage, ln(1 − Φ) or ln Φ of a censored record).
    fn direct(p: &[Passage], mu: f64, beta: f64) -> f64 {
        p.iter()
            .map(|q| match *q {
                Passage::At(x) => {
                    let z = (x.ln() - mu) / beta;
                    -0.5 * z * z - beta.ln() - x.ln() - 0.5 * (2.0 * std::f64::consts::PI).ln()
                }
                Passage::Above(x) => (1.0 - normal_cdf((x.ln() - mu) / beta)).ln(),
                Passage::AtOrBelow(x) => normal_cdf((x.ln() - mu) / beta).ln(),
            })
            .sum()
    }

    /// With two records above the cap of 3.5 and one at or below the first level of 0.8: the fit
    /// is a stationary point of the likelihood written from the densities (central differences,
    /// |∂ℓ/∂μ|, |∂ℓ/∂β| < 1e-5 with the erfc fit's 1.2e-7 in the censored terms) and no point of a
    /// grid of ±20 % around it is higher; the censoring above moves the median above the passed
    /// records' geometric mean (1.73).
    #[test]
    fn maximum_likelihood_with_censored_records_is_the_maximum() {
        let p = [
            Passage::At(1.0),
            Passage::At(1.5),
            Passage::At(2.0),
            Passage::At(3.0),
            Passage::Above(3.5),
            Passage::Above(3.5),
            Passage::AtOrBelow(0.8),
        ];
        let f = fit_fragility(&p).unwrap();
        assert_eq!(f.estimator, Estimator::CensoredMaximumLikelihood);
        let (mu, beta) = (f.median.ln(), f.beta.unwrap());
        let h = 1e-5;
        let dmu = (direct(&p, mu + h, beta) - direct(&p, mu - h, beta)) / (2.0 * h);
        let dbeta = (direct(&p, mu, beta + h) - direct(&p, mu, beta - h)) / (2.0 * h);
        assert!(dmu.abs() < 1e-5 && dbeta.abs() < 1e-5, "gradient {dmu} {dbeta} at {mu} {beta}");
        let best = direct(&p, mu, beta);
        for i in -10..=10 {
            for j in -10..=10 {
                let (m, b) = (mu + 0.02 * i as f64, beta * (1.0 + 0.02 * j as f64));
                assert!(direct(&p, m, b) <= best + 1e-9, "({m}, {b}) higher than the fit ({mu}, {beta})");
            }
        }
        let geo = (1.0f64 * 1.5 * 2.0 * 3.0).powf(0.25);
        assert!(f.median > geo, "{} against {geo}", f.median);
        // Too few passed records to fit with censoring.
        assert_eq!(fit_fragility(&[Passage::At(1.0), Passage::Above(2.0)]), None);
        assert_eq!(fit_fragility(&[Passage::Above(2.0), Passage::Above(2.0)]), None);
    }
}
