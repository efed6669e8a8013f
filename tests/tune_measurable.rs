//! A reference a tune cannot use, said as early as it can be: a kept metric its pile cannot measure
//! (`check` warns before anything runs, from the pile's predicted depth, and `tune` stops after the
//! reference's runs naming the metric and the runs it is undefined on, where it used to say a
//! relative tolerance gives no margin), and a random placement that jams on one of the reference's
//! seeds (refused before anything runs, where the tune used to stop at that replicate saying the
//! reference "does not settle"); and a reference that does not settle within its duration, named
//! with what to change.

mod runner_common;

use runner_common::{demsweep, text};
use std::path::{Path, PathBuf};

/// A tune file of `count` disks of radii 3-4 mm in a box `width` wide, keeping the interior packing.
fn tune_file(dir: &Path, width: f64) -> PathBuf {
    let text = format!(
        r#"name = "shallow"
[scene]
domain.width = {width}
domain.height = 0.12
particles.count = 60
particles.radius = 0.003
particles.radius_max = 0.004
material.youngs_modulus = 5e8
material.restitution = 0.5
material.friction = 0.3
integrator.contact_time_fraction = 0.02
run.duration = 2.0
placement.seed = 4100

[levers]
"damping.local" = {{ linear = [0.0, 0.4] }}

[keep]
packing_fraction_interior = 0.03

[search]
reference_seeds = 4
"#
    );
    let path = dir.join(format!("shallow_{width}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_pile_too_shallow_for_its_kept_interior_packing_is_warned_of_and_stops_the_tune_naming_it() {
    let dir = runner_common::scratch("tune_measurable_shallow");
    // 60 disks across 0.3 m: about 9 mm deep, where the window leaves out 16 mm at each end.
    let file = tune_file(&dir, 0.3);
    let check = demsweep(&["check", file.to_str().unwrap()]);
    let said = text(&check.stdout) + &text(&check.stderr);
    assert!(said.contains("keep.packing_fraction_interior: the pile is predicted"), "{said}");
    assert!(said.contains("predicted empty: packing_fraction_interior is undefined (NaN)"), "{said}");

    let out = dir.join("out");
    let run = demsweep(&["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_ne!(run.status.code(), Some(0), "{}", text(&run.stdout));
    let err = text(&run.stderr);
    assert!(
        err.contains("kept metric packing_fraction_interior is undefined (NaN) on 4 of the reference's 4 runs"),
        "{err}"
    );
    assert!(!err.contains("gives no margin"), "{err}");
}

#[test]
fn a_pile_deep_enough_for_its_window_is_not_warned_of_and_measures_it() {
    let dir = runner_common::scratch("tune_measurable_deep");
    // The same disks across 0.05 m: about 56 mm deep, a window of about 24 mm.
    let file = tune_file(&dir, 0.05);
    let check = demsweep(&["check", file.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stderr));
    let said = text(&check.stdout) + &text(&check.stderr);
    assert!(!said.contains("keep.packing_fraction_interior"), "{said}");

    let out = dir.join("out");
    let run = demsweep(&["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--quiet"]);
    let err = text(&run.stderr);
    assert!(!err.contains("is undefined (NaN)"), "{err}");
    assert_eq!(run.status.code(), Some(0), "{err}");
}

#[test]
fn a_random_placement_that_jams_on_a_later_reference_seed_is_refused_before_anything_runs() {
    let dir = runner_common::scratch("tune_measurable_jam");
    // Disks at an area fraction of 0.48, where random placement jams: the first seed fits them all,
    // a later replicate of the reference does not.
    let study = r#"name = "jam"
[scene]
particles.radius = 0.005786
particles.radius_max = 0.01078
particles.count = 158
domain.width = 0.4941
domain.height = 0.1548
material.youngs_modulus = 5.977e9
material.restitution = 0.86
run.duration = 4
placement.seed = 64947

[levers]
"damping.local" = { linear = [0.0, 0.5] }

[keep]
pile_height = 0.05

[search]
reference_seeds = 9
"#;
    let file = dir.join("jam.toml");
    std::fs::write(&file, study).unwrap();
    let check = demsweep(&["check", file.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(2), "{}", text(&check.stdout));
    let err = text(&check.stderr);
    assert!(err.contains("jam.toml:2:2: scene.particles.count: random placement fit only"), "{err}");
    assert!(err.contains("(on the reference's replicate 3, placement.seed = 64950)"), "{err}");
    let out = dir.join("out");
    let run = demsweep(&["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stderr));
    assert!(!out.exists(), "nothing is written for a tune refused before it runs");
    // The same scene with the reference on fewer seeds, none of them jammed, is accepted.
    std::fs::write(&file, study.replace("reference_seeds = 9", "reference_seeds = 3")).unwrap();
    let check = demsweep(&["check", file.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stderr));
}

#[test]
fn a_reference_that_does_not_settle_within_its_duration_stops_the_tune_saying_what_to_change() {
    let dir = runner_common::scratch("tune_measurable_unsettled");
    // 0.05 s: the disks are still falling when the run ends.
    let file = tune_file(&dir, 0.05);
    let study = std::fs::read_to_string(&file).unwrap().replace("run.duration = 2.0", "run.duration = 0.05");
    std::fs::write(&file, study).unwrap();
    let out = dir.join("out");
    let run = demsweep(&["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--quiet"]);
    assert_ne!(run.status.code(), Some(0), "{}", text(&run.stdout));
    let err = text(&run.stderr);
    assert!(
        err.contains("the reference scene itself does not settle on every seed (replicate 0 did not settle)"),
        "{err}"
    );
    assert!(err.contains("lengthen the scene's run.duration, or damp it more"), "{err}");
}
