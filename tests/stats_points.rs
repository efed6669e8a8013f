//! Statistics over replicates with known answers: points of a constructed summary, the three TOST
//! outcomes, ratio intervals, and `compare` choosing and refusing points and metrics.

use demsweep::output::SummaryRow;
use demsweep::output::SummaryTable;
use demsweep::output::table::ColumnData;
use demsweep::physics::RunStatus;
use demsweep::physics::quantity::{self, FINAL_VALUE_COUNT};
use demsweep::stats::compare::{self, Tolerance};
use demsweep::stats::points::Points;
use demsweep::stats::{Decision, equivalence, ratio_interval, student_t_quantile};
use demsweep::study::ParamValue;

/// t(0.975, 2) and t(0.975, 3) from the tables.
const T975_2: f64 = 4.302_653;
const T975_3: f64 = 3.182_446;

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance
}

/// A settled run at restitution `e`, seed `seed`, with this settle time, packing fraction and steps.
fn row(index: usize, e: f64, seed: i64, settle: Option<f64>, packing: f64, steps: u64) -> SummaryRow {
    let parameters = vec![
        ("material.restitution".to_string(), ParamValue::Float(e)),
        ("placement.seed".to_string(), ParamValue::Int(seed)),
    ];
    let mut row = SummaryRow::failed(index, &format!("r{index:04}"), &parameters, "");
    row.status = if settle.is_some() { RunStatus::Settled } else { RunStatus::NotSettled };
    row.message.clear();
    row.settle_time = settle;
    row.steps = steps;
    row.wall_time = steps as f64 * 1e-4;
    row.particle_steps = steps * 300;
    row.final_values = [0.0; FINAL_VALUE_COUNT];
    row.final_values[quantity::final_value_declarations().position(|q| q.name == "packing_fraction").unwrap()] =
        packing;
    row
}

/// Two points: e = 0.5 (3 settled seeds, one failed run) and e = 0.9 (4 seeds, one not settled).
fn summary() -> SummaryTable {
    let mut failed = SummaryRow::failed(
        3,
        "r0003",
        &[
            ("material.restitution".to_string(), ParamValue::Float(0.5)),
            ("placement.seed".to_string(), ParamValue::Int(4)),
        ],
        "boom",
    );
    failed.wall_time = 0.0;
    SummaryTable::from_rows(&[
        row(0, 0.5, 1, Some(0.40), 0.80, 1000),
        row(1, 0.5, 2, Some(0.50), 0.82, 1200),
        row(2, 0.5, 3, Some(0.60), 0.84, 1400),
        failed,
        row(4, 0.9, 1, Some(1.0), 0.70, 2000),
        row(5, 0.9, 2, Some(2.0), 0.70, 2000),
        row(6, 0.9, 3, Some(3.0), 0.70, 2000),
        row(7, 0.9, 4, None, 0.70, 2000),
    ])
}

