//! The stress profile a run stores with its histories, read back by `demsweep history --stress-profile`.

mod runner_common;

use runner_common::demsweep;
use std::path::Path;

/// A narrow column of 60 disks with wall friction, settled; `histories` on or off.
fn run_column(dir: &Path, histories: bool) -> std::path::PathBuf {
    run_study(dir, histories, "")
}

/// The column with the study text `sweep` after its output table.
fn run_study(dir: &Path, histories: bool, sweep: &str) -> std::path::PathBuf {
    let study = dir.join("column.toml");
    let text = format!(
        "name = \"column\"\n[scene]\nparticles.count = 60\nparticles.radius = 0.005\ndomain.width = 0.05\n\
         domain.height = 0.3\nwall_material.friction = 0.5\nrun.duration = 1.5\n[output]\nframes = false\n\
         histories = {histories}\n{sweep}"
    );
    std::fs::write(&study, text).unwrap();
    let out = dir.join("out");
    let run = demsweep(&["run", study.to_str().unwrap(), "--out", out.to_str().unwrap(), "--progress", "quiet"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    out.join("column.h5")
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("demsweep_stress_profile_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The value of `column` in the first run of a summary CSV.
fn summary_value(results: &Path, column: &str) -> f64 {
    let text = std::fs::read_to_string(results.with_file_name("column_summary.csv")).unwrap();
    let mut lines = text.lines();
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = names.iter().position(|n| *n == column).unwrap();
    lines.next().unwrap().split(',').nth(k).unwrap().parse().unwrap()
}

#[test]
fn a_run_stores_its_stress_profile_from_the_floor_to_the_pile_top() {
    let dir = scratch("stored");
    let results = run_column(&dir, true);
    let out = demsweep(&["history", results.to_str().unwrap(), "r0000", "--stress-profile"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "bottom,top,stress_xx,stress_yy,stress_xy,stress_pressure,stress_deviatoric,wall_normal_stress,wall_shear_stress"
    );
    let rows: Vec<Vec<f64>> =
        lines.filter(|l| !l.is_empty()).map(|l| l.split(',').map(|c| c.parse().unwrap()).collect()).collect();
    // Bands of at most two diameters (2 cm) cover the pile without gaps, up to its highest disk top.
    let height = summary_value(&results, "pile_height");
    assert!(rows.len() as f64 >= height / 0.02, "{} bands for {height} m", rows.len());
    assert_eq!(rows[0][0], 0.0);
    assert!((rows.last().unwrap()[1] - height).abs() < 1e-12, "{text}");
    assert!(rows.windows(2).all(|w| w[0][1] == w[1][0]), "{text}");
    // Compressive, deepest at the floor; the rough walls are pressed and carry weight.
    let (bottom, top) = (&rows[0], rows.last().unwrap());
    assert!(bottom[3] > 0.0 && bottom[3] > top[3], "{text}");
    assert!(rows.iter().all(|r| r[7] >= 0.0) && rows.iter().any(|r| r[7] > 0.0 && r[8] > 0.0), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_histories_a_run_has_no_stress_profile_and_says_so() {
    let dir = scratch("off");
    let results = run_column(&dir, false);
    let out = demsweep(&["history", results.to_str().unwrap(), "r0000", "--stress-profile"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("run `r0000` has no stress profile"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn compare_keeps_the_pile_stress_as_a_metric() {
    let dir = scratch("compare");
    let results = run_study(&dir, false, "[sweep]\n\"wall_material.friction\" = [0.0, 0.5]\nreplicates = 2\n");
    let r = results.to_str().unwrap();
    let keep = ["--keep", "stress_pressure=0.5", "--keep", "stress_deviatoric=0.5"];
    let out = demsweep(&[&["compare", r, "--reference", "friction=0"][..], &keep].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("stress_pressure") && text.contains("stress_deviatoric"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn plot_and_report_chart_the_stress_profile_of_a_run_that_stores_one() {
    let dir = scratch("chart");
    for histories in [true, false] {
        let sub = dir.join(histories.to_string());
        std::fs::create_dir_all(&sub).unwrap();
        let results = run_column(&sub, histories);
        let svg = results.with_file_name("svg");
        let args = ["plot", results.to_str().unwrap(), "--format", "svg", "--out", svg.to_str().unwrap()];
        let out = demsweep(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let chart = std::fs::read_to_string(svg.join("r0000_stress_profile.svg"));
        let page = std::fs::read_to_string(results.with_file_name("column_report.html")).unwrap();
        match histories {
            true => {
                let chart = chart.unwrap();
                let labels =
                    ["Stress profile", "pressure", "deviatoric stress", "side walls", "height (m)", "stress (Pa)"];
                assert!(labels.iter().all(|l| chart.contains(l)), "{chart}");
                assert!(page.contains("Stress profile of the settled pile"), "the report's run section has it");
            }
            false => {
                assert!(chart.is_err(), "no profile stored, no chart");
                assert!(!page.contains("Stress profile of the settled pile"));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn history_writes_a_csv_file_with_each_columns_unit_in_its_sidecar() {
    let dir = scratch("csv_file");
    let results = run_column(&dir, true);
    let r = results.to_str().unwrap();
    let unit_of = |csv: &Path, name: &str| {
        let sidecar = std::fs::read_to_string(format!("{}-metadata.json", csv.display())).unwrap();
        let meta: serde_json::Value = serde_json::from_str(&sidecar).unwrap();
        let columns = meta["tableSchema"]["columns"].as_array().unwrap().clone();
        let column = columns.into_iter().find(|c| c["titles"] == name).unwrap_or_else(|| panic!("{name}: {sidecar}"));
        column.get("schema:unitText").and_then(|u| u.as_str()).unwrap_or("").to_string()
    };
    for (flags, units) in [
        (&["--stress-profile"][..], &[("bottom", "m"), ("stress_pressure", "Pa"), ("wall_shear_stress", "Pa")][..]),
        (&[][..], &[("t", "s"), ("potential", "J"), ("contacts", "")][..]),
    ] {
        let csv = dir.join(format!("table{}.csv", flags.len()));
        let printed = demsweep(&[&["history", r, "r0000"][..], flags].concat());
        let written = demsweep(&[&["history", r, "r0000", "--csv", csv.to_str().unwrap()][..], flags].concat());
        assert!(written.status.success() && written.stdout.is_empty(), "{}", String::from_utf8_lossy(&written.stderr));
        assert_eq!(std::fs::read(&csv).unwrap(), printed.stdout, "the file holds what the command prints");
        for (name, unit) in units {
            assert_eq!(unit_of(&csv, name), *unit, "{name}");
        }
    }
    // A file demsweep did not write is replaced only with --force.
    let mine = dir.join("mine.csv");
    std::fs::write(&mine, "mine").unwrap();
    let args = ["history", r, "r0000", "--stress-profile", "--csv", mine.to_str().unwrap()];
    let refused = demsweep(&args);
    assert_eq!(refused.status.code(), Some(1), "{}", String::from_utf8_lossy(&refused.stderr));
    assert_eq!(std::fs::read_to_string(&mine).unwrap(), "mine");
    assert!(demsweep(&[&args[..], &["--force"]].concat()).status.success());
    assert!(std::fs::read_to_string(&mine).unwrap().starts_with("bottom,top,"));
    let _ = std::fs::remove_dir_all(&dir);
}
