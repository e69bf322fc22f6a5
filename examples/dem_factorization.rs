//! The reference cost of the DEM benchmark: one sparse Cholesky factorization (faer, symbolic
//! analysis + numeric) of the DEM operator of a random sample of N stones, all beams intact.
//!
//!     target/debug/examples/dem_factorization 10000
//!
//! Prints one JSON line: stones, equations, non-zeros of the upper triangle, seconds to build the
//! sample, to assemble, for the first factorization (symbolic + numeric), for a second numeric
//! factorization of the same pattern, for one solve and for a batch of Woodbury columns, with the
//! cost model's estimate (`factor.rs`) of a factorization in solves beside the measured ratio
//! (they agree when `FACTOR_SPEEDUP` is right), and the batch's `BATCH_COLUMN_COST`; beside it the
//! same factorization with the other fill-reducing ordering (AMD or nested dissection, see
//! `factor::NESTED_DISSECTION_MIN`).
//! `scripts/bench/dem.sh` divides the CPU cost of a beam-break event by the numeric
//! factorization's CPU seconds (`numeric_factorization_cpu_seconds`).
use std::time::Instant;

use masonry_hpc::dem::mechanics::MechParams;

#[path = "common/random_sample.rs"]
mod random_sample;
use masonry_hpc::dem::solver::cholmod::UpdatableCholesky;
use masonry_hpc::dem::solver::factor::{Ordering, BATCH};
use masonry_hpc::dem::solver::{DofControl, DofMap, LowRankCholesky, Model};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(1000);
    let t0 = Instant::now();
    let sample = random_sample::random_square(n)?;
    let build = t0.elapsed().as_secs_f64();
    let params = MechParams::default();
    let map = DofMap::new(&sample, [[DofControl::Prescribed; 3]; 2])?;
    let model = Model::new(&sample, &params, map)?;
    let t1 = Instant::now();
    let intact = vec![true; sample.beams.len()];
    let reg: Vec<f64> = model.diagonal().iter().map(|d| 1e-10 * d.max(1.0)).collect();
    let upper = model.assemble(&intact, &reg, &[]);
    let assemble = t1.elapsed().as_secs_f64();
    let n_eq = model.map.n_eq();
    let mut factor = LowRankCholesky::new(n_eq);
    let t2 = Instant::now();
    factor.factorize(&upper).map_err(|e| e.0)?;
    let first = t2.elapsed().as_secs_f64();
    let t3 = Instant::now();
    factor.factorize(&upper).map_err(|e| e.0)?;
    let numeric = t3.elapsed().as_secs_f64();
    // The same in CPU seconds of the process (sequential faer: one thread), best of 3: on a
    // shared machine the wall time overstates it.
    let mut numeric_cpu = f64::INFINITY;
    for _ in 0..3 {
        let c = cpu_seconds();
        factor.factorize(&upper).map_err(|e| e.0)?;
        numeric_cpu = numeric_cpu.min(cpu_seconds() - c);
    }
    // One solve (best of 5), and a batch of BATCH Woodbury columns (best of 3, unit vectors).
    let mut solve = f64::INFINITY;
    for _ in 0..5 {
        let mut x = vec![1.0; n_eq];
        let t4 = Instant::now();
        factor.solve(&mut x).map_err(|e| e.0)?;
        solve = solve.min(t4.elapsed().as_secs_f64());
    }
    let mut batch = f64::INFINITY;
    for _ in 0..3 {
        let cols: Vec<_> = (0..BATCH).map(|k| vec![((k * 7919) % n_eq, 1e-3)]).collect();
        let t5 = Instant::now();
        factor.add_batch(vec![(cols, 1.0)]).map_err(|e| e.0)?;
        batch = batch.min(t5.elapsed().as_secs_f64());
        factor.factorize(&upper).map_err(|e| e.0)?;
    }
    let (w_s, w_f) = factor.costs();
    // The other ordering on the same matrix: flops of a solve and a factorization, seconds of a
    // numeric factorization and of a solve (best of 3).
    let other = match factor.ordering {
        Ordering::Amd => Ordering::NestedDissection,
        Ordering::NestedDissection => Ordering::Amd,
    };
    let mut alt = LowRankCholesky::with_ordering(n_eq, other);
    let t6 = Instant::now();
    alt.factorize(&upper).map_err(|e| e.0)?;
    let alt_first = t6.elapsed().as_secs_f64();
    let (mut alt_numeric, mut alt_solve) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        let t7 = Instant::now();
        alt.factorize(&upper).map_err(|e| e.0)?;
        alt_numeric = alt_numeric.min(t7.elapsed().as_secs_f64());
        let mut x = vec![1.0; n_eq];
        let t8 = Instant::now();
        alt.solve(&mut x).map_err(|e| e.0)?;
        alt_solve = alt_solve.min(t8.elapsed().as_secs_f64());
    }
    let (alt_w_s, alt_w_f) = alt.costs();
    // CHOLMOD's simplicial LDLᵀ (the factor updated in place), its solve (best of 5), and the
    // supernodal f32 copy of it the preconditioner solves with: build and solve (best of 5 each),
    // and the copy's solution error relative to the largest entry of the exact one.
    let mut simplicial = UpdatableCholesky::new(n_eq).map_err(|e| e.0)?;
    simplicial.factorize(&upper).map_err(|e| e.0)?;
    let (mut s_solve, mut copy_build, mut copy_solve) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut copy = None;
    for _ in 0..5 {
        let t = Instant::now();
        copy = simplicial.supernodal_copy::<f32>();
        copy_build = copy_build.min(t.elapsed().as_secs_f64());
    }
    let mut copy = copy.ok_or("no factor to copy")?;
    let mut scratch = Vec::new();
    let mut x_ref = vec![1.0; n_eq];
    let mut copy_err = 0.0;
    for _ in 0..5 {
        let mut x = vec![1.0; n_eq];
        let t = Instant::now();
        simplicial.solve(&mut x).map_err(|e| e.0)?;
        s_solve = s_solve.min(t.elapsed().as_secs_f64());
        x_ref = x;
        let mut y = vec![1.0; n_eq];
        let t = Instant::now();
        simplicial.solve_with(&mut copy, &mut y, &mut scratch).map_err(|e| e.0)?;
        copy_solve = copy_solve.min(t.elapsed().as_secs_f64());
        let scale = x_ref.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let diff = y.iter().zip(&x_ref).fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
        copy_err = diff / scale;
        if diff > 1e-4 * scale {
            return Err(format!("supernodal copy's solve off by {diff:e} of {scale:e}").into());
        }
    }
    let simplicial_line = format!(
        "\"simplicial_entries\": {}, \"simplicial_solve_seconds\": {s_solve:.6}, \"supernodes\": {}, \"supernodal_stored\": {}, \"supernodal_copy_seconds\": {copy_build:.6}, \"supernodal_solve_seconds\": {copy_solve:.6}, \"supernodal_solve_error\": {copy_err:.3e}",
        simplicial.entries(),
        copy.supernodes(),
        copy.stored()
    );
    let ordering = |o: Ordering| if o == Ordering::Amd { "amd" } else { "nested_dissection" };
    let alt_line = format!(
        "\"ordering\": \"{}\", \"other_ordering\": {{\"ordering\": \"{}\", \"first_factorization_seconds\": {alt_first:.5}, \"numeric_factorization_seconds\": {alt_numeric:.5}, \"solve_seconds\": {alt_solve:.6}, \"solve_flops\": {alt_w_s:.4e}, \"factor_flops\": {alt_w_f:.4e}}}, \"factor_flops\": {w_f:.4e}",
        ordering(factor.ordering),
        ordering(other)
    );
    println!(
        "{{{alt_line}, {simplicial_line}, \"stones\": {}, \"equations\": {n_eq}, \"upper_triplets\": {}, \"build_seconds\": {build:.4}, \"assemble_seconds\": {assemble:.4}, \"first_factorization_seconds\": {first:.5}, \"numeric_factorization_seconds\": {numeric:.5}, \"numeric_factorization_cpu_seconds\": {numeric_cpu:.5}, \"solve_seconds\": {solve:.6}, \"batch_columns\": {BATCH}, \"batch_seconds\": {batch:.6}, \"solve_flops\": {w_s:.4e}, \"factor_cost_in_solves\": {:.2}, \"factor_over_solve_time\": {:.2}, \"batch_column_cost\": {:.3}}}",
        sample.particles.len(),
        upper.len(),
        w_f / w_s,
        numeric / solve,
        (batch / solve - 1.0) / (BATCH as f64 - 1.0)
    );
    Ok(())
}

/// CPU seconds (user + system) of this process so far.
fn cpu_seconds() -> f64 {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `t` is a valid timespec the call writes to.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    if rc == 0 {
        t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
    } else {
        f64::NAN
    }
}
