//! What a study may do but probably should not: warned about before running, with file, line and key,
//! without failing.

mod study_support;

use demsweep::study::StudyError;
use study_support::{SMALL_SCENE, StudyDir, plan};

/// The warnings with `key`.
fn with_key<'a>(warnings: &'a [StudyError], key: &str) -> Vec<&'a StudyError> {
    warnings.iter().filter(|w| w.key == key).collect()
}

#[test]
fn sampling_longer_than_the_run_is_warned_with_its_key() {
    let text = format!("{SMALL_SCENE}run.sample_interval = 0.05\nrun.frame_times = [0.0, 0.005, 0.5]\n");
    let warnings = plan("sampling", &text).warnings;
    let interval = with_key(&warnings, "scene.run.sample_interval");
    assert_eq!(interval.len(), 1, "{warnings:#?}");
    assert_eq!(interval[0].location.map(|l| l.line), Some(5));
    assert!(
        interval[0]
            .reason
            .starts_with("0.05 s is longer than run.duration (0.01 s): the run is sampled only at its start and end")
    );
    let frames = with_key(&warnings, "scene.run.frame_times");
    assert_eq!(frames[0].reason, "0.5 s past run.duration (0.01 s): never recorded");
    let swept = format!("{SMALL_SCENE}[sweep]\n\"run.sample_interval\" = [0.001, 0.02]\n");
    let warnings = plan("sampling_swept", &swept).warnings;
    let on_axis = with_key(&warnings, "sweep.\"run.sample_interval\"");
    assert_eq!(
        (on_axis.len(), on_axis[0].value.as_deref(), on_axis[0].run.as_deref()),
        (1, Some("0.02"), Some("r0001"))
    );
}

#[test]
fn overlapping_initial_disks_below_the_divergence_limit_are_warned_with_rows() {
    let dir = StudyDir::new("csvwarn");
    let study = dir.write("s.toml", "[scene]\nplacement.kind = \"file\"\nplacement.file = \"init.csv\"\n");
    dir.write("init.csv", "x,y,r\n0.1,0.1,0.01\n0.3,0.1,0.01\n0.318,0.1,0.01\n0.2,0.0085,0.01\n0.2,0.05,0.01\n");
    let warnings = demsweep::study::load(&study).unwrap().warnings;
    let overlaps = with_key(&warnings, "scene.placement.file");
    assert_eq!(overlaps.len(), 1, "{warnings:#?}");
    assert_eq!(
        overlaps[0].reason,
        "disks 2 and 3 (rows 2 and 3 of the file) overlap by 0.2 radii, beyond limits.overlap_warning_ratio = 0.1 \
         (Hertz validity): they start pushed apart; 2 overlaps beyond it in all"
    );
}

#[test]
fn a_radius_key_beside_a_placement_file_with_radii_is_warned_as_drawing_none() {
    let dir = StudyDir::new("file-radii");
    dir.write("init.csv", "x,y,r\n0.1,0.1,0.01\n0.2,0.1,0.02\n");
    let text = "[scene]\nplacement.kind = \"file\"\nplacement.file = \"init.csv\"\nparticles.radius_max = 0.03\n";
    let plan = demsweep::study::load(&dir.write("s.toml", text)).unwrap();
    let radii: Vec<f64> = plan.runs[0].initial.as_ref().unwrap().iter().map(|d| d.r).collect();
    assert_eq!(radii, [0.01, 0.02], "the file's radii");
    let drawn = with_key(&plan.warnings, "scene.particles.radius_max");
    assert_eq!((drawn.len(), drawn[0].location.map(|l| l.line)), (1, Some(4)), "{:#?}", plan.warnings);
    assert!(drawn[0].reason.starts_with("draws no radius: ") && drawn[0].reason.contains("init.csv"), "{}", drawn[0]);
}

#[test]
fn seeds_of_a_placement_that_does_not_draw_from_them_are_warned_as_copies() {
    let lattice = format!("{SMALL_SCENE}placement.kind = \"lattice\"\n[sweep]\nreplicates = 3\n");
    let warnings = plan("copies", &lattice).warnings;
    let copies = with_key(&warnings, "scene.placement.kind");
    assert_eq!(copies.len(), 1, "{warnings:#?}");
    assert_eq!((copies[0].runs_affected, copies[0].location.map(|l| l.line)), (3, Some(5)));
    assert!(copies[0].reason.contains("the study's 3 seeds run identical copies"), "{}", copies[0]);
    let dir = StudyDir::new("copies-file");
    dir.write("init.csv", "x,y\n0.1,0.1\n0.2,0.1\n");
    let file =
        "[scene]\nplacement.kind = \"file\"\nplacement.file = \"init.csv\"\n[sweep]\n\"placement.seed\" = [1, 2]\n";
    let warnings = demsweep::study::load(&dir.write("s.toml", file)).unwrap().warnings;
    assert!(with_key(&warnings, "scene.placement.kind")[0].reason.contains("the study's 2 seeds"), "{warnings:#?}");
    for drawn in ["", "placement.kind = \"lattice\"\nparticles.radius_max = 0.012\n"] {
        let text = format!("{SMALL_SCENE}{drawn}[sweep]\nreplicates = 3\n");
        let warnings = plan("drawn", &text).warnings;
        assert!(with_key(&warnings, "scene.placement.kind").is_empty(), "{drawn}: {warnings:#?}");
    }
    assert!(
        with_key(
            &plan("one", &format!("{SMALL_SCENE}placement.kind = \"lattice\"\n")).warnings,
            "scene.placement.kind"
        )
        .is_empty()
    );
}

