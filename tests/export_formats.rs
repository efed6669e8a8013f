//! `demsweep export`: each format read back by the program it is for (VTK's own XML readers, LAMMPS
//! itself, demsweep's placement reader), a settled pile restarted from its CSV, and the errors.

mod python_env;
mod runner_common;

use std::path::{Path, PathBuf};
use std::process::Command;

use demsweep::export::{ExportError, ExportRequest, Format, export, format};
use demsweep::output::{reader, stored};
use demsweep::physics::config::ContactLawKind;
use demsweep::physics::config::PlacementKind;
use demsweep::physics::quantity::PILE_METRICS;
use demsweep::physics::record::{RunStatus, Snapshot};
use demsweep::physics::simulation::Control;
use demsweep::physics::{RunError, run_scene, run_scene_with_history};
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

fn vtk() -> &'static Format {
    format("vtk").unwrap()
}

fn lammps_format() -> &'static Format {
    format("lammps").unwrap()
}

fn csv() -> &'static Format {
    format("csv").unwrap()
}

fn request(results: &Path, format: &'static Format, runs: &[&str], out: PathBuf) -> ExportRequest {
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
    let mut vtk = request(&results, vtk(), &["r000"], out.clone());
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

/// Runs LAMMPS as Debian installs it (`lmp`), or `lmp_serial`, with `args` in `folder`, with a
/// session folder of its own for Open MPI (removed after): in the shared default
/// (`/tmp/ompi.HOST.UID`) two of this file's tests starting LAMMPS at the same moment made one fail
/// ("mkdir: File exists"). A short path, as Open MPI puts sockets there.
fn lammps(args: &[&str], folder: &Path) -> std::process::Output {
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let found = ["lmp", "lmp_serial"].into_iter().find(|name| Command::new(name).arg("-h").output().is_ok());
    let run = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let session = std::env::temp_dir().join(format!("demsweep-ompi-{}-{run}", std::process::id()));
    std::fs::create_dir_all(&session).unwrap();
    let output = Command::new(found.expect("no LAMMPS (lmp): scripts/test.sh installs Debian's lammps package"))
        .args(args)
        .current_dir(folder)
        .env("OMPI_MCA_orte_tmpdir_base", &session)
        .output()
        .unwrap();
    std::fs::remove_dir_all(&session).unwrap();
    output
}

#[test]
fn lammps_reads_the_data_file_and_runs_from_it() {
    let (results, dir) = results("export_lammps", 0.5);
    let out = dir.join("lammps");
    export(&request(&results, lammps_format(), &["r001"], out.clone())).unwrap();
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
    let run = lammps(&["-in", "in.restart", "-log", "lammps.log"], &out);
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
    // The dump LAMMPS wrote is a placement demsweep reads back (`placement.kind = "lammps"`).
    let read = demsweep::study::lammps_file::read(&out.join("read.dump"), 1.0, &out).unwrap();
    assert_eq!(read, pile(&state), "the pile LAMMPS dumped is the exported one");
}

/// The disks of a state as a placement reads them (every angle 0: LAMMPS keeps none).
fn pile(state: &Snapshot) -> Vec<demsweep::physics::particles::InitialDisk> {
    (0..state.x.len())
        .map(|i| demsweep::physics::particles::InitialDisk {
            x: state.x[i],
            y: state.y[i],
            r: state.r[i],
            vx: state.vx[i],
            vy: state.vy[i],
            omega: state.omega[i],
            angle: 0.0,
        })
        .collect()
}

#[test]
fn a_study_places_the_pile_of_its_own_lammps_export() {
    let (results, dir) = results("export_lammps_back", 0.3);
    let out = dir.join("lammps");
    export(&request(&results, lammps_format(), &["r000"], out.clone())).unwrap();
    let study = out.join("back.toml");
    let text = "[scene]\ndomain.width = 0.12\ndomain.height = 0.2\nrun.duration = 0.01\n\
                placement.kind = \"lammps\"\nplacement.file = \"r000_final.data\"\n";
    std::fs::write(&study, text).unwrap();
    let plan = demsweep::study::load(&study).unwrap_or_else(|e| panic!("{e}"));
    let state = final_state(&results, "r000");
    assert_eq!(plan.runs[0].scene.particles.count, state.x.len());
    assert_eq!(plan.runs[0].initial.as_deref().unwrap(), &pile(&state)[..], "positions, radii, velocities, spins");
    std::fs::write(out.join("r000_final.data"), "LAMMPS data file\n\n3 atoms\n").unwrap();
    let refused = demsweep::study::load(&study).unwrap_err().to_string();
    assert!(refused.contains("scene.placement.file") && refused.contains("no `Atoms` section"), "{refused}");
}

/// Runs LAMMPS on `input` in `folder` for `steps` steps; its output, after checking it ran without error.
fn run_lammps(folder: &Path, input: &str, steps: u64) -> String {
    let run = lammps(&["-var", "steps", &steps.to_string(), "-in", input, "-log", "none"], folder);
    let text = format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success() && !text.contains("ERROR"), "LAMMPS failed on {input}:\n{text}");
    assert!(!text.contains("Lost atoms"), "{text}");
    text
}

