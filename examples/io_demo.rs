//! Writes a tiny time series with the parallel results writer: a plate of 2×2 quadrangles, two
//! triangles, two beams (lines) and a point mass, over any number of ranks, three steps.
//!
//! ```text
//!  y=2  6---7---8
//!       |   |   |          quads   q0 (0,1,4,3)  q1 (1,2,5,4)  q2 (3,4,7,6)  q3 (4,5,8,7)
//!  y=1  3---4---5---10     tris    t0 (2,9,10)   t1 (2,10,5)
//!       |   |   | / |      lines   l0 (11,0)     l1 (12,2)     (nodes 11, 12 at z = -1)
//!  y=0  0---1---2---9      point   p0 (9)
//!       x=0 x=1 x=2 x=3
//! ```
//! Output order of the cells: q0 q1 l0 t0 q2 q3 t1 l1 p0 (types interleaved on purpose).
//! Nodes are split into contiguous blocks over all ranks; cells over all ranks but the last
//! (when there are several), so that one rank owns no cell and exercises empty selections.
//!
//! Run:
//! ```text
//! cargo run --example io_demo -- /tmp/io_demo
//! OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -n 2 target/debug/examples/io_demo /tmp/io_demo
//! python3 scripts/check_xdmf.py /tmp/io_demo/demo.xdmf
//! ```
//! Expected: `demo.h5` + `demo.xdmf` with 13 nodes, 9 cells (meshio: 4 quad, 2 triangle, 3 line,
//! the point being a zero-length line, see `masonry_hpc::io`), steps at t = 0.1, 0.2,
//! 0.30000000000000004, node fields `displacement` (3), `temperature` (1), `u_rot` (6), cell
//! fields `damage` (1), `stress` (3). Rank 0 prints one line per step; every rank prints the bad
//! fields it rejected in step 0 (a wrong length; with several ranks also a name that differs
//! between ranks). Every dataset and the XDMF text are the same whatever the number of ranks.
//!
//! Optional second argument:
//! - `--abort-in-step`: `MPI_Abort` inside a fourth step (begun, one field written, never ended),
//!   as a killed job stops: the pair must still read as the three completed steps.
//! - `--abort-after-create`: stop right after writing the mesh: the index then holds the mesh
//!   alone, as one Uniform grid.

use std::path::PathBuf;

use masonry_hpc::io::{IoError, OutputMesh, ResultsWriter};
use masonry_hpc::mesh::CellKind;
use mpi::traits::Communicator;

/// All nodes of the demo mesh, in output order.
fn coords() -> Vec<[f64; 3]> {
    let mut c: Vec<[f64; 3]> = (0..9).map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0]).collect();
    c.extend([[3.0, 0.0, 0.0], [3.0, 1.0, 0.0], [0.0, 0.0, -1.0], [2.0, 0.0, -1.0]]);
    c
}

/// All cells of the demo mesh, in output order: kind, nodes, physical group.
fn cells() -> Vec<(CellKind, Vec<usize>, i32)> {
    use CellKind::*;
    vec![
        (Quad4, vec![0, 1, 4, 3], 1),
        (Quad4, vec![1, 2, 5, 4], 1),
        (Line2, vec![11, 0], 2),
        (Tri3, vec![2, 9, 10], 3),
        (Quad4, vec![3, 4, 7, 6], 1),
        (Quad4, vec![4, 5, 8, 7], 1),
        (Tri3, vec![2, 10, 5], 3),
        (Line2, vec![12, 2], 2),
        (Point1, vec![9], 4),
    ]
}

/// Block `r` of `n` items split into `parts` contiguous blocks.
fn block(n: usize, parts: usize, r: usize) -> std::ops::Range<usize> {
    (r * n / parts)..((r + 1) * n / parts)
}

