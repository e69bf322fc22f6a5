//! Seeds of the Voronoi cells: coursed masonry or random Poisson-disk stones, from a seeded RNG.
//!
//! **Coursed.** The wall `W × H` is cut into `n_c` courses of height `h = H/n_c`, each into
//! `n` stones of mean width `w = W/n`. The interior joints of course `k` sit at
//!
//! ```text
//! x_m = m·w + o_k + v·(w/2)·u_m,   m = 1 … n−1,   u_m ~ U[−1, 1)
//! ```
//!
//! with the stagger offset `o_k = 0` on even courses and `± s·w/2` on odd ones (the sign
//! alternating, `+` on courses 1, 5, 9, …, `−` on 3, 7, …, so the long end stones alternate sides
//! like quoins). Every stone width stays ≥ `w (1 − s/2 − v) > 0` for `s ≤ 1`, `v < 1/2`; for larger `v`
//! the joints are sorted, which is still a valid course. The seed of a stone `[x_m, x_{m+1}]` is
//! its centre moved by `j·(Δx/2)·u` horizontally and `j·(h/2)·u'` vertically (`j` = jitter < 1), so it
//! stays strictly inside its stone. Seeds are numbered course by course from the bottom, left to
//! right: particle `k·n + m`.
//!
//! **Random.** Dart throwing (the original Poisson-disk process, random sequential adsorption):
//! uniform candidates in the domain shrunk by `r/2` on each side (so boundary stones are not
//! slivers), accepted when no accepted seed is
//! closer than `r = f·sqrt(W H / N)`, until exactly `N` are placed. A background grid of spacing
//! `r/√2` (at most one seed per bucket) makes each test O(1). Bridson's algorithm was not used
//! because it produces a *maximal* sample whose count is set by `r`, not a requested `N`.
//!
//! The generator is ChaCha8 seeded by `seed_from_u64`; only `random::<f64>()` (uniform [0, 1)) is
//! drawn, whose values are stable across `rand` patch releases.
use super::config::{CoursedLayout, RandomLayout};
use super::error::SampleError;
use crate::dem::polygon::P2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The seeded generator used for every sample.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

fn sym(rng: &mut ChaCha8Rng) -> f64 {
    2.0 * rng.random::<f64>() - 1.0
}

/// Seeds of a coursed wall (validated layout), `n_courses · n_per_course` of them.
pub fn coursed_seeds(l: &CoursedLayout, rng: &mut ChaCha8Rng) -> Vec<P2> {
    let (n, nc) = (l.n_per_course, l.n_courses);
    let w = l.width / n as f64;
    let h = l.height / nc as f64;
    let mut seeds = Vec::with_capacity(n * nc);
    for k in 0..nc {
        let offset = if k % 2 == 0 {
            0.0
        } else if (k / 2) % 2 == 0 {
            0.5 * l.stagger * w
        } else {
            -0.5 * l.stagger * w
        };
        let mut joints = Vec::with_capacity(n + 1);
        joints.push(0.0);
        for m in 1..n {
            let x = m as f64 * w + offset + l.size_variability * 0.5 * w * sym(rng);
            joints.push(x.clamp(0.0, l.width));
        }
        joints.push(l.width);
        joints.sort_by(f64::total_cmp);
        let yc = (k as f64 + 0.5) * h;
        for m in 0..n {
            let (a, b) = (joints[m], joints[m + 1]);
            let x = 0.5 * (a + b) + l.jitter * 0.5 * (b - a) * sym(rng);
            let y = yc + l.jitter * 0.5 * h * sym(rng);
            seeds.push([x, y]);
        }
    }
    seeds
}

/// Minimum seed distance of a random layout: `r = f · sqrt(W H / N)`.
pub fn min_distance(l: &RandomLayout) -> f64 {
    l.min_distance_factor * (l.width * l.height / l.n_particles as f64).sqrt()
}

/// Exactly `n_particles` Poisson-disk seeds at mutual distance ≥ [`min_distance`].
///
/// Gives up with [`SampleError::PoissonDiskFailed`] after `1000 N + 10 000` candidates.
pub fn poisson_disk_seeds(l: &RandomLayout, rng: &mut ChaCha8Rng) -> Result<Vec<P2>, SampleError> {
    poisson_disk_with_budget(l, rng, 1000 * l.n_particles + 10_000)
}

