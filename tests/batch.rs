//! Dynamic batch scheduling (`parallel::run_batch`) on 1, 2 and 3 ranks: every task's result
//! arrives once, in task order; a failing task is reported in its slot; with several ranks, every
//! rank computes (rank 0 too, on its worker thread).
mod common;
use common::*;

fn batch_demo() -> std::path::PathBuf {
    // Integration tests live in target/<profile>/deps; cargo test builds examples beside them.
    let exe = std::env::current_exe().unwrap();
    exe.parent().unwrap().parent().unwrap().join("examples").join("batch_demo")
}

#[test]
fn every_task_once_in_order_on_1_2_3_ranks() {
    let n = 60;
    for np in [1, 2, 3] {
        let mut cmd = std::process::Command::new("mpirun");
        cmd.args(["-n", &np.to_string(), "--oversubscribe", "--bind-to", "none"])
            .arg(batch_demo())
            .arg(n.to_string())
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
        let out = run_with_timeout(cmd, std::time::Duration::from_secs(120));
        assert!(out.status.success(), "np={np}: {}", stderr(&out));
        let v: serde_json::Value = serde_json::from_str(stdout(&out).trim()).unwrap();
        assert_eq!(v["n"], n, "np={np}: {v}");
        let tasks = v["tasks"].as_array().unwrap();
        // Task 13 fails on purpose; all others return k² in order.
        let expected: Vec<usize> = (0..n).filter(|&k| k != 13).collect();
        assert_eq!(tasks.len(), expected.len(), "np={np}");
        for (t, k) in tasks.iter().zip(&expected) {
            assert_eq!(t[0].as_u64().unwrap() as usize, *k);
            assert_eq!(t[1].as_u64().unwrap(), (k * k) as u64);
        }
        assert_eq!(v["errors"][0][0], 13);
        assert_eq!(v["errors"][0][1], "task 13 fails on purpose");
        let per_rank: Vec<u64> = v["per_rank"].as_array().unwrap().iter().map(|x| x.as_u64().unwrap()).collect();
        assert_eq!(per_rank.len(), np);
        assert!(per_rank.iter().all(|&c| c > 0), "np={np}: every rank computes: {per_rank:?}");
    }
}