fn run(world: &mpi::topology::SimpleCommunicator, dir: &std::path::Path, abort: Option<&str>) -> Result<(), IoError> {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let all_coords = coords();
    let all_cells = cells();
    let nodes = block(all_coords.len(), size, rank);
    let cell_parts = if size > 1 { size - 1 } else { 1 };
    let my_cells =
        if rank < cell_parts { block(all_cells.len(), cell_parts, rank) } else { all_cells.len()..all_cells.len() };

    let coords = &all_coords[nodes.clone()];
    let node_ids: Vec<u64> = nodes.clone().map(|i| 100 + i as u64).collect();
    let kinds: Vec<CellKind> = all_cells[my_cells.clone()].iter().map(|c| c.0).collect();
    let cell_nodes: Vec<usize> = all_cells[my_cells.clone()].iter().flat_map(|c| c.1.clone()).collect();
    let cell_ids: Vec<u64> = my_cells.clone().map(|i| 1000 + i as u64).collect();
    let groups: Vec<i32> = all_cells[my_cells.clone()].iter().map(|c| c.2).collect();
    let mesh = OutputMesh {
        node_offset: nodes.start,
        n_nodes_global: all_coords.len(),
        coords,
        node_ids: &node_ids,
        cell_offset: my_cells.start,
        n_cells_global: all_cells.len(),
        cell_kinds: &kinds,
        cell_nodes: &cell_nodes,
        cell_ids: &cell_ids,
        cell_groups: &groups,
    };
    let mut out = ResultsWriter::create(world, dir, "demo", &mesh)?;
    if abort == Some("--abort-after-create") {
        // Killed before any step: the index holds the mesh alone, as one Uniform grid.
        world.abort(3);
    }

    for (k, t) in [0.1, 0.2, 0.1 + 0.2].into_iter().enumerate() {
        out.begin_step(t)?;
        let disp: Vec<f64> = coords.iter().flat_map(|x| [x[0] * t, x[1] * t, 0.5 * t]).collect();
        out.write_node_field("displacement", 3, &disp)?;
        let temp: Vec<f64> = coords.iter().map(|x| x[0] + 10.0 * x[1] + 100.0 * t).collect();
        out.write_node_field("temperature", 1, &temp)?;
        let urot: Vec<f64> = coords.iter().flat_map(|x| [x[0], x[1], x[2], t, 2.0 * t, 3.0 * t]).collect();
        out.write_node_field("u_rot", 6, &urot)?;
        let damage: Vec<f64> = my_cells.clone().map(|c| c as f64 * t).collect();
        out.write_cell_field("damage", 1, &damage)?;
        let stress: Vec<f64> = my_cells.clone().flat_map(|c| [c as f64, t, -t]).collect();
        out.write_cell_field("stress", 3, &stress)?;
        if k == 0 {
            // Bad calls are rejected on every rank (no rank is left waiting) and the step goes on:
            // a wrong length on every rank, then a name that differs between ranks (when size > 1).
            let wrong_length = out.write_node_field("bad", 3, &[]);
            let mut results = vec![wrong_length];
            if size > 1 {
                let name = format!("bad_on_rank_{}", rank.min(1));
                results.push(out.write_node_field(&name, 1, &temp));
            }
            for r in results {
                match r {
                    Err(e) => println!("rank {rank}: rejected as expected: {e}"),
                    Ok(()) => println!("rank {rank}: a bad field was accepted"),
                }
            }
        }
        out.end_step()?;
        if rank == 0 {
            println!("step {k}: t = {t:?} written to {}", out.xdmf_path().display());
        }
    }
    if abort == Some("--abort-in-step") {
        // Simulates a run killed in the middle of a step: the pair must still show steps 0..=2.
        out.begin_step(0.4)?;
        out.write_node_field("displacement", 3, &vec![0.0; 3 * coords.len()])?;
        if rank == 0 {
            println!("aborting inside step 3 (begun, never ended)");
        }
        world.abort(3);
    }
    out.close()
}

fn main() {
    let Some(universe) = mpi::initialize() else {
        eprintln!("io_demo: MPI is already initialized");
        std::process::exit(1);
    };
    let world = universe.world();
    let dir = std::env::args().nth(1).map(PathBuf::from).unwrap_or_else(|| PathBuf::from("io_demo_out"));
    let abort = std::env::args().nth(2);
    if let Err(e) = run(&world, &dir, abort.as_deref()) {
        eprintln!("rank {}: {e}", world.rank());
        world.abort(1);
    }
}
