//! `bench tune` on a tiny tune file: tune against the brute-force ladder over its levers on fresh
//! seeds, with its CSV, Markdown and charts written.

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
    assert!(
        (4 + 2 * run..=4 * (run + 1)).contains(&row.ladder_runs),
        "a fresh reference on 4 seeds and every rung that ran on 2 to 4: {row:?}"
    );
    let raced_out = row.rungs.iter().filter(|r| r.state == "raced_out").count();
    assert!(row.ladder_runs <= 4 + 4 * (run - raced_out) + 2 * raced_out, "{row:?}");
    if let Some((cost, setting)) = row
        .rungs
        .iter()
        .filter(|r| r.state == "equivalent")
        .map(|r| (r.cost_ratio, &r.setting))
        .min_by(|a, b| a.0.total_cmp(&b.0))
    {
        assert_eq!(row.ladder_ratio, cost, "the best is the cheapest equivalent rung ({setting}): {row:?}");
    }
    let grid: Vec<_> = row.rungs.iter().filter(|r| r.setting.starts_with("material.restitution = ")).collect();
    let restitutions: std::collections::BTreeSet<_> =
        grid.iter().map(|r| r.setting.split(',').next().unwrap().to_string()).collect();
    assert!(restitutions.len() >= 3, "the grid moves the restitution, not only the time step: {grid:?}");
    assert!(grid.iter().all(|r| r.setting.contains("integrator.time_step = ")), "{grid:?}");
    assert!(row.rungs[0].setting.starts_with("tune's answer: "), "the answer is judged on the ladder's seeds: {row:?}");
    assert_eq!(row.answer_on_ladder_state, row.rungs[0].state);
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
