//! `bench tune` on a tiny tune file: tune against a two-level grid, both sharing the reference runs,
//! with its CSV, Markdown and charts written.

mod tune_common;

use std::path::PathBuf;

use demsweep::bench::tune::{TuneBenchOptions, tune_bench};
use tune_common::TUNE;

#[test]
fn tune_against_a_grid_writes_its_table() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench_tune");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("tiny_bench.toml");
    std::fs::write(&file, TUNE.replace("name = \"tiny_tune\"", "name = \"tiny_bench\"")).unwrap();
    let options = TuneBenchOptions {
        tunes: vec![file],
        levels: 2,
        jobs: 2,
        out_dir: dir.join("out"),
        work_dir: dir.join("work"),
    };
    let rows = tune_bench(&options).expect("the bench runs");
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    assert_eq!((row.levers, row.grid_points + row.grid_skipped), (2, 4));
    assert_eq!(row.grid_runs, 4 + 2 * row.grid_points, "the reference plus the seeds of every point");
    assert!(row.tune_runs <= 40 && row.tune_cost > 0.0 && row.grid_cost > 0.0);
    assert!(row.tune_ratio.is_finite(), "{row:?}");
    for name in ["tune.csv", "tune.md", "tiny_bench_cost_vs_difference.png"] {
        let path = options.out_dir.join(if name.starts_with("tiny") { format!("tune_{name}") } else { name.into() });
        assert!(path.is_file(), "{} missing", path.display());
    }
    let md = std::fs::read_to_string(options.out_dir.join("tune.md")).unwrap();
    assert!(md.contains("| tiny_bench |"), "{md}");
}