#[test]
fn predicted_validity_is_warned_once_per_kind_and_value_at_the_key_at_fault() {
    let text =
        "[scene]\nparticles.count = 20\nrun.duration = 0.01\n[sweep]\n\"material.youngs_modulus\" = [2e4, 3e4, 1e11]\n";
    let warnings = plan("predicted", text).warnings;
    let impact: Vec<&StudyError> =
        warnings.iter().filter(|w| w.reason.starts_with("predicted: an impact at")).collect();
    assert_eq!(impact.len(), 2, "{warnings:#?}");
    for (w, (value, run)) in impact.iter().zip([("20000.0", "r0000"), ("30000.0", "r0001")]) {
        assert_eq!(
            (w.key.as_str(), w.value.as_deref(), w.run.as_deref(), w.location.map(|l| l.line)),
            ("sweep.\"material.youngs_modulus\"", Some(value), Some(run), Some(5))
        );
    }
    assert!(impact[0].reason.contains("would overlap") && impact[0].reason.contains("E = 2.000e4 Pa"), "{}", impact[0]);
    assert!(warnings.iter().any(|w| w.reason.contains("into the floor")), "{warnings:#?}");
    // Not swept: the scene's key, its line and its value.
    let text = "[scene]\nparticles.count = 20\nrun.duration = 0.01\n\nmaterial.youngs_modulus = 2e4\n";
    let warnings = plan("predicted_unswept", text).warnings;
    let impact = warnings.iter().find(|w| w.reason.starts_with("predicted: an impact at")).expect("an impact warning");
    assert_eq!(
        (impact.key.as_str(), impact.value.as_deref(), impact.location.map(|l| l.line)),
        ("scene.material.youngs_modulus", Some("20000"), Some(5))
    );
}

