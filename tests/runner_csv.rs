//! The CSV summary: the expected columns, RFC 4180 quoting, empty cells for missing values; failed
//! and diverged runs are recorded and the sweep goes on.

mod runner_common;

use demsweep::runner::run_plan;
use demsweep::study::ParamValue;

/// Splits RFC 4180 text into records of fields.
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let (mut records, mut record, mut field) = (Vec::new(), Vec::new(), String::new());
    let mut chars = text.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => record.push(std::mem::take(&mut field)),
            (false, '\r') => {}
            (false, '\n') => {
                record.push(std::mem::take(&mut field));
                records.push(std::mem::take(&mut record));
            }
            (false, c) => field.push(c),
        }
    }
    records
}

#[test]
fn csv_summary_has_the_columns_and_quotes_messages() {
    let fine = runner_common::tiny_scene(12, 0.04);
    let mut diverging = fine.clone();
    diverging.integrator.time_step = Some(2e-3);
    let mut crowded = fine.clone();
    crowded.particles.count = 400;
    let param = |dt: f64| vec![("integrator.time_step".to_string(), ParamValue::Float(dt))];
    let plan =
        runner_common::plan("csv", vec![(param(1e-5), fine), (param(2e-3), diverging), (param(1e-5), crowded.clone())]);
    let report = run_plan(&plan, &runner_common::options(&runner_common::scratch("csv"), 2)).unwrap();
    assert_eq!(
        report.exit_code(),
        demsweep::runner::EXIT_PARTIAL,
        "a failed run makes the exit code that of a partial sweep"
    );
    assert_eq!(report.failed(), 1);

    let text = std::fs::read_to_string(&report.summary_csv).unwrap();
    assert!(report.summary_csv.ends_with("csv_summary.csv"));
    assert!(text.ends_with("\r\n"));
    let records = parse_csv(&text);
    // The names line, then the values; the units in the CSVW sidecar beside it (the swept key in its
    // unit too, docs/results.md).
    let expected = [
        ("run_id", ""),
        ("index", ""),
        ("integrator.time_step", "s"),
        ("status", ""),
        ("settle_time", "s"),
        ("steps", ""),
        ("particle_steps", ""),
        ("simulated_time", "s"),
        ("wall_time", "s"),
        ("cpu_time", "s"),
        ("time_step", "s"),
        ("final_kinetic", "J"),
        ("final_potential", "J"),
        ("final_elastic", "J"),
        ("final_dissipated", "J"),
        ("final_numerical_damping_dissipated", "J"),
        ("final_mechanical", "J"),
        ("final_ubf", ""),
        ("energy_balance_error", ""),
        ("largest_overlap_ratio", ""),
        ("physics_start_time", "s"),
        ("poured_disks", ""),
        ("refused_disks", ""),
        ("pile_height", "m"),
        ("surface_height", "m"),
        ("packing_fraction", ""),
        ("packing_fraction_interior", ""),
        ("coordination_number", ""),
        ("mechanical_coordination_number", ""),
        ("rattler_fraction", ""),
        ("floor_load_ratio", ""),
        ("floor_mean_contact_force", "N"),
        ("fabric_anisotropy", ""),
        ("fabric_direction", "rad"),
        ("normal_force_width", ""),
        ("sliding_fraction", ""),
        ("mean_overlap_ratio", ""),
        ("stress_pressure", "Pa"),
        ("stress_deviatoric", "Pa"),
        ("stress_xx", "Pa"),
        ("stress_yy", "Pa"),
        ("stress_xy", "Pa"),
        ("warnings", ""),
        ("message", ""),
        ("identity", ""),
    ];
    let col = |name: &str| expected.iter().position(|c| c.0 == name).unwrap();
    assert_eq!(records[0], expected.map(|c| c.0));
    let sidecar = report.summary_csv.with_file_name("csv_summary.csv-metadata.json");
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(sidecar).unwrap()).unwrap();
    assert_eq!(meta["url"], "csv_summary.csv");
    let columns = meta["tableSchema"]["columns"].as_array().unwrap();
    let listed: Vec<(&str, &str)> =
        columns.iter().map(|c| (c["titles"].as_str().unwrap(), c["schema:unitText"].as_str().unwrap_or(""))).collect();
    assert_eq!(listed, expected);
    let datatype = |name: &str| columns[col(name)]["datatype"].as_str().unwrap();
    assert_eq!([datatype("run_id"), datatype("steps"), datatype("settle_time")], ["string", "integer", "double"]);
    assert_eq!(records.len(), 4, "the names line, then one line per run");
    let statuses: Vec<&str> = records[1..].iter().map(|r| r[col("status")].as_str()).collect();
    assert_eq!(statuses, ["not_settled", "diverged", "error"]);
    assert_eq!(records[2][col("integrator.time_step")], "0.002");
    assert_eq!(records[2][col("time_step")], "0.002", "the time step used is a column of its own");
    assert_eq!(
        records[1][col("particle_steps")],
        (12 * 4000).to_string(),
        "12 disks x 0.04 s / 1e-5 s: {:?}",
        records[1]
    );
    assert!(records[2][col("message")].contains("limits."), "divergence explained: {:?}", records[2]);

    let placement_error = demsweep::physics::placement::generate(&crowded).unwrap_err().to_string();
    assert!(placement_error.contains(',') && placement_error.contains('"'), "needs quoting: {placement_error}");
    assert_eq!(records[3][col("message")], placement_error, "the message survives RFC 4180 quoting");
    for missing in ["settle_time", "final_kinetic", "pile_height"] {
        assert_eq!(records[3][col(missing)], "", "{missing} of a failed run is an empty cell");
    }
    assert_eq!(records[1][col("settle_time")], "", "a run that did not settle has an empty settle time");
    let steps: u64 = records[1][col("steps")].parse().unwrap();
    assert_eq!(steps, 4000);
}