/// The thermo rows (step, time, atoms, kinetic energy, pile height) of a LAMMPS output.
fn thermo(text: &str) -> Vec<[f64; 5]> {
    let rows = text.lines().skip_while(|l| !l.trim_start().starts_with("Step Time Atoms KinEng c_pile_height")).skip(1);
    rows.map_while(|l| {
        let values: Vec<f64> = l.split_whitespace().filter_map(|v| v.parse().ok()).collect();
        <[f64; 5]>::try_from(values).ok()
    })
    .collect()
}

#[test]
fn the_lammps_script_continues_a_settled_pile_of_every_law() {
    let cases: Vec<_> = ContactLawKind::ALL.iter().map(|&law| (law, 7)).collect();
    let (results, _) = settled_piles("export_lammps_laws", &cases);
    let out = results.parent().unwrap().join("lammps");
    export(&request(&results, lammps_format(), &[], out.clone())).unwrap();
    let file = reader::open(&results).unwrap();
    for (row, (law, _)) in reader::rows(&file, &results).unwrap().iter().zip(&cases) {
        assert_eq!(row.status, RunStatus::Settled, "{law:?}");
        let n = final_state(&results, &row.id).x.len() as f64;
        let input = format!("{}_final.in", row.id);
        let script = std::fs::read_to_string(out.join(&input)).unwrap();
        let header: String = script.lines().take_while(|l| l.starts_with('#')).collect::<Vec<_>>().join("\n");
        assert!(header.contains("Adams-Bashforth/Adams-Moulton"), "{law:?}: the integrator named:\n{header}");
        let name = toml::Value::try_from(law).unwrap().as_str().unwrap().to_string();
        let expressed = ["hertz_mindlin", "linear"].contains(&name.as_str());
        assert_eq!(header.contains(&format!("LAMMPS has no `{name}` law")), !expressed, "{law:?}:\n{header}");
        let rows = thermo(&run_lammps(&out, &input, 5000));
        assert_eq!(rows.len(), 6, "thermo every 1000 steps of 5000");
        assert!(rows.iter().all(|r| r[2] == n), "{law:?}: every atom kept: {rows:?}");
        let first = rows[0][4];
        let drift = rows.iter().map(|r| (r[4] / first - 1.0).abs()).fold(0.0, f64::max);
        println!("{law:?}: pile height {first} m, drift over 5000 steps {drift:.2e}");
        assert!(drift < 0.01, "{law:?}: the pile's height moved by {drift} of {first} m: {rows:?}");
    }
}

