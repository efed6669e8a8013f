//! `demsweep export`: each format read back by the program it is for (VTK's own XML readers, LAMMPS
//! itself, demsweep's placement reader), a settled pile restarted from its CSV, and the errors.

mod python_env;
mod runner_common;

use std::path::{Path, PathBuf};
use std::process::Command;

use demsweep::export::{ExportRequest, Format, export};
use demsweep::output::{reader, stored};
use demsweep::physics::config::PlacementKind;
use demsweep::physics::quantity::PILE_METRICS;
use demsweep::physics::record::{RunStatus, Snapshot};
use demsweep::physics::run_scene;
use demsweep::physics::simulation::Control;
use demsweep::study::ParamValue;

/// A results file of two small piles deposited for `duration` (s) with frames (runs `r000`, `r001`), and a third run
/// `r002` that fails (too many disks for its box: no final state).
fn results(test: &str, duration: f64) -> (PathBuf, PathBuf) {
    let dir = runner_common::scratch(test);
    let runs = (0..3)
        .map(|i| {
            let mut scene = runner_common::tiny_scene(if i == 2 { 400 } else { 30 }, duration);
            scene.placement.seed = 7 + i as u64;
            scene.run.frame_times = vec![0.0, 0.1, 0.2];
            (vec![("placement.seed".to_string(), ParamValue::Int(7 + i as i64))], scene)
        })
        .collect();
    let plan = runner_common::plan(test, runs);
    let report = demsweep::runner::run_plan(&plan, &runner_common::options(&dir, 2)).unwrap();
    (report.results, dir)
}

fn request(results: &Path, format: Format, runs: &[&str], out: PathBuf) -> ExportRequest {
    ExportRequest {
        results: results.to_path_buf(),
        format,
        runs: runs.iter().map(|s| s.to_string()).collect(),
        frames: false,
        out,
        force: false,
    }
}

/// The stored final state of a run.
fn final_state(results: &Path, id: &str) -> Snapshot {
    let file = reader::open(results).unwrap();
    let rows = reader::rows(&file, results).unwrap();
    let row = rows.iter().find(|r| r.id == id).unwrap();
    stored::read_run(&file, results, row).unwrap().final_state.unwrap()
}

#[test]
fn vtk_files_read_by_vtk_equal_the_results_file() {
    let (results, dir) = results("export_vtk", 0.5);
    let out = dir.join("vtk");
    let mut vtk = request(&results, Format::Vtk, &["r000"], out.clone());
    vtk.frames = true;
    let summary = export(&vtk).unwrap();
    assert_eq!(summary.runs, 1);
    assert!(!final_state(&results, "r000").contacts.is_empty(), "the pile has contacts to export");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/interop/check_vtk.py");
    let group = reader::find_run(&reader::open(&results).unwrap(), &results, "r000").unwrap();
    let check = python_env::python(script).arg(&out).arg(&results).arg(group).arg("r000").output();
    let check = check.expect("run the tests' Python");
    let text = format!("{}{}", String::from_utf8_lossy(&check.stdout), String::from_utf8_lossy(&check.stderr));
    assert!(check.status.success(), "VTK check failed (scripts/test.sh installs vtk and h5py):\n{text}");
    assert!(text.contains("4 states of r000 checked, 0 problems"), "{text}");
}

/// LAMMPS as Debian installs it (`lmp`), or `lmp_serial`.
fn lammps() -> Command {
    let found = ["lmp", "lmp_serial"].into_iter().find(|name| Command::new(name).arg("-h").output().is_ok());
    Command::new(found.expect("no LAMMPS (lmp): scripts/test.sh installs Debian's lammps package"))
}

#[test]
fn lammps_reads_the_data_file_and_runs_from_it() {
    let (results, dir) = results("export_lammps", 0.5);
    let out = dir.join("lammps");
    export(&request(&results, Format::Lammps, &["r001"], out.clone())).unwrap();
    let state = final_state(&results, "r001");
    let scene = runner_common::tiny_scene(30, 0.5);
    let input = format!(
        "dimension 2\nunits si\natom_style sphere\nboundary f f p\ncomm_modify vel yes\n\
         read_data r001_final.data\n\
         write_dump all custom read.dump id x y radius mass vx vy omegaz modify sort id format float %.17g\n\
         pair_style gran/hooke/history 1e4 NULL 10 NULL 0.5 1\npair_coeff * *\n\
         fix move all nve/sphere disc\nfix plane all enforce2d\nfix weight all gravity 9.81 vector 0 -1 0\n\
         fix floor all wall/gran hooke/history 1e4 NULL 10 NULL 0.5 1 yplane 0 NULL\n\
         fix sides all wall/gran hooke/history 1e4 NULL 10 NULL 0.5 1 xplane 0 {}\n\
         timestep 1e-6\nthermo_style custom step atoms\nthermo 100\nrun 500\n",
        scene.domain.width
    );
    std::fs::write(out.join("in.restart"), input).unwrap();
    let run = lammps().args(["-in", "in.restart", "-log", "lammps.log"]).current_dir(&out).output().unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success(), "LAMMPS failed:\n{text}");
    assert!(!text.contains("Lost atoms"), "{text}");
    let n = state.x.len();
    let last_thermo = text.lines().rfind(|l| l.trim().starts_with("500 ")).expect("a thermo line at step 500");
    assert_eq!(last_thermo.split_whitespace().nth(1), Some(n.to_string().as_str()), "every atom kept:\n{text}");
    let dump = std::fs::read_to_string(out.join("read.dump")).unwrap();
    let atoms: Vec<Vec<f64>> = dump
        .lines()
        .skip_while(|l| !l.starts_with("ITEM: ATOMS"))
        .skip(1)
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(atoms.len(), n);
    let (density, thickness) = (scene.material.density, scene.particles.thickness);
    for (i, atom) in atoms.iter().enumerate() {
        assert_eq!(atom[0], (i + 1) as f64);
        assert_eq!([atom[1], atom[2], atom[3]], [state.x[i], state.y[i], state.r[i]], "atom {i}");
        let mass = density * std::f64::consts::PI * state.r[i] * state.r[i] * thickness;
        assert!((atom[4] / mass - 1.0).abs() < 1e-12, "atom {i}: mass {} vs {mass}", atom[4]);
        assert_eq!([atom[5], atom[6], atom[7]], [state.vx[i], state.vy[i], state.omega[i]], "atom {i}");
    }
}