#[test]
fn a_stage_step_past_the_limit_is_warned_like_a_scenes_at_the_stages_key() {
    let scene = |step: &str, stage: &str| {
        format!(
            "[scene]\nparticles.count = 20\nrun.duration = 0.01\nmaterial.youngs_modulus = 1e11\n\
             integrator.time_step = {step}\n\
             [[scene.stages]]\nname = \"fill\"\nuntil.time = 0.005\n{stage}"
        )
    };
    let kinds = |warnings: &[StudyError]| {
        let mut kinds: Vec<_> = warnings.iter().filter_map(|w| w.rule).collect();
        kinds.sort();
        kinds
    };
    let in_scene = plan("step_in_scene", &scene("0.01", "")).warnings;
    let predicted: Vec<&StudyError> = in_scene.iter().filter(|w| w.rule.is_some()).collect();
    assert!(!predicted.is_empty(), "the scene's step past the limit is warned");
    for w in predicted {
        assert_eq!((w.key.as_str(), w.value.as_deref()), ("scene.integrator.time_step", Some("0.01")), "{w}");
    }
    let in_stage = plan("step_in_stage", &scene("1e-5", "integrator.time_step = 0.01\n")).warnings;
    assert_eq!(kinds(&in_stage), kinds(&in_scene), "{in_stage:#?}");
    for w in in_stage.iter().filter(|w| w.rule.is_some()) {
        assert_eq!(
            (w.key.as_str(), w.value.as_deref(), w.location.map(|l| l.line)),
            ("scene.stages.fill.integrator.time_step", Some("0.01"), Some(9)),
            "{w}"
        );
        assert!(w.reason.starts_with("predicted in stage \"fill\": "), "{w}");
    }
    // Under --strict, check refuses it as it refuses the scene's.
    let dir = StudyDir::new("step_in_stage_strict");
    let file = dir.write("s.toml", &scene("1e-5", "integrator.time_step = 0.01\n"));
    let check = std::process::Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["check", "--strict", file.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(check.status.code(), Some(2), "{}", String::from_utf8_lossy(&check.stderr));
    // A stage that sets the scene's own step adds nothing.
    let same = plan("step_same", &scene("1e-5", "integrator.time_step = 1e-5\n")).warnings;
    assert!(same.iter().all(|w| w.rule.is_none()), "{same:#?}");
    // Tune's screen predicts the same of a setting.
    let staged = &plan("step_in_stage_screen", &scene("1e-5", "integrator.time_step = 0.01\n")).runs[0];
    let screened = demsweep::tune::validity::predicted_warnings(&staged.scene, None).unwrap();
    let mut screened: Vec<_> = screened.iter().map(|w| w.kind).collect();
    screened.sort();
    assert_eq!(screened, kinds(&in_scene));
}

#[test]
fn results_larger_than_the_free_disk_space_are_warned_with_the_figures() {
    let mut scene = demsweep::physics::SceneConfig::default();
    scene.run.frame_interval = Some(1e-6);
    let plan = study_support::plan_in_code("huge_output", vec![scene; 100_000]);
    let dir = StudyDir::new("space");
    let warning = demsweep::study::resources::output_space_warning(&plan, &dir.path.join("not/yet")).unwrap();
    assert!(warning.starts_with("huge_output.toml: the results of 100000 runs need about 2.5 PB"), "{warning}");
    assert!(warning.contains(&format!("but {} has ", dir.path.display())) && warning.ends_with(" free"), "{warning}");
}

#[test]
fn a_heavily_damped_paper_integrator_at_a_tenth_of_the_contact_time_is_warned() {
    // Restitution 0.1 at 0.1 of the contact time: under the paper's integrator the pile never comes to
    // rest, though Δt/t_c and Δt × damping rate are each within their own limits.
    let scene = |scheme: &str, fraction: f64| {
        format!(
            "[scene]\nparticles.count = 20\nrun.duration = 0.01\nmaterial.restitution = 0.1\n\
             integrator.scheme = \"{scheme}\"\nintegrator.contact_time_fraction = {fraction}\n"
        )
    };
    let stable_step = |w: &&StudyError| w.reason.contains("the stable step of the integrator (integrator.scheme)");
    let warnings = plan("damped_ab2", &scene("adams_bashforth_moulton", 0.1)).warnings;
    let warned: Vec<&StudyError> = warnings.iter().filter(stable_step).collect();
    assert_eq!(warned.len(), 1, "{warnings:#?}");
    assert!(
        warned[0].reason.starts_with("predicted: time step is 0.09") && warned[0].reason.contains(", past 0.0"),
        "{}",
        warned[0]
    );
    assert!(!warnings.iter().any(|w| w.reason.contains("limits.contact_time_fraction")), "{warnings:#?}");
    assert!(!warnings.iter().any(|w| w.reason.contains("limits.damping_rate_fraction")), "{warnings:#?}");
    // A smaller step, or the lighter damping of restitution 0.7 at a smaller step, passes.
    let warnings = plan("damped_ab2_small", &scene("adams_bashforth_moulton", 0.03)).warnings;
    assert!(!warnings.iter().any(|w| stable_step(&w)), "{warnings:#?}");
    let light = scene("adams_bashforth_moulton", 0.06).replace("restitution = 0.1", "restitution = 0.7");
    let warnings = plan("light_ab2", &light).warnings;
    assert!(!warnings.iter().any(|w| stable_step(&w)), "{warnings:#?}");
}

#[test]
fn stages_that_take_the_whole_run_are_warned_at_the_stage_that_ends_it() {
    // 0.004 s + 0.006 s of stages that end only by time fill run.duration = 0.01 s: the physics never
    // starts. A stage that may end sooner (on the unbalanced force ratio) counts for nothing.
    let stage = |name: &str, time: f64, extra: &str| {
        format!("[[scene.stages]]\nname = \"{name}\"\nuntil.time = {time}\n{extra}damping.local = 0.1\n")
    };
    let text = format!("{SMALL_SCENE}{}{}", stage("fill", 0.004, ""), stage("calm", 0.006, ""));
    let warnings = plan("stages_past_the_run", &text).warnings;
    let past = with_key(&warnings, "scene.stages.calm.until.time");
    assert_eq!(past.len(), 1, "{warnings:#?}");
    assert_eq!(past[0].location.map(|l| l.line), Some(11));
    assert!(past[0].reason.starts_with("the stages up to \"calm\" last 0.01 s, run.duration = 0.01 s: the physics"));
    let sooner = format!(
        "{SMALL_SCENE}{}{}",
        stage("fill", 0.004, ""),
        stage("calm", 0.006, "until.unbalanced_force_ratio = 0.01\n")
    );
    let warnings = plan("stages_may_end_sooner", &sooner).warnings;
    assert!(with_key(&warnings, "scene.stages.calm.until.time").is_empty(), "{warnings:#?}");
}