#[test]
fn the_lammps_script_has_the_runs_stiffness_against_disks_and_floor() {
    // Two disks in a column (a box 2.5 radii wide) settle on the floor; in LAMMPS, continued with the
    // exported script, each overlap (floor and disk-disk) is the one demsweep's material gives.
    let dir = runner_common::scratch("export_lammps_column");
    let mut scene = runner_common::tiny_scene(2, 3.0);
    scene.domain.width = 0.025;
    scene.material.youngs_modulus = 1e7;
    scene.material.poisson_ratio = Some(0.25);
    scene.integrator.contact_time_fraction = Some(0.02);
    let plan = runner_common::plan("export_lammps_column", vec![(Vec::new(), scene)]);
    let results = demsweep::runner::run_plan(&plan, &runner_common::options(&dir, 1)).unwrap().results;
    let out = dir.join("lammps");
    export(&request(&results, lammps_format(), &["r000"], out.clone())).unwrap();
    let state = final_state(&results, "r000");
    let dump =
        "include r000_final.in\nwrite_dump all custom column.dump id y radius modify sort id format float %.17g\n";
    std::fs::write(out.join("column.in"), dump).unwrap();
    run_lammps(&out, "column.in", 20_000);
    let atoms: Vec<Vec<f64>> = std::fs::read_to_string(out.join("column.dump"))
        .unwrap()
        .lines()
        .skip_while(|l| !l.starts_with("ITEM: ATOMS"))
        .skip(1)
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect();
    let (low, high) = if state.y[0] < state.y[1] { (0, 1) } else { (1, 0) };
    let overlaps = |y: [f64; 2], r: [f64; 2]| [r[0] - y[0], r[0] + r[1] - (y[1] - y[0])];
    let demsweep = overlaps([state.y[low], state.y[high]], [state.r[low], state.r[high]]);
    let lammps = overlaps([atoms[low][1], atoms[high][1]], [atoms[low][2], atoms[high][2]]);
    for (what, (d, l)) in ["floor", "disk-disk"].iter().zip(demsweep.iter().zip(&lammps)) {
        println!("{what} overlap: demsweep {d:e} m, LAMMPS {l:e} m");
        assert!((l / d - 1.0).abs() < 0.02, "{what} overlap: demsweep {d} m, LAMMPS {l} m");
    }
}

