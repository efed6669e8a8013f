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
    let (out_dir, work_dir) = (dir.join("out"), dir.join("work"));
    let options = TuneBenchOptions { tunes: vec![file], jobs: 2, out_dir, work_dir, ladder_seeds: 4 };
    let rows = tune_bench(&options).expect("the bench runs");
    assert_eq!(rows.len(), 1);
    let row = &rows[0];
    let run = row.rungs.iter().filter(|r| r.state != "not_run").count();
    let confirmations = row.rungs.iter().filter(|r| r.reason.contains("confirmed on 4 more fresh seeds")).count();
    assert_eq!(row.ladder_seeds, 4);
    assert!(
        (4 + 2 * run + 4 * confirmations..=4 * (run + 1 + confirmations)).contains(&row.ladder_runs),
        "a fresh reference on 4 seeds, every rung that ran on 2 to 4, each confirmation on 4: {row:?}"
    );
    let raced_out = row.rungs.iter().filter(|r| r.state == "raced_out").count();
    assert!(row.ladder_runs <= 4 + 4 * (run - raced_out + confirmations) + 2 * raced_out, "{row:?}");
    // The best is the cheapest equivalent rung whose confirmation passed; every cheaper equivalent rung
    // was tried and not confirmed.
    let equivalent = |r: &&demsweep::bench::tune_ladder::Rung| r.state == "equivalent";
    match row.rungs.iter().skip(1).find(|r| r.reason.starts_with("confirmed")) {
        Some(best) => {
            assert_eq!(row.ladder_best, best.setting, "{row:?}");
            let cheaper = row.rungs.iter().skip(1).filter(equivalent).filter(|r| r.cost_ratio < best.cost_ratio);
            assert!(cheaper.clone().all(|r| r.reason.starts_with("not confirmed")), "{row:?}");
            // Its cost on the confirmation seeds alone, which the reason names, and over both sets.
            let there = format!("(cost there {:.3})", row.ladder_confirmation_ratio);
            assert!(best.reason.contains(&there), "{there} in {row:?}");
            let both = (best.cost_ratio + row.ladder_confirmation_ratio) / 2.0;
            assert!((row.ladder_ratio - both).abs() < 1e-12, "{row:?}");
            let like = row.answer_on_ladder_ratio / row.ladder_confirmation_ratio;
            assert!(like.is_finite() && (row.like_with_like() - like).abs() < 1e-12, "{row:?}");
        }
        None => assert!(row.ladder_ratio.is_nan() && row.ladder_best == "none", "{row:?}"),
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
    assert!(md.contains("| tiny_bench |") && md.contains("| like with like |"), "{md}");
    let csv = std::fs::read_to_string(options.out_dir.join("tune.csv")).unwrap();
    assert!(csv.lines().next().unwrap().contains("ladder_confirmation_cost_ratio"), "{csv}");
    // A setting is quoted once, as RFC 4180 quotes a field with commas or quotes: a reader gets it back.
    let answer = format!("\"{}\"", row.tune_answer.replace('"', "\"\""));
    assert!(csv.contains(&format!("30,{answer},")), "{csv}");
}

#[test]
fn a_ladder_seed_count_past_its_range_is_refused_not_a_panic() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["bench", "tune", "--ladder-seeds", "1000000000000000000", "--tune", "missing.toml"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--ladder-seeds") && stderr.contains("2..=1000"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
