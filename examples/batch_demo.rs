//! Dynamic batch scheduling over MPI ranks (`parallel::run_batch`), checked end to end.
//!
//!     mpirun -n 2 target/debug/examples/batch_demo 40
//!
//! Runs N tasks of uneven cost (task k sleeps (k mod 7) ms and returns k²); rank 0 prints one
//! JSON line: the results in task order, and how many tasks each rank computed.
use masonry_hpc::parallel::{run_batch, Unfinished};
use mpi::traits::Communicator;

/// A task's failure: its message.
#[derive(serde::Serialize, serde::Deserialize)]
struct Failed(String);

impl From<Unfinished> for Failed {
    fn from(u: Unfinished) -> Failed {
        Failed(u.to_string())
    }
}

#[derive(serde::Serialize, serde::Deserialize)]
struct Out {
    task: usize,
    square: u64,
    rank: i32,
}

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(40);
    let Some((universe, _)) = mpi::initialize_with_threading(mpi::Threading::Funneled) else {
        eprintln!("MPI init failed");
        std::process::exit(70);
    };
    let world = universe.world();
    let rank = world.rank();
    let result = run_batch(
        &world,
        n,
        |k| {
            std::thread::sleep(std::time::Duration::from_millis((k % 7) as u64));
            if k == 13 {
                return Err(Failed("task 13 fails on purpose".to_string()));
            }
            Ok(Out { task: k, square: (k * k) as u64, rank })
        },
        |_, _| {},
    );
    match result {
        Ok(Some(results)) => {
            let mut per_rank = vec![0usize; world.size() as usize];
            let mut tasks = Vec::new();
            let mut errors = Vec::new();
            for (k, r) in results.iter().enumerate() {
                match r {
                    Ok(o) => {
                        per_rank[o.rank as usize] += 1;
                        tasks.push(serde_json::json!([o.task, o.square]));
                    }
                    Err(Failed(e)) => errors.push(serde_json::json!([k, e])),
                }
            }
            println!(
                "{}",
                serde_json::json!({ "n": results.len(), "tasks": tasks, "errors": errors, "per_rank": per_rank })
            );
        }
        Ok(None) => {}
        Err(e) => {
            eprintln!("error: {e}");
            world.abort(1);
        }
    }
}
