//! Checks of the input seeds and of the finished cells: every failure is a typed error naming the
//! particle(s) and the offending number.
//!
//! Tolerances, all relative to the mean seed spacing `h = sqrt(W H / N)`:
//! * two seeds closer than `1e-9 h` are duplicates;
//! * a cell with area below `1e-12 h²` is degenerate;
//! * convexity: every turn left within `1e-9` relative to the edge lengths
//!   ([`Polygon::is_convex`]);
//! * the seed is inside its cell when `(v_{k+1} − v_k) × (s − v_k) ≥ −1e-12 |e_k| h` for every edge;
//! * tiling: `|Σ A_i − W H| ≤ 1e-10 W H`.
use super::error::SampleError;
use super::particle::Particle;
use crate::dem::polygon::{Polygon, P2};
use std::collections::HashMap;

/// Mean seed spacing `sqrt(W H / N)` (m).
pub fn mean_spacing(width: f64, height: f64, n: usize) -> f64 {
    (width * height / n.max(1) as f64).sqrt()
}

/// Seeds finite, strictly inside the domain, pairwise distinct.
pub fn check_seeds(width: f64, height: f64, seeds: &[P2]) -> Result<(), SampleError> {
    if seeds.is_empty() {
        return Err(SampleError::NoSeeds);
    }
    for (index, p) in seeds.iter().enumerate() {
        let inside = p[0] > 0.0 && p[0] < width && p[1] > 0.0 && p[1] < height;
        if !inside {
            return Err(SampleError::SeedOutsideDomain { index, x: p[0], y: p[1], width, height });
        }
    }
    let h = mean_spacing(width, height, seeds.len());
    let tol = 1e-9 * h;
    let mut buckets: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let key = |p: P2| ((p[0] / h).floor() as i64, (p[1] / h).floor() as i64);
    for (j, &p) in seeds.iter().enumerate() {
        let (kx, ky) = key(p);
        for dy in -1..=1 {
            for dx in -1..=1 {
                for &i in buckets.get(&(kx + dx, ky + dy)).map(Vec::as_slice).unwrap_or(&[]) {
                    let q = seeds[i];
                    let distance = (q[0] - p[0]).hypot(q[1] - p[1]);
                    if distance <= tol {
                        return Err(SampleError::DuplicateSeeds { i, j, distance, tolerance: tol });
                    }
                }
            }
        }
        buckets.entry((kx, ky)).or_default().push(j);
    }
    Ok(())
}

/// Every cell non-degenerate, convex and containing its seed; the cells tile the domain.
pub fn check_cells(width: f64, height: f64, particles: &[Particle]) -> Result<(), SampleError> {
    let h = mean_spacing(width, height, particles.len());
    for (k, p) in particles.iter().enumerate() {
        if p.polygon.len() < 3 || p.area < 1e-12 * h * h {
            return Err(SampleError::ZeroAreaCell { particle: k, area: p.area });
        }
        if !p.polygon.is_convex(1e-9) {
            return Err(SampleError::NonConvexCell { particle: k });
        }
        if !contains(&p.polygon, p.seed, 1e-12 * h) {
            return Err(SampleError::SeedOutsideCell { particle: k, x: p.seed[0], y: p.seed[1] });
        }
    }
    let sum: f64 = particles.iter().map(|p| p.area).sum();
    let domain = width * height;
    let relative = (sum - domain).abs() / domain;
    if relative > 1e-10 {
        return Err(SampleError::TilingMismatch { sum, domain, relative });
    }
    Ok(())
}

/// Whether `s` is inside the convex counter-clockwise polygon, within `tol` (m).
pub fn contains(poly: &Polygon, s: P2, tol: f64) -> bool {
    let v = &poly.vertices;
    (0..v.len()).all(|k| {
        let (a, b) = (v[k], v[(k + 1) % v.len()]);
        let e = [b[0] - a[0], b[1] - a[1]];
        e[0] * (s[1] - a[1]) - e[1] * (s[0] - a[0]) >= -tol * e[0].hypot(e[1])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_seeds_are_named() {
        assert_eq!(check_seeds(1.0, 1.0, &[]), Err(SampleError::NoSeeds));
        let e = check_seeds(1.0, 1.0, &[[0.5, 0.5], [1.0, 0.5]]).unwrap_err();
        assert!(matches!(e, SampleError::SeedOutsideDomain { index: 1, .. }), "{e}");
        let e = check_seeds(1.0, 1.0, &[[0.5, f64::NAN]]).unwrap_err();
        assert!(matches!(e, SampleError::SeedOutsideDomain { index: 0, .. }), "{e}");
        let e = check_seeds(1.0, 1.0, &[[0.2, 0.2], [0.5, 0.5], [0.2, 0.2 + 1e-12]]).unwrap_err();
        assert!(matches!(e, SampleError::DuplicateSeeds { i: 0, j: 2, .. }), "{e}");
        assert!(e.to_string().contains("seeds 0 and 2"));
        assert!(check_seeds(1.0, 1.0, &[[0.2, 0.2], [0.2, 0.2 + 1e-6]]).is_ok());
    }

    #[test]
    fn bad_cells_are_named() {
        // A non-convex "cell" (an L) and a cell not containing its seed.
        let l = Polygon::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.5, 0.5], [0.5, 1.0], [0.0, 1.0]]);
        let e = check_cells(1.0, 1.0, &[Particle::new(l, [0.25, 0.25])]).unwrap_err();
        assert_eq!(e, SampleError::NonConvexCell { particle: 0 });
        let sq = Polygon::rectangle(0.0, 0.0, 1.0, 1.0);
        let e = check_cells(1.0, 1.0, &[Particle::new(sq.clone(), [1.5, 0.5])]).unwrap_err();
        assert!(matches!(e, SampleError::SeedOutsideCell { particle: 0, .. }));
        let e = check_cells(2.0, 1.0, &[Particle::new(sq, [0.5, 0.5])]).unwrap_err();
        assert!(matches!(e, SampleError::TilingMismatch { relative, .. } if (relative - 0.5).abs() < 1e-15));
        let flat = Polygon::new(vec![[0.0, 0.0], [1.0, 0.0], [0.5, 0.0]]);
        let e = check_cells(1.0, 1.0, &[Particle::new(flat, [0.5, 0.0])]).unwrap_err();
        assert!(matches!(e, SampleError::ZeroAreaCell { particle: 0, .. }));
    }
}
