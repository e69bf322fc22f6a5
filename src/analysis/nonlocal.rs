//! Nonlocal averaging of the damage-driving strains of shell layers over the whole model
//! (`[analysis] nonlocal_radius` of static_nonlinear; the law at a point: `material::nonlocal`).
//!
//! # Set-up (once)
//! Every element that takes part ([`Element::enable_nonlocal`]: damage shells) lists its points
//! (position, volume weight V, layer index); the lists of all ranks are gathered on every rank,
//! and each rank keeps, for each of its own points i, its neighbours j within the radius R in the
//! same layer with the normalized weights
//!
//! ```text
//!   a_ij = α(|x_i − x_j|) V_j / Σ_k α(|x_i − x_k|) V_k,    α(r) = ⟨1 − r²/R²⟩₊²
//! ```
//! (a bucket grid of cell size R finds them; the sum runs over the points inside the model, so
//! near a boundary the average is over the part of the ball inside: the usual normalization).
//! The point's own share a_ii enters the tangent (`material::nonlocal` docs).
//!
//! # Each evaluation of the internal forces or the stiffness
//! ```text
//!   1. each rank: ε_loc = [ε_t,loc, ε_c,loc] at its points, from the current displacement
//!   2. all ranks: the values of every point (MPI_Allgatherv, rank order)
//!   3. each rank: ε̄_i = Σ_j a_ij ε_loc,j for its points, handed to its elements
//! ```
//! Step 2 replicates the whole field on every rank instead of a halo exchange with the ranks
//! whose points lie within R: simple and exact for any rank count, and cheap for models of up
//! to some 10⁵ points (the wall in shear has 9,000 at 25 × 30 cells); the church-size models
//! would need the halo exchange (neighbour ranks from the same bucket grid) before this is
//! used there. Results do not depend on the rank count beyond round-off of the sums.
use std::collections::HashMap;

use mpi::traits::CommunicatorCollectives;

use super::assembly;
use super::Discretization;
use crate::error::Error;
use crate::material::nonlocal::bell;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::Context;

/// The averaging operator of one run (module docs).
#[derive(Debug)]
pub struct NonlocalAveraging {
    /// Points per owned element (aligned with `Discretization::elements`).
    per_element: Vec<usize>,
    /// Points per rank (for the gather), and their offsets.
    counts: Vec<usize>,
    offsets: Vec<usize>,
    /// CSR neighbour lists of this rank's points: global point indices and weights a_ij.
    start: Vec<usize>,
    neighbour: Vec<u32>,
    weight: Vec<f64>,
    /// a_ii of each of this rank's points.
    self_share: Vec<f64>,
}

impl NonlocalAveraging {
    /// Collective. Switches every owned element to its nonlocal law with the regularization
    /// length `radius` and builds the averaging operator. Errors: an element whose law cannot
    /// be built for that length (named by its tag), and no element on any rank taking part.
    pub fn setup(
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
        radius: f64,
    ) -> Result<Self, Error> {
        let enabled = enable_elements(disc, mesh, model, radius);
        let (mine, per_element) = crate::parallel::agree(&ctx.comm, enabled, Error::exit_code)?;
        let all = all_gather(ctx, &mine);
        let counts: Vec<usize> = all.1.iter().map(|n| n / POINT_FIELDS).collect();
        let offsets = offsets(&counts);
        let pts: Vec<&[f64]> = all.0.chunks_exact(POINT_FIELDS).collect();
        if pts.is_empty() {
            // The same on every rank (the list is global): an agreed input error.
            return Err(no_points(radius));
        }
        let grid = BucketGrid::new(&pts, radius);
        let first = offsets[ctx.rank];
        let Neighbours { start, neighbour, weight, self_share } =
            Neighbours::of_points(&pts, &grid, first..first + counts[ctx.rank]);
        let n_global = pts.len();
        let pairs = crate::parallel::global_sum(ctx, neighbour.len() as f64);
        ctx.log.info(format!(
            "nonlocal averaging: radius {radius} m, {n_global} points, {:.1} neighbours per point on average",
            pairs / n_global as f64
        ));
        Ok(NonlocalAveraging { per_element, counts, offsets, start, neighbour, weight, self_share })
    }