#[test]
fn points_csv_and_the_points_group_agree() {
    // Restitution 0.3, 0.4, 0.5, 0.6 with two seeds each: four points of two runs.
    let plan = runner_common::sweep("points", 8);
    let report = run_plan(&plan, &runner_common::options(&runner_common::scratch("points"), 2)).unwrap();
    assert!(report.points_csv.ends_with("points_points.csv"));
    let stored = demsweep::stats::points::read(&report.results).unwrap();
    assert_eq!(stored, report.points);
    assert_eq!(stored, demsweep::stats::points::Points::new(&report.summary).table());
    assert_eq!(stored.len(), 4);

    let records = parse_csv(&std::fs::read_to_string(&report.points_csv).unwrap());
    let names: Vec<&str> = stored.columns.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(records[0].len(), names.len());
    assert_eq!(records[0], names, "the names line holds the bare names, as /points does");
    assert_eq!(records[0][..3], ["material.restitution", "n", "settled"]);
    // A statistic of a quantity with a unit is in that unit (the CSVW sidecar's); a count has none.
    let sidecar = std::fs::read_to_string(format!("{}-metadata.json", report.points_csv.display())).unwrap();
    let meta: serde_json::Value = serde_json::from_str(&sidecar).unwrap();
    let column = |name: &str| &meta["tableSchema"]["columns"][names.iter().position(|n| *n == name).unwrap()];
    let unit = |name: &str| column(name)["schema:unitText"].as_str().unwrap_or("");
    assert_eq!([unit("settle_time_ci95"), unit("pile_height_mean"), unit("settle_time_n")], ["s", "m", ""]);
    assert_eq!([&column("settle_time_n")["datatype"], &column("runs")["datatype"]], ["integer", "string"]);
    assert_eq!(records.len(), 1 + 4);
    for (i, record) in records[1..].iter().enumerate() {
        let cells: Vec<String> = stored.columns.iter().map(|c| c.data.text(i)).collect();
        assert_eq!(record, &cells, "point {i}");
    }
    let n = stored.columns.iter().position(|c| c.name == "n").unwrap();
    assert!(records[2..].iter().all(|r| r[n] == "2"));
}
