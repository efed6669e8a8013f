//! `bench tune` on a tiny tune file: tune against the brute-force ladder of time steps on the
//! reference's seeds, with its CSV, Markdown and charts written.

mod tune_common;

use std::path::PathBuf;

use demsweep::bench::tune::{TuneBenchOptions, tune_bench};
use tune_common::TUNE;

#[test]
fn tune_against_the_ladder_writes_its_table() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench_tune");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("tiny_bench.toml");
    std::fs::write(&file, TUNE.replace("name = \"tiny_tune\"", "name = \"tiny_bench\"")).unwrap();
    let options = TuneBenchOptions { tunes: vec![file], jobs: 2, out_dir: dir.join("out"), work_dir: dir.join("work") };
    let rows = tune_bench(&options).expect("the bench runs");
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    let run = row.rungs.iter().filter(|r| r.state != "not_run").count();
    assert_eq!(row.ladder_runs, 4 * run, "every rung that ran, on the reference's 4 seeds: {row:?}");
    assert!(!row.rungs.is_empty() && row.tune_spend > 0.0, "{row:?}");
    assert!(row.tune_ratio.is_finite(), "{row:?}");
    if row.ladder_ratio.is_finite() {
        assert_eq!(row.goal_met, row.tune_ratio <= 1.25 * row.ladder_ratio && row.tune_spend <= 20.0, "{row:?}");
    }
    for name in ["tune.csv", "tune.md", "tiny_bench_cost_vs_difference.png"] {
        let path = options.out_dir.join(if name.starts_with("tiny") { format!("tune_{name}") } else { name.into() });
        assert!(path.is_file(), "{} missing", path.display());
    }
    let md = std::fs::read_to_string(options.out_dir.join("tune.md")).unwrap();
    assert!(md.contains("| tiny_bench |"), "{md}");
}
