//! `demsweep check` and `demsweep plan` as a user runs them.

mod runner_common;
mod study_support;

use runner_common::{demsweep, text};
use study_support::{SMALL_SCENE, StudyDir};

#[test]
fn check_accepts_a_valid_study() {
    let dir = StudyDir::new("cli-ok");
    let study = dir.write("ok.toml", &format!("{SMALL_SCENE}[sweep]\n\"material.friction\" = [0.1, 0.3, 0.5, 0.7]\n"));
    let out = demsweep(&["check", study.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "ok: 4 runs (1 warning above)\n");
    assert!(
        text(&out.stderr).contains("(run r0000 and 3 more runs): predicted: an impact at"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn check_prints_the_warnings_it_can_predict_without_failing() {
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/paper_table1.toml");
    let out = demsweep(&["check", study]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "ok: 1 run (4 warnings above)\n");
    let stderr = text(&out.stderr);
    for expected in [
        "paper_table1.toml:22:1: scene.material.youngs_modulus (run r0000): 20000 Pa is implausible for this key",
        "units are SI: did you mean 2e10 Pa (20000 MPa)",
        "paper_table1.toml:22:1: scene.material.youngs_modulus: value 20000 (run r0000): predicted: an impact at 3.37 m/s would overlap 0.8144 radii",
        "paper_table1.toml:22:1: scene.material.youngs_modulus: value 20000 (run r0000): predicted: the settled pile's weight would press the bottom disks 8.528 radii into the floor",
    ] {
        assert!(stderr.lines().any(|l| l.starts_with("warning: ") && l.contains(expected)), "{expected}\n{stderr}");
    }
}

#[test]
fn check_reports_every_problem_and_exits_2() {
    let dir = StudyDir::new("cli-bad");
    let bad = "[scene]\nparticles.count = 20\nintegrator.time_step = -1e-5\n[sweep]\n\"material.friction\" = []\n";
    let study = dir.write("bad.toml", bad);
    let out = demsweep(&["check", study.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let stderr = text(&out.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 3, "{stderr}");
    assert!(
        lines[0].ends_with("bad.toml:3:12: scene.integrator.time_step: must be a finite number > 0, got -0.00001"),
        "{stderr}"
    );
    assert!(lines[1].ends_with("bad.toml:5:1: sweep.\"material.friction\": an axis needs at least one value, got []"));
    assert!(lines[2].ends_with("bad.toml: 2 problem(s); nothing was run"));
}

#[test]
fn plan_lists_runs_parameters_and_cost() {
    let dir = StudyDir::new("cli-plan");
    let study = dir.write("p.toml", &format!("{SMALL_SCENE}[sweep]\n\"material.friction\" = [0.1, 0.5]\n"));
    let out = demsweep(&["plan", study.to_str().unwrap(), "--cores", "2"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].starts_with("study p ("), "{stdout}");
    assert!(lines[0].ends_with(", 2 runs"));
    let header: Vec<&str> = lines[1].split_whitespace().collect();
    assert_eq!(header, ["id", "material.friction", "disks", "time_step", "steps", "particle-steps"]);
    assert_eq!(lines[3].split_whitespace().collect::<Vec<_>>(), ["r0001", "0.5", "20", "1.000e-5", "1000", "2.000e4"]);
    assert!(lines[4].starts_with("total 4.000e4 particle-steps"), "{stdout}");
    assert!(lines[4].ends_with("on 2 cores"), "{stdout}");
}

#[test]
fn every_command_explains_itself_with_an_example() {
    for args in [&["--help"][..], &["check", "--help"], &["plan", "--help"]] {
        let out = demsweep(args);
        assert_eq!(out.status.code(), Some(0));
        let help = text(&out.stdout);
        assert!(help.contains("Example"), "{args:?}: {help}");
        assert!(help.contains("demsweep"), "{args:?}: {help}");
    }
}

#[test]
fn run_on_a_tune_file_points_to_tune() {
    let tune = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/tune_deposition.toml");
    let out = demsweep(&["run", tune, "--out", std::env::temp_dir().join("demsweep-run-tune").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let expected = format!(
        "error: {tune} is a tune file ([levers], [keep], [search]), not a study: run it with `demsweep tune {tune}`"
    );
    assert_eq!(text(&out.stderr).trim_end(), expected);
}

#[test]
fn strict_makes_warnings_errors_for_check_and_run() {
    let dir = StudyDir::new("cli-strict");
    let study = dir.write("soft.toml", &format!("{SMALL_SCENE}[sweep]\n\"material.friction\" = [0.1, 0.3]\n"));
    let study = study.to_str().unwrap();
    assert_eq!(demsweep(&["check", study]).status.code(), Some(0), "warnings alone pass");
    let out = dir.path.join("out");
    for args in [vec!["check", study, "--strict"], vec!["run", study, "--strict", "--out", out.to_str().unwrap()]] {
        let refused = demsweep(&args);
        let stderr = text(&refused.stderr);
        assert_eq!(refused.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains("soft.toml: 1 warning above, errors under --strict; nothing was run"), "{stderr}");
        assert!(refused.stdout.is_empty(), "{args:?}");
    }
    assert!(!out.exists(), "a refused run writes nothing");
}

#[test]
fn check_states_what_a_size_distribution_gives_and_placement_draws_it() {
    let dir = StudyDir::new("cli-sizes");
    let scene = "[scene]\nparticles.count = 90\ndomain.width = 0.3\ndomain.height = 0.3\nrun.duration = 0.01\n";
    let mix = "particles.size_distribution = { kind = \"discrete\", radii = [0.004, 0.006], fractions = [1, 3] }\n";
    let study = dir.write("mix.toml", &format!("{scene}{mix}[sweep]\nreplicates = 2\n"));
    let out = demsweep(&["check", study.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let expected = "particles.size_distribution: 90 disks: 23 of radius 0.004 m, 67 of radius 0.006 m";
    assert!(text(&out.stdout).contains(expected), "{}", text(&out.stdout));
    let plan = study_support::plan("sizes", &format!("{scene}{mix}[sweep]\nreplicates = 2\n"));
    for run in &plan.runs {
        let disks = demsweep::physics::placement::generate(&run.scene).unwrap();
        assert_eq!(disks.iter().filter(|d| d.r == 0.004).count(), 23, "{}", run.id);
        assert_eq!(disks.iter().filter(|d| d.r == 0.006).count(), 67, "{}", run.id);
    }
    let normal =
        "particles.size_distribution = { kind = \"normal\", mean = 0.005, std = 0.001, min = 0.003, max = 0.007 }\n";
    let study = dir.write("normal.toml", &format!("{scene}{normal}"));
    let out = demsweep(&["check", study.to_str().unwrap()]);
    let stdout = text(&out.stdout);
    assert!(stdout.contains("particles.size_distribution: 90 disks, normal: with placement seed 12345"), "{stdout}");
    // A placement file keeps its radii: check states no draw from the distribution, and warns of it.
    dir.write("pile.csv", "x,y,r\n0.05,0.05,0.01\n0.15,0.05,0.02\n");
    let file = "placement.kind = \"file\"\nplacement.file = \"pile.csv\"\n";
    let out = demsweep(&["check", dir.write("file.toml", &format!("{scene}{mix}{file}")).to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(!text(&out.stdout).contains("particles.size_distribution:"), "{}", text(&out.stdout));
    assert!(
        text(&out.stderr).contains("scene.particles.size_distribution (run r0000): draws no radius"),
        "{}",
        text(&out.stderr)
    );
    let both = dir.write("both.toml", &format!("{scene}particles.radius_max = 0.02\n{normal}"));
    let out = demsweep(&["check", both.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("give either particles.radius_max or particles.size_distribution"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn a_study_sweeps_the_placement_kind_and_check_says_how_full_a_dropped_pile_is() {
    let dir = StudyDir::new("cli-dropped");
    let sweep = "[sweep]\n\"placement.kind\" = [\"random\", \"dropped\"]\nreplicates = 2\n";
    let study = dir.write("kinds.toml", &format!("{SMALL_SCENE}{sweep}"));
    let out = demsweep(&["check", study.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let note =
        stdout.lines().find(|l| l.starts_with("placement.kind = \"dropped\": 20 disks rest up to ")).expect(&stdout);
    assert!(note.ends_with("(placement seed 12345, run r0002)"), "one note for both seeds: {stdout}");
    let results = dir.path.join("out");
    let run = demsweep(&["run", study.to_str().unwrap(), "--out", results.to_str().unwrap(), "--progress", "quiet"]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let summary = std::fs::read_to_string(results.join("kinds_summary.csv")).unwrap();
    let mut lines = summary.lines().map(|l| l.split(',').collect::<Vec<_>>());
    let names = lines.next().unwrap();
    let column = |name: &str| names.iter().position(|n| *n == name).unwrap();
    let (kind, potential) = (column("placement.kind"), column("final_potential"));
    let rows: Vec<(String, f64)> = lines.map(|row| (row[kind].to_string(), row[potential].parse().unwrap())).collect();
    let kinds: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert_eq!(kinds, ["random", "random", "dropped", "dropped"]);
    // Dropped disks start on the floor: after 10 ms, far less height (potential energy) than falling ones.
    assert!(rows[2].1.max(rows[3].1) < 0.2 * rows[0].1.min(rows[1].1), "{rows:?}");
}