    /// Collective. The averaged driving strains at the displacement `u_local` (local form of the
    /// ghosted vector) handed to the owned elements (module docs, steps 1–3).
    pub fn update(
        &self,
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
        u_local: &[f64],
    ) -> Result<(), Error> {
        let local = disc.dofs.local_index();
        let mut values = Vec::with_capacity(2 * self.self_share.len());
        let mut u_e = Vec::new();
        for (i, &c) in disc.local_cells.iter().enumerate() {
            if self.per_element[i] == 0 {
                continue;
            }
            let cell = &mesh.cells[model.cells[c].cell];
            assembly::gather(&cell.nodes, Some(u_local), Some(&local), &mut u_e);
            disc.elements[i].local_driving_strains(&u_e, &mut values).map_err(|source| Error::Element {
                tag: cell.tag,
                group: String::new(),
                source,
            })?;
        }
        debug_assert_eq!(values.len(), 2 * self.self_share.len());
        let (all, _) = all_gather(ctx, &values);
        debug_assert_eq!(all.len(), 2 * self.counts.iter().sum::<usize>());
        let first = self.offsets[ctx.rank];
        let mut averaged = vec![0.0; values.len()];
        for i in 0..self.self_share.len() {
            let (mut t, mut c) = (0.0, 0.0);
            for k in self.start[i]..self.start[i + 1] {
                let j = self.neighbour[k] as usize;
                t += self.weight[k] * all[2 * j];
                c += self.weight[k] * all[2 * j + 1];
            }
            averaged[2 * i] = t;
            averaged[2 * i + 1] = c;
        }
        debug_assert!(first + self.self_share.len() <= self.counts.iter().sum::<usize>());
        let mut at = 0;
        for (e, &n) in disc.elements.iter_mut().zip(&self.per_element) {
            if n > 0 {
                e.set_nonlocal_strains(&averaged[2 * at..2 * (at + n)], &self.self_share[at..at + n]);
                at += n;
            }
        }
        Ok(())
    }
}

/// Values per point in the gathered lists: x, y, z, V, layer.
const POINT_FIELDS: usize = 5;

/// Switches the owned elements to their nonlocal law of length `radius`: their points (x, y, z,
/// V, layer each, [`POINT_FIELDS`]) and the number of points per element; the first element
/// whose law cannot be built stops it with an input error naming its tag.
fn enable_elements(
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    radius: f64,
) -> Result<(Vec<f64>, Vec<usize>), Error> {
    let mut mine = Vec::new();
    let mut per_element = Vec::with_capacity(disc.elements.len());
    for (i, &c) in disc.local_cells.iter().enumerate() {
        match disc.elements[i].enable_nonlocal(radius) {
            Ok(points) => {
                per_element.push(points.len());
                for p in points {
                    mine.extend_from_slice(&[p.x[0], p.x[1], p.x[2], p.volume, p.layer as f64]);
                }
            }
            Err(e) => {
                let cell = &mesh.cells[model.cells[c].cell];
                return Err(Error::ElementInput {
                    tag: cell.tag,
                    group: String::new(),
                    message: format!(
                        "nonlocal_radius = {radius} m used as the regularization length of the damage law: {e}"
                    ),
                });
            }
        }
    }
    Ok((mine, per_element))
}

/// Where each rank's points start in the gathered list: the running sums of `counts`.
fn offsets(counts: &[usize]) -> Vec<usize> {
    counts
        .iter()
        .scan(0, |acc, &n| {
            let o = *acc;
            *acc += n;
            Some(o)
        })
        .collect()
}

/// The agreed input error of a model in which no element takes part.
fn no_points(radius: f64) -> Error {
    Error::Agreed(crate::parallel::Agreed {
        message: format!(
            "[analysis] nonlocal_radius = {radius}: no element of the model has a damage law that can be averaged (only shells with a `damage` material take part)"
        ),
        exit_code: 2,
        rank: 0,
    })
}