#[test]
fn a_settled_pile_restarts_from_its_csv_settled_with_its_metrics() {
    let (results, dir) = results("export_restart", 3.0);
    let out = dir.join("csv");
    export(&request(&results, Format::Csv, &["r000"], out.clone())).unwrap();
    let file = reader::open(&results).unwrap();
    let rows = reader::rows(&file, &results).unwrap();
    let first = stored::read_run(&file, &results, &rows[0]).unwrap();
    assert_eq!(rows[0].status, RunStatus::Settled);
    let csv = out.join("r000_final.csv");
    let disks = demsweep::study::initial_csv::read(&csv, 1.0).unwrap();
    let state = first.final_state.unwrap();
    assert_eq!(disks.len(), state.x.len());
    for (i, d) in disks.iter().enumerate() {
        assert_eq!(
            [d.x, d.y, d.r, d.vx, d.vy, d.omega],
            [state.x[i], state.y[i], state.r[i], state.vx[i], state.vy[i], state.omega[i]]
        );
    }
    let mut scene = first.scene.clone();
    scene.placement.kind = PlacementKind::File;
    scene.placement.file = Some(csv.display().to_string());
    let restarted = run_scene(&scene, Some(disks.clone()), &mut |_| Control::Continue).unwrap();
    let hold = scene.settle.hold_time;
    assert_eq!(restarted.status, RunStatus::Settled, "{:?}", restarted.message);
    assert!(restarted.settle_time.unwrap() <= hold, "settled from the start: {:?} s", restarted.settle_time);
    // The validity prediction sees disks at rest on each other (their speed, plus the floor of the
    // estimate: a fall through one radius), not the fall from the box top of a generated placement.
    let original = run_scene(&first.scene, None, &mut |_| Control::Continue).unwrap();
    let r_max = state.r.iter().copied().fold(0.0, f64::max);
    let fastest = (0..state.x.len()).map(|i| state.vx[i].hypot(state.vy[i])).fold(0.0, f64::max);
    let at_rest = fastest + (2.0 * 9.81 * r_max).sqrt();
    let impact = restarted.stability.impact_speed;
    assert!(impact <= at_rest * (1.0 + 1e-9), "{impact} m/s, disks at rest {at_rest} m/s");
    assert!(impact < 0.5 * original.stability.impact_speed, "{impact} vs {} m/s", original.stability.impact_speed);
    // Geometry is kept to the solver's drift; contacts may form or open at the threshold; forces
    // redistribute, as the tangential springs (contact history, in no placement file) start from zero.
    let n = state.x.len() as f64;
    let metrics = PILE_METRICS.iter().zip(original.pile.values()).zip(restarted.pile.values());
    for ((metric, &a), &b) in metrics {
        let name = metric.name;
        let tolerance = match name {
            "pile_height" | "packing_fraction" | "packing_fraction_interior" => 1e-3 * a.abs(),
            "coordination_number" | "mechanical_coordination_number" => 4.0 / n,
            "rattler_fraction" | "sliding_fraction" => 2.0 / n,
            _ => 0.25 * a.abs(),
        };
        println!("{name}: {a} → {b} (tolerance {tolerance})");
        assert!((a - b).abs() <= tolerance, "{name}: {a} → {b}");
    }
}

#[test]
fn bad_requests_name_the_run_and_the_option_and_leave_nothing_behind() {
    let (results, dir) = results("export_errors", 0.5);
    let out = dir.join("out");
    let unknown = export(&request(&results, Format::Csv, &["r000", "r077"], out.clone())).unwrap_err();
    assert!(unknown.contains("no run `r077` (--run)"), "{unknown}");
    let failed = export(&request(&results, Format::Vtk, &["r002"], out.clone())).unwrap_err();
    assert!(failed.contains("run r002 has no stored final state") && failed.contains("--run"), "{failed}");
    assert!(!out.exists() && !dir.join("out.partial").exists(), "nothing half-written");
    let mut frames = request(&results, Format::Csv, &[], out.clone());
    frames.frames = true;
    let every = export(&frames).unwrap();
    assert_eq!(every.runs, 2, "every run that finished (r002 failed)");
    let again = export(&request(&results, Format::Csv, &[], out.clone())).unwrap_err();
    assert!(again.contains("already exists: pass --force"), "{again}");
    let mut forced = request(&results, Format::Lammps, &["r000"], out.clone());
    forced.force = true;
    assert_eq!(export(&forced).unwrap().files, 1, "the folder replaced, not added to");
    let cli = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["export", results.to_str().unwrap(), "--format", "vtk", "--run", "r009", "--out"])
        .arg(dir.join("cli"))
        .output()
        .unwrap();
    assert!(!cli.status.success());
    assert!(String::from_utf8_lossy(&cli.stderr).contains("no run `r009`"));
}
