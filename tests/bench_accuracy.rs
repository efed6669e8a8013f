//! The work-precision benchmark on a tiny range: its rows, files and convergence.

mod bench_common;

use bench_common::*;
use demsweep::bench::accuracy::{AccuracyOptions, AccuracyRow, accuracy};
use demsweep::physics::config::IntegratorKind;

fn tiny(out_dir: std::path::PathBuf) -> AccuracyOptions {
    AccuracyOptions {
        coarsest_ratio: 10.0,
        finest_ratio: 40.0,
        per_halving: 1,
        impact_reference_ratio: 2000.0,
        deposition_count: 12,
        deposition_duration: 0.5,
        deposition_reference_ratio: 60.0,
        out_dir,
        ..Default::default()
    }
}

fn error(rows: &[AccuracyRow], problem: &str, scheme: IntegratorKind, ratio: f64, observable: &str) -> f64 {
    rows.iter()
        .find(|r| r.problem == problem && r.scheme == scheme && r.ratio == ratio && r.observable == observable)
        .unwrap()
        .relative_error
}

#[test]
fn tiny_accuracy_run_writes_its_files_and_impact_errors_fall_at_second_order() {
    let dir = fresh_dir("accuracy");
    let rows = accuracy(&tiny(dir.clone())).unwrap();
    // 2 schemes x 3 time steps x (3 + 3 + 6 observables).
    assert_eq!(rows.len(), 2 * 3 * 12);
    let csv = csv_lines(&dir.join("accuracy.csv"));
    assert_eq!(csv.len(), rows.len() + 1, "names, then a line per row");
    assert!(csv[0].starts_with("problem,scheme,contact_time_over_dt,time_step,run_time,"), "{}", csv[0]);
    assert!(units(&dir.join("accuracy.csv"))[..5].iter().eq(["", "", "", "s", "s"]), "the sidecar's units");
    for chart in ["impact_undamped", "impact_damped", "deposition"] {
        let png = std::fs::read(dir.join(format!("work_precision_{chart}.png"))).unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }
    let summary = std::fs::read_to_string(dir.join("accuracy.md")).unwrap();
    assert!(summary.contains("Fastest setting") && summary.contains("Chaos floor"));
    for scheme in [IntegratorKind::AdamsBashforthMoulton, IntegratorKind::VelocityVerlet] {
        for observable in ["contact_duration", "max_overlap"] {
            let coarse = error(&rows, "impact_undamped", scheme, 10.0, observable);
            let fine = error(&rows, "impact_undamped", scheme, 40.0, observable);
            println!("{scheme:?} {observable}: {coarse:.3e} at t_c/10, {fine:.3e} at t_c/40");
            assert!(fine < coarse / 6.0 && fine < 2e-3, "{scheme:?} {observable}: {coarse} -> {fine}");
        }
    }
    assert!(rows.iter().all(|r| r.run_time > 0.0));
    std::fs::remove_dir_all(dir).unwrap();
}