/// A bucket grid of cell size R over the points: the points within R of a point are in the 27
/// buckets around (and including) its own.
struct BucketGrid {
    /// R.
    radius: f64,
    /// The indices of the points in each bucket, in increasing order.
    buckets: HashMap<(i64, i64, i64), Vec<u32>>,
}

impl BucketGrid {
    /// The grid of cell size `radius` over `pts`.
    fn new(pts: &[&[f64]], radius: f64) -> Self {
        let mut grid = BucketGrid { radius, buckets: HashMap::new() };
        for (j, p) in pts.iter().enumerate() {
            grid.buckets.entry(grid.key(p)).or_default().push(j as u32);
        }
        grid
    }

    /// The bucket of point `p`: ⌊x/R⌋, ⌊y/R⌋, ⌊z/R⌋.
    fn key(&self, p: &[f64]) -> (i64, i64, i64) {
        let r = self.radius;
        ((p[0] / r).floor() as i64, (p[1] / r).floor() as i64, (p[2] / r).floor() as i64)
    }

    /// The candidate neighbours of `p`: the points of the 27 buckets around its own, bucket by
    /// bucket (x offset slowest, z fastest).
    fn around(&self, p: &[f64]) -> impl Iterator<Item = u32> + '_ {
        let (kx, ky, kz) = self.key(p);
        (-1..=1)
            .flat_map(move |dx| (-1..=1).flat_map(move |dy| (-1..=1).map(move |dz| (kx + dx, ky + dy, kz + dz))))
            .filter_map(|k| self.buckets.get(&k))
            .flatten()
            .copied()
    }
}

/// CSR neighbour lists of a range of points: global point indices j and weights a_ij (module
/// docs), and the own share a_ii of each point.
struct Neighbours {
    /// Where each point's list starts in `neighbour` and `weight` (one more entry: the end).
    start: Vec<usize>,
    /// Global point indices j.
    neighbour: Vec<u32>,
    /// Weights a_ij.
    weight: Vec<f64>,
    /// a_ii.
    self_share: Vec<f64>,
}

impl Neighbours {
    /// The lists of the points `range` of `pts`, found through `grid`.
    fn of_points(pts: &[&[f64]], grid: &BucketGrid, range: std::ops::Range<usize>) -> Self {
        let mut n = Neighbours { start: vec![0], neighbour: Vec::new(), weight: Vec::new(), self_share: Vec::new() };
        for i in range {
            n.push_point(pts, grid, i);
        }
        n
    }

    /// Point i's list: the points j of its layer with `α(|x_i − x_j|) V_j > 0`, their weights
    /// normalized by their sum.
    fn push_point(&mut self, pts: &[&[f64]], grid: &BucketGrid, i: usize) {
        let p = pts[i];
        let begin = self.neighbour.len();
        let mut total = 0.0;
        let mut own = 0.0;
        for j in grid.around(p) {
            let q = pts[j as usize];
            if q[4] != p[4] {
                continue;
            }
            let r = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
            let a = bell(r, grid.radius) * q[3];
            if a > 0.0 {
                self.neighbour.push(j);
                self.weight.push(a);
                total += a;
                if j as usize == i {
                    own = a;
                }
            }
        }
        for w in &mut self.weight[begin..] {
            *w /= total;
        }
        self.self_share.push(own / total);
        self.start.push(self.neighbour.len());
    }
}

/// Collective. Every rank's `values` concatenated in rank order, and each rank's count.
fn all_gather(ctx: &Context, values: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut lens = vec![0u64; ctx.size];
    ctx.comm.all_gather_into(&(values.len() as u64), &mut lens[..]);
    let counts: Vec<i32> = lens.iter().map(|&l| l as i32).collect();
    let displs: Vec<i32> = counts
        .iter()
        .scan(0, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect();
    let mut all = vec![0.0; lens.iter().sum::<u64>() as usize];
    {
        let mut partition = mpi::datatype::PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
        ctx.comm.all_gather_varcount_into(values, &mut partition);
    }
    (all, lens.iter().map(|&l| l as usize).collect())
}