fn poisson_disk_with_budget(
    l: &RandomLayout,
    rng: &mut ChaCha8Rng,
    max_attempts: usize,
) -> Result<Vec<P2>, SampleError> {
    let target = l.n_particles;
    let r = min_distance(l);
    // Margin r/2 (a quarter of the side for a domain narrower than 2r): seeds stay strictly inside.
    let (x0, y0) = ((0.5 * r).min(0.25 * l.width), (0.5 * r).min(0.25 * l.height));
    let (wx, wy) = (l.width - 2.0 * x0, l.height - 2.0 * y0);
    let g = r / std::f64::consts::SQRT_2;
    let nx = ((wx / g).ceil() as usize).max(1);
    let ny = ((wy / g).ceil() as usize).max(1);
    let mut grid: Vec<Option<u32>> = vec![None; nx * ny];
    let mut seeds: Vec<P2> = Vec::with_capacity(target);
    let mut attempts = 0;
    let r2 = r * r;
    while seeds.len() < target && attempts < max_attempts {
        attempts += 1;
        let p = [x0 + wx * rng.random::<f64>(), y0 + wy * rng.random::<f64>()];
        let bx = (((p[0] - x0) / g) as usize).min(nx - 1);
        let by = (((p[1] - y0) / g) as usize).min(ny - 1);
        // A seed closer than r lies within 2 buckets (r = √2 g < 2 g).
        let mut ok = true;
        'scan: for yy in by.saturating_sub(2)..(by + 3).min(ny) {
            for xx in bx.saturating_sub(2)..(bx + 3).min(nx) {
                if let Some(q) = grid[yy * nx + xx] {
                    let q = seeds[q as usize];
                    if (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) < r2 {
                        ok = false;
                        break 'scan;
                    }
                }
            }
        }
        if ok {
            grid[by * nx + bx] = Some(seeds.len() as u32);
            seeds.push(p);
        }
    }
    if seeds.len() < target {
        return Err(SampleError::PoissonDiskFailed { placed: seeds.len(), target, min_distance: r, attempts });
    }
    Ok(seeds)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(jitter: f64, stagger: f64, v: f64) -> CoursedLayout {
        CoursedLayout { width: 1.0, height: 1.2, n_courses: 10, n_per_course: 6, jitter, stagger, size_variability: v }
    }

    #[test]
    fn regular_courses_without_randomness() {
        // jitter = v = 0, s = 1: course 0 centres (m + ½)/6; course 1 joints at m/6 + 1/12,
        // so its first stone is [0, 1.5/6] with centre 0.75/6; course 3 is mirrored: last
        // stone [4.5/6, 1] with centre 5.25/6. Rows at y = (k + ½)·0.12.
        let s = coursed_seeds(&wall(0.0, 1.0, 0.0), &mut rng(1));
        assert_eq!(s.len(), 60);
        let w = 1.0 / 6.0;
        assert!((s[0][0] - 0.5 * w).abs() < 1e-15 && (s[0][1] - 0.06).abs() < 1e-15);
        assert!((s[6][0] - 0.75 * w).abs() < 1e-15 && (s[6][1] - 0.18).abs() < 1e-15);
        assert!((s[23][0] - 5.25 * w).abs() < 1e-15);
    }

    #[test]
    fn jittered_seeds_stay_inside_and_are_reproducible() {
        let l = wall(0.9, 1.0, 0.9);
        let a = coursed_seeds(&l, &mut rng(42));
        let b = coursed_seeds(&l, &mut rng(42));
        let c = coursed_seeds(&l, &mut rng(43));
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert!(a.iter().all(|p| p[0] > 0.0 && p[0] < 1.0 && p[1] > 0.0 && p[1] < 1.2));
    }

    #[test]
    fn poisson_disk_count_and_spacing() {
        let l = RandomLayout { width: 2.0, height: 1.0, n_particles: 500, min_distance_factor: 0.7 };
        let s = poisson_disk_seeds(&l, &mut rng(3)).expect("placeable");
        assert_eq!(s.len(), 500);
        let r = min_distance(&l);
        for i in 0..s.len() {
            for j in 0..i {
                let d = (s[i][0] - s[j][0]).hypot(s[i][1] - s[j][1]);
                assert!(d >= r, "seeds {i}, {j} at {d} < {r}");
            }
        }
    }

    #[test]
    fn exhausted_budget_is_an_error() {
        // One candidate is always accepted (nothing to conflict with), then the budget is spent.
        let l = RandomLayout { width: 1.0, height: 1.0, n_particles: 5, min_distance_factor: 0.5 };
        let e = poisson_disk_with_budget(&l, &mut rng(0), 1).unwrap_err();
        assert!(matches!(e, SampleError::PoissonDiskFailed { placed: 1, target: 5, attempts: 1, .. }), "{e}");
        assert!(e.to_string().contains("lower `min_distance_factor`"));
    }
}
