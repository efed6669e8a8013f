//! Small stress scenarios: each ends with its expected status and a clear message, never a panic.

mod bench_common;

use bench_common::*;
use demsweep::bench::stress::{Outcome, StressOptions, stress};

#[test]
fn every_stress_scenario_ends_with_its_expected_status_and_a_message() {
    let dir = fresh_dir("stress");
    let options = StressOptions { count: 40, duration: 1.0, large_count: 2000, large_steps: 10, out_dir: dir.clone() };
    let rows = stress(&options).unwrap();
    assert_eq!(rows.len(), 10);
    for r in &rows {
        println!("{}: {} ({}) {} | {}", r.scenario, r.outcome.as_str(), r.expected.as_str(), r.message, r.note);
        assert!(r.as_expected(), "{}: expected {:?}, got {:?}: {}", r.scenario, r.expected, r.outcome, r.message);
        assert!(!r.message.is_empty());
        let longest_number = r.message.split(|c: char| !c.is_ascii_digit()).map(str::len).max().unwrap_or(0);
        assert!(longest_number <= 12, "{}: a number of {longest_number} digits in {}", r.scenario, r.message);
        assert_ne!(r.outcome, Outcome::Panic);
    }
    let row = |name: &str| rows.iter().find(|r| r.scenario == name).unwrap();
    assert!(row("zero_disks").message.contains("particles.count"));
    assert!(row("paper_table1").note.starts_with("collapse"));
    // Every scenario that diverged was warned about before it ran.
    for name in ["paper_table1", "very_stiff_large_dt", "impact_50_m_per_s", "beta_50"] {
        assert!(!row(name).warnings.is_empty(), "{name} diverged without a warning");
    }
    assert!(row("large_100000").note.contains("2000 disks") && row("large_100000").note.contains("per step"));
    assert!(row("frictionless").note.contains("% saved"));
    let csv = csv_lines(&dir.join("stress.csv"));
    assert_eq!(csv.len(), 11, "names and 10 scenarios");
    assert_eq!(csv[0], "scenario,expected,outcome,as_expected,run_time,message,warnings,note");
    assert_eq!(units(&dir.join("stress.csv")).join(","), ",,,,s,,,", "the sidecar's units");
    std::fs::remove_dir_all(dir).unwrap();
}