fn floats(table: &SummaryTable, name: &str) -> Vec<f64> {
    match &table.column(name).unwrap_or_else(|| panic!("no column {name}")).data {
        ColumnData::Float(v) => v.clone(),
        ColumnData::Int(v) => v.iter().map(|&i| i as f64).collect(),
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn points_of_a_constructed_summary_have_known_statistics() {
    let summary = summary();
    let points = Points::new(&summary);
    assert_eq!(points.len(), 2);
    assert_eq!(points.label(1), "material.restitution=0.9");
    let table = points.table();
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names[..14],
        [
            "material.restitution",
            "n",
            "settled",
            "not_settled",
            "diverged",
            "error",
            "unsettled",
            "settle_time_n",
            "settle_time_mean",
            "settle_time_std",
            "settle_time_ci95",
            "settle_time_min",
            "settle_time_max",
            "steps_n"
        ],
        "the swept values first, no seed column"
    );
    assert_eq!(floats(&table, "material.restitution"), [0.5, 0.9]);
    assert_eq!(floats(&table, "n"), [4.0, 4.0]);
    assert_eq!(floats(&table, "settled"), [3.0, 3.0]);
    assert_eq!(floats(&table, "not_settled"), [0.0, 1.0]);
    assert_eq!(floats(&table, "error"), [1.0, 0.0]);
    assert_eq!(floats(&table, "unsettled"), [1.0, 1.0], "the failed run and the one that did not settle");
    // Settle time over settled runs: 0.4, 0.5, 0.6 (std 0.1) and 1, 2, 3 (std 1).
    let mean = floats(&table, "settle_time_mean");
    assert!(close(mean[0], 0.5, 1e-15) && close(mean[1], 2.0, 1e-15));
    let std = floats(&table, "settle_time_std");
    assert!(close(std[0], 0.1, 1e-15) && close(std[1], 1.0, 1e-15));
    let ci = floats(&table, "settle_time_ci95");
    assert!(close(ci[0], T975_2 * 0.1 / 3f64.sqrt(), 1e-7), "{}", ci[0]);
    assert!(close(ci[1], T975_2 / 3f64.sqrt(), 1e-6), "{}", ci[1]);
    assert_eq!(floats(&table, "settle_time_min"), [0.4, 1.0]);
    assert_eq!(floats(&table, "settle_time_max"), [0.6, 3.0]);
    // The failed run's placeholder values (steps 0) are left out of the metrics.
    assert_eq!(floats(&table, "steps_n"), [3.0, 4.0]);
    assert_eq!(floats(&table, "steps_mean"), [1200.0, 2000.0]);
    assert_eq!(floats(&table, "steps_std"), [200.0, 0.0]);
    assert_eq!(floats(&table, "packing_fraction_ci95")[1], 0.0, "no spread, no interval");
    let runs = table.column("runs").unwrap();
    assert_eq!(
        (runs.data.text(0), runs.data.text(1)),
        ("r0000 r0001 r0002 r0003".into(), "r0004 r0005 r0006 r0007".into())
    );
    // index and the seed are no metrics.
    assert!(table.column("index_mean").is_none() && table.column("placement.seed_mean").is_none());
    assert!(table.column("warnings_mean").is_some());
    // Four seeds: t(0.975, 3).
    assert!(close(points.describe(1, "packing_fraction").half_width_95, 0.0, 0.0));
    assert!(close(student_t_quantile(0.975, 3.0), T975_3, 1e-6));
}

#[test]
fn tost_decides_equivalent_different_and_undecided() {
    let reference = [1.0, 1.1, 0.9, 1.0];
    // mean 0, s² = 0.02/3 per group: se = √(2 · 0.02/3 / 4), Welch df = 6 (equal variances and n).
    let se = (2.0 * 0.02 / 3.0 / 4.0f64).sqrt();
    let t95_6 = 1.943_180;

    let same = equivalence(&reference, &[1.02, 1.12, 0.92, 1.02], 0.2);
    assert!(close(same.difference, 0.02, 1e-12));
    assert!(close(same.low, 0.02 - t95_6 * se, 1e-6) && close(same.high, 0.02 + t95_6 * se, 1e-6));
    assert_eq!((same.decision, same.seeds_needed), (Decision::Equivalent, None));

    let shifted = equivalence(&reference, &[1.5, 1.6, 1.4, 1.5], 0.2);
    assert!(shifted.low >= 0.2, "{shifted:?}");
    assert_eq!((shifted.decision, shifted.seeds_needed), (Decision::Different, None));
    let below = equivalence(&reference, &[0.5, 0.6, 0.4, 0.5], 0.2);
    assert_eq!(below.decision, Decision::Different);

    // Within the margin on average, but the interval (±0.158) crosses +0.1.
    let unsure = equivalence(&reference, &[1.05, 1.15, 0.95, 1.05], 0.1);
    assert!(unsure.low < 0.1 && unsure.high > 0.1 && unsure.low > -0.1, "{unsure:?}");
    assert_eq!(unsure.decision, Decision::Undecided);
    // Pooled s = √(0.02/3); the gap to the margin is 0.05: n seeds decide once
    // t(0.95, 2n − 2) · s · √(2/n) < 0.05.
    let s = (0.02f64 / 3.0).sqrt();
    let half = |n: usize| student_t_quantile(0.95, (2 * n - 2) as f64) * s * (2.0 / n as f64).sqrt();
    let n = unsure.seeds_needed.expect("an estimate");
    assert!(half(n) < 0.05 && half(n - 1) >= 0.05, "n = {n}");
    assert_eq!(n, 16, "t(0.95, 30) · 0.0816 · √(2/16) = 0.0490 < 0.05 <= 0.0507 at 15");

    let alone = equivalence(&[1.0], &reference, 0.5);
    assert_eq!((alone.decision, alone.seeds_needed), (Decision::Undecided, None));
    assert!(alone.low.is_nan() && close(alone.difference, 0.0, 1e-15));
}

#[test]
fn ratio_interval_by_the_delta_method_on_logs() {
    let exact = ratio_interval(&[2.0, 2.0, 2.0], &[3.0, 3.0]);
    assert_eq!((exact.ratio, exact.low, exact.high), (1.5, 1.5, 1.5));
    // Equal relative spread and n: the interval is symmetric in log around ln(ratio).
    let r = ratio_interval(&[9.0, 10.0, 11.0], &[18.0, 20.0, 22.0]);
    assert!(close(r.ratio, 2.0, 1e-15));
    assert!(close((r.high / r.ratio).ln(), (r.ratio / r.low).ln(), 1e-12));
    // se² = 2 · (0.1² / 3) with ν = 4 (Welch, equal terms).
    let half = student_t_quantile(0.975, 4.0) * (2.0 * 0.01 / 3.0f64).sqrt();
    assert!(close(r.high, 2.0 * half.exp(), 1e-9), "{r:?}");
    assert!(ratio_interval(&[1.0], &[2.0, 3.0]).low.is_nan());
}

#[test]
fn compare_notes_points_whose_runs_are_copies_of_one_run() {
    let copies = SummaryTable::from_rows(&[
        row(0, 0.5, 1, Some(0.40), 0.80, 1000),
        row(1, 0.5, 2, Some(0.50), 0.82, 1200),
        row(2, 0.9, 1, Some(1.0), 0.70, 2000),
        row(3, 0.9, 2, Some(1.0), 0.70, 2000),
        row(4, 0.9, 3, Some(1.0), 0.70, 2000),
    ]);
    let comparison = compare::compare(&Points::new(&copies), "restitution=0.5", &[]).unwrap();
    assert_eq!(comparison.notes.len(), 1, "{:?}", comparison.notes);
    assert!(
        comparison.notes[0].starts_with("the runs of material.restitution=0.9 are copies of one run"),
        "{}",
        comparison.notes[0]
    );
    let comparison = compare::compare(&Points::new(&summary()), "restitution=0.5", &[]).unwrap();
    assert!(comparison.notes.is_empty(), "runs that differ somewhere are no copies: {:?}", comparison.notes);
}

#[test]
fn compare_finds_points_and_refuses_unknown_ones() {
    let table = summary();
    let points = Points::new(&table);
    assert_eq!(compare::find_point(&points, "material.restitution=0.9"), Ok(1));
    assert_eq!(compare::find_point(&points, "restitution=0.5"), Ok(0));
    assert_eq!(compare::find_point(&points, "r0005"), Ok(1), "a run id names its point");
    let err = compare::find_point(&points, "restitution=0.7").unwrap_err().to_string();
    assert!(err.starts_with("no point has restitution=0.7; the points are:\n  material.restitution=0.5\n"), "{err}");
    let err = compare::find_point(&points, "friction=0.5").unwrap_err().to_string();
    assert!(err.contains("`friction` is not a swept parameter; the swept parameters are: material.restitution"));

    let keep = [Tolerance { metric: "bogus".into(), relative: 0.1 }];
    let err = compare::compare(&points, "r0000", &keep).unwrap_err().to_string();
    assert!(err.starts_with("`bogus`: not a per-run quantity or numeric summary column; the metrics of this file are: settle_time, steps,"), "{err}");
    assert_eq!(
        "x=0".parse::<Tolerance>().unwrap_err().to_string(),
        "the tolerance of `x` must be a positive relative tolerance, got 0"
    );

    // By default the pile metrics, and cost in particle-steps.
    let comparison = compare::compare(&points, "restitution=0.5", &[]).unwrap();
    let kept: Vec<&str> = comparison.kept.iter().map(|k| k.tolerance.metric.as_str()).collect();
    assert_eq!(kept, quantity::kept_by_default().map(|(m, _)| m).collect::<Vec<_>>());
    assert_eq!((comparison.notes.len(), comparison.cost_column.as_str()), (0, "particle_steps"));
    assert!(close(comparison.points[0].cost.ratio, 2000.0 / 1200.0, 1e-12));

    // A file written before the pile metrics and particle-steps: the fallback, said in a note.
    let mut old = summary();
    let newer: Vec<&str> = quantity::kept_by_default().map(|(m, _)| m).chain(["particle_steps"]).collect();
    old.columns.retain(|c| !newer.contains(&c.name.as_str()));
    let points = Points::new(&old);
    let comparison = compare::compare(&points, "restitution=0.5", &[]).unwrap();
    let kept: Vec<&str> = comparison.kept.iter().map(|k| k.tolerance.metric.as_str()).collect();
    assert_eq!(kept, ["packing_fraction", "pile_height"]);
    assert!(comparison.notes[0].contains("keeping packing_fraction, pile_height instead"));
    assert_eq!(comparison.cost_column, "steps");
    let other = &comparison.points[0];
    assert_eq!((other.point, other.n), (1, 4));
    // Packing 0.70 against 0.82 ± 0.0082: clearly different.
    assert!(close(comparison.kept[0].margin, 0.0082, 1e-12));
    assert_eq!(other.tests[0].decision, Decision::Different);
    assert!(!other.acceptable());
    assert!(close(other.cost.ratio, 2000.0 / 1200.0, 1e-12));
    let table = comparison.table(&points);
    assert_eq!(table.len(), 2, "one row per other point and kept metric");

    // Read back from an old file, the newer columns exist but hold no value: the same fallback.
    let mut unmeasured = summary();
    for column in unmeasured.columns.iter_mut().filter(|c| quantity::kept_by_default().any(|(m, _)| m == c.name)) {
        column.data = ColumnData::Float(vec![f64::NAN; column.data.len()]);
    }
    let comparison = compare::compare(&Points::new(&unmeasured), "restitution=0.5", &[]).unwrap();
    assert_eq!(comparison.kept[0].tolerance.metric, "packing_fraction");
    assert_eq!(table.column("decision").unwrap().data.text(0), "different");
}