#[test]
fn a_settled_pile_opens_in_pandas_and_restarts_from_its_csv_settled_with_its_metrics() {
    let (results, dir) = results("export_restart", 3.0);
    let out = dir.join("csv");
    export(&request(&results, csv(), &["r000"], out.clone())).unwrap();
    let file = reader::open(&results).unwrap();
    let rows = reader::rows(&file, &results).unwrap();
    let first = stored::read_run(&file, &results, &rows[0]).unwrap();
    assert_eq!(rows[0].status, RunStatus::Settled);
    let csv = out.join("r000_final.csv");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/interop/check_csv.py");
    let group = reader::find_run(&file, &results, "r000").unwrap();
    let check = python_env::python(script).arg(&out).arg(&results).arg(group).arg("r000").output();
    let check = check.expect("run the tests' Python");
    let text = format!("{}{}", String::from_utf8_lossy(&check.stdout), String::from_utf8_lossy(&check.stderr));
    assert!(check.status.success(), "pandas check failed (scripts/test.sh installs pandas and h5py):\n{text}");
    assert!(text.contains("r000: 30 disks and") && text.contains(", 0 problems"), "{text}");
    let disks = demsweep::study::initial_csv::read(&csv, 1.0, csv.parent().unwrap()).unwrap();
    let state = first.final_state.unwrap();
    assert_eq!(disks.len(), state.x.len());
    for (i, d) in disks.iter().enumerate() {
        assert_eq!(
            [d.x, d.y, d.r, d.vx, d.vy, d.omega, d.angle],
            [state.x[i], state.y[i], state.r[i], state.vx[i], state.vy[i], state.omega[i], state.angle[i]]
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
    // Without its contacts file: geometry is kept to the solver's drift; contacts may form or open at
    // the threshold; forces redistribute, as the tangential springs start from zero.
    let n = state.x.len() as f64;
    let metrics = PILE_METRICS.iter().zip(original.pile.values()).zip(restarted.pile.values());
    for ((metric, &a), &b) in metrics {
        let name = metric.name;
        let tolerance = match name {
            "pile_height" | "surface_height" | "packing_fraction" | "packing_fraction_interior" => 1e-3 * a.abs(),
            "coordination_number" | "mechanical_coordination_number" => 4.0 / n,
            "rattler_fraction" | "sliding_fraction" => 2.0 / n,
            // Stresses are forces, which redistribute: within a quarter of the pressure (a shear
            // stress near zero has no relative scale of its own).
            stress if stress.starts_with("stress_") => 0.25 * original.pile["stress_pressure"],
            _ => 0.25 * a.abs(),
        };
        println!("{name}: {a} → {b} (tolerance {tolerance})");
        assert!((a - b).abs() <= tolerance, "{name}: {a} → {b}");
    }
}

/// A frictional 30-disk pile settled with each law and placement seed of `cases` (runs `r000`,
/// `r001`, …), exported as CSV (disks and contacts) into `<scratch>/csv`.
fn settled_piles(test: &str, cases: &[(ContactLawKind, u64)]) -> (PathBuf, PathBuf) {
    let dir = runner_common::scratch(test);
    let runs = cases
        .iter()
        .map(|&(law, seed)| {
            let mut scene = runner_common::tiny_scene(30, 3.0);
            scene.placement.seed = seed;
            scene.contact.law = law;
            let parameters = vec![
                ("contact.law".to_string(), ParamValue::Text(format!("{law:?}"))),
                ("placement.seed".to_string(), ParamValue::Int(seed as i64)),
            ];
            (parameters, scene)
        })
        .collect();
    let plan = runner_common::plan(test, runs);
    let report = demsweep::runner::run_plan(&plan, &runner_common::options(&dir, 2)).unwrap();
    export(&request(&report.results, csv(), &[], dir.join("csv"))).unwrap();
    (report.results, dir.join("csv"))
}

#[test]
fn a_pile_restarted_with_its_contacts_file_keeps_every_pile_metric() {
    // The hysteretic law has a law state (the largest overlap) besides the tangential springs;
    // three placement seeds each.
    let laws = [ContactLawKind::HertzMindlin, ContactLawKind::HystereticLinear];
    let cases: Vec<_> = laws.iter().flat_map(|&law| [7, 8, 9].map(|seed| (law, seed))).collect();
    let (results, csv) = settled_piles("export_history", &cases);
    let file = reader::open(&results).unwrap();
    let (mut largest_difference, mut force_changes) = (0.0_f64, Vec::new());
    for (row, &(law, _)) in reader::rows(&file, &results).unwrap().iter().zip(&cases) {
        let run = stored::read_run(&file, &results, row).unwrap();
        assert_eq!(row.status, RunStatus::Settled, "{law:?}");
        let state = run.final_state.unwrap();
        let disks = demsweep::study::initial_csv::read(&csv.join(format!("{}_final.csv", row.id)), 1.0, &csv).unwrap();
        let contacts_file = csv.join(format!("{}_final_contacts.csv", row.id));
        let contacts = demsweep::study::initial_csv::read_contacts(&contacts_file, disks.len(), 3, &csv).unwrap();
        assert_eq!(contacts.len(), state.contacts.len());
        let springs = state.contacts.tangential_spring.iter().filter(|s| **s != 0.0).count();
        let law_states = state.contacts.law_state.iter().filter(|s| **s != 0.0).count();
        println!("{law:?}: {} contacts, {springs} springs, {law_states} law states", contacts.len());
        assert!(springs > contacts.len() / 2, "the pile's springs are loaded");
        assert_eq!(law_states > 0, law == ContactLawKind::HystereticLinear);
        let mut scene = run.scene.clone();
        scene.placement.kind = PlacementKind::File;
        scene.placement.file = Some(format!("{}_final.csv", row.id));
        let without = run_scene(&scene, Some(disks.clone()), &mut |_| Control::Continue).unwrap();
        scene.placement.contacts = Some(contacts_file.display().to_string());
        let unread = run_scene(&scene, Some(disks.clone()), &mut |_| Control::Continue).unwrap_err();
        let file = contacts_file.display().to_string();
        assert_eq!(unread, RunError::HistoryNotGiven { file }, "the error names the unread history");
        assert!(unread.to_string().starts_with("placement.contacts: the contact history"), "{unread}");
        let observe = &mut |_: &_| Control::Continue;
        let restarted = run_scene_with_history(&scene, Some(disks), Some(&contacts), observe).unwrap();
        assert_eq!(restarted.status, RunStatus::Settled, "{law:?}: {:?}", restarted.message);
        assert!(restarted.settle_time.unwrap() <= scene.settle.hold_time, "{law:?}: {:?} s", restarted.settle_time);
        // The pile left alone for as long as the restart ran: how much its metrics drift by themselves.
        let mut continued = run.scene.clone();
        continued.run.stop_at_settle = false;
        continued.run.duration = row.simulated_time + restarted.simulated_time;
        let continued = run_scene(&continued, None, &mut |_| Control::Continue).unwrap();
        let original = run_scene(&run.scene, None, &mut |_| Control::Continue).unwrap();
        assert_eq!(original.final_state, state, "{law:?}: the stored run, run again");
        // A restart differs from the pile left alone only by its first step (the paper's scheme starts
        // with one Adams-Bashforth 1 step, having no earlier acceleration) and by the springs'
        // update at the restart's first force evaluation (`v_t Δt` once more, with v_t ≈ 0 in a
        // settled pile): measured 7e-6 relative at most over these 6 piles, so 1e-4 relative is the
        // tolerance. The pile itself drifts by far more over the same time (printed: 1e-3 to 2e-1
        // relative), and without the contacts file the force metrics move by more than 1e-3.
        let records = [&original, &continued, &restarted, &without];
        let tolerance = |left_alone: f64| 1e-4 * left_alone.abs();
        for (k, metric) in PILE_METRICS.iter().enumerate() {
            let [a, left_alone, b, w] = records.map(|r| r.pile.values()[k]);
            let name = metric.name;
            println!("{law:?} {name}: {a:e}, left alone {left_alone:e}, restarted {b:e}, without contacts file {w:e}");
            assert!((b - left_alone).abs() <= tolerance(left_alone), "{law:?} {name}: {b} vs {left_alone}");
            if left_alone != 0.0 {
                largest_difference = largest_difference.max((b / left_alone - 1.0).abs());
            }
        }
        // Without the contacts file the forces redistribute (the test can fail): the largest change
        // of the force metrics is at least 100 times the tolerance.
        let largest_change =
            ["floor_load_ratio", "floor_mean_contact_force", "normal_force_width", "mean_overlap_ratio"]
                .map(|name| ((without.pile[name] / continued.pile[name] - 1.0).abs(), name))
                .into_iter()
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap();
        assert!(largest_change.0 > 1e-3, "{law:?}: without the contacts file, at most {largest_change:?}");
        force_changes.push((largest_change.0, law, largest_change.1));
    }
    force_changes.sort_by(|a, b| a.0.total_cmp(&b.0));
    println!(
        "{} piles: restarted against left alone at most {largest_difference:.1e} relative; without the contacts \
         file the force metrics moved by up to {:.1e} to {:.1e} ({:?})",
        cases.len(),
        force_changes[0].0,
        force_changes[force_changes.len() - 1].0,
        force_changes.iter().map(|c| format!("{:?} {} {:.3}", c.1, c.2, c.0)).collect::<Vec<_>>()
    );
}

#[test]
fn a_study_restarts_from_the_exported_files_as_the_library_does() {
    // The whole chain: `placement.contacts` read by the study, carried by the planned run and
    // handed to the simulation by the runner.
    let (results, csv) = settled_piles("export_study_restart", &[(ContactLawKind::HertzMindlin, 7)]);
    let study = csv.join("restart.toml");
    let text = "[scene]\ndomain.width = 0.12\ndomain.height = 0.2\nrun.duration = 3.0\nrun.sample_interval = 2e-3\n\
                placement.kind = \"file\"\nplacement.file = \"r000_final.csv\"\n\
                placement.contacts = \"r000_final_contacts.csv\"\n";
    std::fs::write(&study, text).unwrap();
    let plan = demsweep::study::load(&study).unwrap_or_else(|e| panic!("{e}"));
    let run = &plan.runs[0];
    let contacts = run.initial_contacts.as_deref().expect("the contacts file is read");
    assert_eq!(contacts.len(), final_state(&results, "r000").contacts.len());
    let report = demsweep::runner::run_plan(&plan, &runner_common::options(&csv.join("out"), 1)).unwrap();
    let file = reader::open(&report.results).unwrap();
    let row = &reader::rows(&file, &report.results).unwrap()[0];
    assert_eq!(row.status, RunStatus::Settled, "{:?}", row.message);
    let disks = run.initial.as_deref().unwrap().clone();
    let direct = run_scene_with_history(&run.scene, Some(disks), Some(contacts), &mut |_| Control::Continue).unwrap();
    let stored = stored::read_run(&file, &report.results, row).unwrap().final_state.unwrap();
    assert_eq!(stored, direct.final_state, "the study's run is the library's restart, to the bit");
}

#[test]
fn bad_requests_name_the_run_and_the_option_and_leave_nothing_behind() {
    let (results, dir) = results("export_errors", 0.5);
    let out = dir.join("out");
    let unknown = export(&request(&results, csv(), &["r000", "r077"], out.clone())).unwrap_err();
    assert!(matches!(&unknown, ExportError::UnknownRun { id, .. } if id == "r077"), "{unknown:?}");
    assert!(unknown.to_string().contains("no run `r077` (--run)"), "{unknown}");
    let failed = export(&request(&results, vtk(), &["r002"], out.clone())).unwrap_err();
    assert!(matches!(&failed, ExportError::NoFinalState { id, .. } if id == "r002"), "{failed:?}");
    let failed = failed.to_string();
    assert!(failed.contains("run r002 has no stored final state") && failed.contains("--run"), "{failed}");
    assert!(!out.exists() && !dir.join("out.partial").exists(), "nothing half-written");
    let mut frames = request(&results, csv(), &[], out.clone());
    frames.frames = true;
    let every = export(&frames).unwrap();
    assert_eq!(every.runs, 2, "every run that finished (r002 failed)");
    let again = export(&request(&results, csv(), &[], out.clone())).unwrap_err();
    assert!(matches!(&again, ExportError::Guard(e) if e.path == out), "{again:?}");
    assert!(again.to_string().contains("already exists: pass --force"), "{again}");
    let mut forced = request(&results, lammps_format(), &["r000"], out.clone());
    forced.force = true;
    assert_eq!(
        export(&forced).unwrap().files,
        2,
        "the folder replaced (a data file and its input script), not added to"
    );
    let cli = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["export", results.to_str().unwrap(), "--format", "vtk", "--run", "r009", "--out"])
        .arg(dir.join("cli"))
        .output()
        .unwrap();
    assert!(!cli.status.success());
    assert!(String::from_utf8_lossy(&cli.stderr).contains("no run `r009`"));
}

/// A frictional 30-disk pile settled between periodic sides 0.12 m apart (run `r000`), with
/// contacts across the boundary.
fn periodic_pile(test: &str) -> (PathBuf, Snapshot) {
    let dir = runner_common::scratch(test);
    let mut scene = runner_common::tiny_scene(30, 6.0);
    scene.domain.periodic_x = true;
    let plan = runner_common::plan(test, vec![(Vec::new(), scene)]);
    let report = demsweep::runner::run_plan(&plan, &runner_common::options(&dir, 1)).unwrap();
    let state = final_state(&report.results, "r000");
    let c = &state.contacts;
    let across = (0..c.len()).filter(|&k| {
        usize::try_from(c.second[k]).is_ok_and(|j| (state.x[j] - state.x[c.first[k] as usize]).abs() > 0.06)
    });
    assert!(across.count() > 0, "contacts across the boundary");
    (report.results, state)
}

#[test]
fn lammps_continues_a_periodic_pile_with_no_lost_atom() {
    let (results, state) = periodic_pile("export_lammps_periodic");
    let out = results.parent().unwrap().join("lammps");
    export(&request(&results, lammps_format(), &["r000"], out.clone())).unwrap();
    let script = std::fs::read_to_string(out.join("r000_final.in")).unwrap();
    assert!(script.contains("boundary p fm p") && !script.contains("xplane"), "periodic x, no side walls:\n{script}");
    let rows = thermo(&run_lammps(&out, "r000_final.in", 5000));
    assert_eq!(rows.len(), 6, "thermo every 1000 steps of 5000");
    let n = state.x.len() as f64;
    assert!(rows.iter().all(|r| r[2] == n), "every atom kept: {rows:?}");
    // Without its contacts across the boundary the pile would spread sideways and sink.
    let first = rows[0][4];
    let drift = rows.iter().map(|r| (r[4] / first - 1.0).abs()).fold(0.0, f64::max);
    println!("periodic pile height {first} m, drift over 5000 steps {drift:.2e}");
    assert!(drift < 0.01, "the pile's height moved by {drift} of {first} m: {rows:?}");
}

/// The numbers of the VTK data array `name` of `file`.
fn vtk_array(file: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(file).unwrap();
    let start = text.find(&format!("Name=\"{name}\"")).unwrap_or_else(|| panic!("{name} in {}", file.display()));
    let values = &text[start..][text[start..].find('>').unwrap() + 1..];
    values[..values.find("</DataArray>").unwrap()].split_whitespace().map(|v| v.parse().unwrap()).collect()
}

#[test]
fn vtk_draws_a_periodic_pile_whole_at_both_sides() {
    let (results, state) = periodic_pile("export_vtk_periodic");
    let out = results.parent().unwrap().join("vtk");
    export(&request(&results, vtk(), &["r000"], out.clone())).unwrap();
    let (width, n) = (0.12, state.x.len());
    // Disks, then the images of those reaching past a side, one width over.
    let disks = out.join("r000_final_disks.vtp");
    let (ids, images, points) = (vtk_array(&disks, "id"), vtk_array(&disks, "image"), vtk_array(&disks, "Points"));
    let crossing: usize =
        (0..n).map(|i| usize::from(state.x[i] < state.r[i]) + usize::from(state.x[i] + state.r[i] > width)).sum();
    assert!(crossing > 0 && ids.len() == n + crossing, "{} vertices, {n} disks, {crossing} across a side", ids.len());
    for (k, (&id, &image)) in ids.iter().zip(&images).enumerate() {
        let i = id as usize;
        let shift = points[3 * k] - state.x[i];
        assert_eq!((image, points[3 * k + 1]), (f64::from(u8::from(k >= n)), state.y[i]), "vertex {k}");
        assert!(if k < n { shift == 0.0 } else { (shift.abs() - width).abs() < 1e-12 }, "vertex {k} shifted {shift}");
    }
    // Every disk-disk contact is drawn to the nearest image of its second disk: no longer than the
    // two radii.
    let contacts = out.join("r000_final_contacts.vtp");
    let (first, second, ends) =
        (vtk_array(&contacts, "first"), vtk_array(&contacts, "second"), vtk_array(&contacts, "Points"));
    for k in (0..first.len()).filter(|&k| second[k] >= 0.0) {
        let (i, j) = (first[k] as usize, second[k] as usize);
        let length = (ends[6 * k + 3] - ends[6 * k]).hypot(ends[6 * k + 4] - ends[6 * k + 1]);
        assert!(length <= state.r[i] + state.r[j], "contact {i}-{j} drawn {length} m long");
    }
    let walls = vtk_array(&out.join("r000_walls.vtp"), "wall");
    assert_eq!(walls, [0.0], "the floor alone: no side walls");
}
