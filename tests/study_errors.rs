//! Malformed studies: each problem is reported with its file, line, key and reason, all at once.

mod study_support;

use std::path::Path;

use demsweep::study;
use study_support::{SMALL_SCENE, StudyDir, errors, errors_at, single_error};

/// SMALL_SCENE takes lines 1-4; a `[sweep]` header written after it is line 5.
const SWEEP_LINE: usize = 6;

fn sweep(name: &str, axes: &str) -> study::StudyError {
    let text = format!("{SMALL_SCENE}[sweep]\n{axes}\n");
    let key = format!("sweep.{}", axes.split(" =").next().unwrap());
    single_error(name, &text, SWEEP_LINE, &key)
}

#[test]
fn unreadable_study_file() {
    let errors = errors_at(Path::new("/nonexistent/nothing.toml"));
    assert_eq!(errors.len(), 1);
    assert!(
        errors[0].to_string().starts_with("/nonexistent/nothing.toml: cannot read the study file"),
        "{}",
        errors[0]
    );
}

#[test]
fn toml_syntax_error_names_the_line() {
    let e = &errors("syntax", "[scene]\nparticles.count = 20\nrun.duration = = 1\n")[0];
    assert_eq!(e.location.map(|l| l.line), Some(3));
    assert!(e.reason.starts_with("TOML syntax"), "{e}");
}

#[test]
fn unknown_scene_key() {
    let e = single_error(
        "unknown",
        "[scene]\nparticles.count = 20\n\n[scene.material]\npoison_ratio = 0.3\n",
        5,
        "scene.material.poison_ratio",
    );
    assert_eq!(e.reason, "unknown field `poison_ratio`: did you mean `poisson_ratio`?", "{e}");
    assert!(e.to_string().contains("unknown.toml:5:1: scene.material.poison_ratio: unknown field"), "{e}");
    let far = single_error("far", "[scene]\nparticles.count = 20\nmaterial.colour = 1\n", 3, "scene.material.colour");
    assert!(far.reason.starts_with("unknown field `colour`, expected one of `density`"), "no near field: {far}");
}

#[test]
fn misspelt_words_suggest_the_nearest_valid_one() {
    let choice = single_error(
        "choice",
        "[scene]\nparticles.count = 20\nplacement.kind = \"randon\"\n",
        3,
        "scene.placement.kind",
    );
    assert_eq!(choice.reason, "unknown variant `randon`: did you mean `random`?", "{choice}");
    let table = single_error("table", &format!("{SMALL_SCENE}[outptu]\nframes = true\n"), 5, "outptu");
    assert_eq!(table.reason, "unknown key (did you mean `output`?)", "{table}");
    let report = format!("{SMALL_SCENE}[sweep]\n\"material.friction\" = [0.2, 0.6]\n[report]\nreferense = 1\n");
    assert_eq!(
        single_error("report", &report, 8, "report.referense").reason,
        "unknown key (did you mean `reference`?)"
    );
}

#[test]
fn a_misspelt_sweep_axis_is_one_error_not_a_knock_on_one_about_the_reference() {
    let text = format!(
        "{SMALL_SCENE}[sweep]\n\"material.restitutin\" = [0.1, 0.5]\n\"material.friction\" = [0.2, 0.6]\n\
         [report]\nreference = {{ \"material.restitution\" = 0.1, \"material.friction\" = 0.2 }}\n"
    );
    let e = single_error("axis_typo", &text, SWEEP_LINE, "sweep.\"material.restitutin\"");
    assert_eq!(e.reason, "unknown field `restitutin`: did you mean `restitution`?", "{e}");
}

#[test]
fn wrong_type_names_the_expected_one() {
    let e = single_error("type", "[scene]\nparticles.count = \"many\"\n", 2, "scene.particles.count");
    assert!(e.reason.contains("invalid type: string \"many\""), "{e}");
    assert_eq!(e.location.unwrap().column, 11, "points at `count` in `particles.count`");
}

#[test]
fn a_refused_value_is_one_error_not_a_second_one_about_its_default() {
    // 30 disks fit a 5 cm box; the default count that stands in for the refused 30.0 does not.
    let text = "[scene]\nparticles.count = 30.0\ndomain.width = 0.05\n";
    let e = single_error("count_float", text, 2, "scene.particles.count");
    assert!(e.reason.contains("expected a whole number"), "{e}");
}

#[test]
fn a_time_step_too_small_to_finish_is_refused_once() {
    let e = single_error(
        "tiny_dt",
        "[scene]\nparticles.count = 20\nintegrator.time_step = 5e-324\n",
        1,
        "scene.run.duration",
    );
    assert!(e.reason.starts_with("needs inf steps of integrator.time_step"), "{}", e.reason);
}

#[test]
fn non_positive_time_step() {
    let e = single_error(
        "dt",
        "[scene]\nparticles.count = 20\nintegrator.time_step = 0.0\n",
        3,
        "scene.integrator.time_step",
    );
    assert_eq!(e.reason, "must be a finite number > 0, got 0");
}

#[test]
fn extreme_values_are_echoed_exactly_and_short() {
    let e = single_error("tiny", "[scene]\nparticles.count = 20\ndomain.width = 1e-300\n", 3, "scene.domain.width");
    assert_eq!(e.reason, "1e-300 m is narrower than the largest disk diameter 0.02 m");
    let e = single_error("huge", "[scene]\nparticles.count = 20\ndamping.local = -2.5e200\n", 3, "scene.damping.local");
    assert_eq!(e.reason, "must lie in [0, 1), got -2.5e200");
    let e = single_error("count", "[scene]\nparticles.count = 1e200\n", 2, "scene.particles.count");
    assert_eq!(e.reason, "invalid type: floating point `1e200`, expected a whole number ≥ 0");
}

#[test]
fn time_step_given_twice_names_both_keys() {
    let e = single_error(
        "dt-twice",
        "[scene]\nparticles.count = 20\nintegrator.time_step = 1e-5\nintegrator.contact_time_fraction = 0.05\n",
        4,
        "scene.integrator.contact_time_fraction",
    );
    assert_eq!(e.reason, "give either integrator.time_step or integrator.contact_time_fraction, not both");
    let text = "[scene]\nparticles.count = 20\n[sweep]\n\"integrator.rayleigh_fraction\" = [0.1]\n\"integrator.contact_time_fraction\" = [0.05]\n";
    let e = single_error("fractions", text, 4, "sweep.\"integrator.rayleigh_fraction\"");
    assert!(e.reason.contains("integrator.contact_time_fraction or integrator.rayleigh_fraction"), "{e}");
}

#[test]
fn swept_poisson_ratio_outside_its_range_names_value_and_run() {
    let text =
        format!("{SMALL_SCENE}[sweep]\n\"material.friction\" = [0.1, 0.5]\n\"material.poisson_ratio\" = [0.3, 0.7]\n");
    let e = single_error("nu", &text, 7, "sweep.\"material.poisson_ratio\"");
    assert_eq!((e.value.as_deref(), e.run.as_deref(), e.runs_affected), (Some("0.7"), Some("r0001"), 2));
    assert!(e.to_string().ends_with(
        "nu.toml:7:1: sweep.\"material.poisson_ratio\": value 0.7 (run r0001 and 1 more run): \
         Poisson's ratio must lie in (-1, 0.5], got 0.7"
    ));
}

#[test]
fn disks_that_cannot_fit_are_caught_before_running() {
    let text = "[scene]\nparticles.count = 3000\nplacement.max_attempts = 50\n";
    let e = single_error("jam", text, 2, "scene.particles.count");
    assert!(e.reason.starts_with("random placement fit only"), "{e}");
    let lattice = "[scene]\nparticles.count = 3000\nplacement.kind = \"lattice\"\n";
    assert!(single_error("lattice", lattice, 2, "scene.particles.count").reason.contains("the lattice fits only"));
}

#[test]
fn disks_that_cannot_fit_are_one_error_for_all_seeds_with_their_count() {
    let text = "[scene]\nparticles.count = 3000\nplacement.max_attempts = 50\n[sweep]\nreplicates = 4\n";
    let e = single_error("jam_seeds", text, 2, "scene.particles.count");
    assert_eq!((e.run.as_deref(), e.runs_affected), (Some("r0000"), 4), "{e}");
    assert!(e.to_string().contains("(run r0000 and 3 more runs): random placement fit only"), "{e}");
}

#[test]
fn a_length_in_mm_that_makes_the_box_too_small_is_named_with_its_si_value() {
    let normal = "[scene.particles.size_distribution]\nkind = \"normal\"\nmean = 4\nstd = 0.5\nmin = 3\nmax = 5\n";
    let found = errors("mm_distribution", normal);
    let reasons: Vec<String> = found.iter().map(|e| format!("{}: {}", e.key, e.reason)).collect();
    assert!(reasons.iter().any(|r| r.starts_with("scene.domain.width: 0.4 m is narrower")), "{reasons:#?}");
    let mean = "scene.particles.size_distribution.mean: 4 m is implausible for this key (plausible: 1e-7 to 1 m); \
                units are SI: did you mean 0.004 m (4 mm)";
    assert!(reasons.iter().any(|r| r.starts_with(mean)), "{reasons:#?}");
    assert!(reasons.iter().all(|r| !r.starts_with("scene.particles.size_distribution.std")), "0.5 m is plausible");
    let radius = errors("mm_radius", "[scene]\nparticles.radius = 7\n");
    assert_eq!(radius.len(), 2, "{radius:#?}");
    assert_eq!((radius[1].key.as_str(), radius[1].location.map(|l| l.line)), ("scene.particles.radius", Some(2)));
    assert!(radius[1].reason.contains("units are SI: did you mean 0.007 m (7 mm)"), "{}", radius[1]);
}

#[test]
fn zero_disks() {
    let e = single_error("zero", "[scene]\nparticles.count = 0\n", 2, "scene.particles.count");
    assert_eq!(e.reason, "a scene needs at least one disk, got 0");
}

#[test]
fn malformed_axes() {
    assert!(sweep("empty", "\"material.friction\" = []").reason.contains("at least one value"));
    assert!(
        sweep("logzero", "\"material.beta\" = { log = [0.0, 10.0], steps = 3 }").reason.contains("ends must be > 0")
    );
    assert!(sweep("steps0", "\"material.beta\" = { linear = [1, 2], steps = 0 }").reason.contains("at least 1, got 0"));
    assert!(
        sweep("steps1", "\"material.beta\" = { linear = [1, 2], steps = 1 }").reason.contains("ends 1 and 2 differ")
    );
    assert!(sweep("scalar", "\"material.beta\" = 0.5").reason.contains("got a single float"));
    assert!(sweep("nested", "\"material.beta\" = [[1, 2]]").reason.contains("found an array"));
}

#[test]
fn a_misspelt_sweep_keyword_is_named() {
    let e = sweep("replicate", "replicate = 3");
    assert!(e.reason.ends_with("did you mean `replicates`?"), "{e}");
    assert!(sweep("zips", "zips = []").reason.ends_with("did you mean `zip`?"));
    assert!(sweep("seed", "seed = [1, 2]").reason.ends_with("nor `replicates` or `zip`"));
}

#[test]
fn sweeping_an_unknown_key_is_reported_on_the_axis_line() {
    let e = sweep("unknownaxis", "\"material.stiffness\" = [1.0, 2.0]");
    assert!(e.reason.starts_with("unknown field `stiffness`"), "{e}");
    assert_eq!(e.value, None, "one report for the axis, not one per value");
    let floats = format!("{SMALL_SCENE}[sweep]\n\"particles.count\" = {{ linear = [10, 20], steps = 3 }}\n");
    let per_value = errors("axistype", &floats);
    let values: Vec<Option<&str>> = per_value.iter().map(|e| e.value.as_deref()).collect();
    assert_eq!(values, [Some("10.0"), Some("15.0"), Some("20.0")]);
    assert!(
        per_value[1].reason.starts_with("invalid type: floating point `15.0`, expected a whole number ≥ 0"),
        "{}",
        per_value[1]
    );
    let into_value = sweep("intovalue", "\"material.friction.x\" = [1.0]");
    assert_eq!(into_value.reason, "invalid type: map, expected a number");
    let set = format!("{SMALL_SCENE}material.friction = 0.5\n[sweep]\n\"material.friction.x\" = [1.0]\n");
    let e = single_error("intoset", &set, 7, "sweep.\"material.friction.x\"");
    assert_eq!(e.reason, "cannot sweep this key: scene.material.friction is a float, not a table");
}

#[test]
fn zip_groups_must_match() {
    let axes = "\"material.friction\" = [0.1, 0.2]\n\"material.beta\" = [1.0, 2.0, 3.0]\nzip = [\"material.friction\", \"material.beta\"]";
    let e = single_error("ziplen", &format!("{SMALL_SCENE}[sweep]\n{axes}\n"), 8, "sweep.zip");
    assert_eq!(e.reason, "zipped axes must have equal lengths: material.friction has 2, material.beta has 3");
    let unknown = "\"material.friction\" = [0.1]\nzip = [\"material.friction\", \"material.density\"]";
    let e = single_error("zipname", &format!("{SMALL_SCENE}[sweep]\n{unknown}\n"), 7, "sweep.zip");
    assert_eq!(e.reason, "\"material.density\" is not a sweep axis");
}

#[test]
fn duplicate_axes_and_replicates_clashing_with_a_seed_axis() {
    let twice = format!("{SMALL_SCENE}[sweep]\n\"material.friction\" = [0.1]\nmaterial.friction = [0.2]\n");
    let e = single_error("dup", &twice, 7, "sweep.\"material.friction\"");
    assert_eq!(e.reason, "swept twice (also on line 6)");
    let seeds = format!("{SMALL_SCENE}[sweep]\n\"placement.seed\" = [1, 2]\nreplicates = 2\n");
    assert!(single_error("seedrep", &seeds, 6, "sweep.\"placement.seed\"").reason.contains("not both"));
}

#[test]
fn unknown_top_level_key_and_bad_output() {
    let e = single_error("top", "[scene]\nparticles.count = 20\n[sweeps]\na = [1]\n", 3, "sweeps");
    assert!(e.reason.starts_with("unknown key"), "{e}");
    let e = single_error("output", "[scene]\nparticles.count = 20\n[output]\nframe = false\n", 4, "output.frame");
    assert!(e.reason.starts_with("unknown field `frame`"), "{e}");
}

#[test]
fn placement_file_problems_name_the_csv_line_and_column() {
    let dir = StudyDir::new("csverr");
    let text = "[scene]\nplacement.kind = \"file\"\nplacement.file = \"init.csv\"\n";
    let study = dir.write("s.toml", text);
    let missing = errors_at(&study);
    assert_eq!((missing.len(), missing[0].key.as_str()), (1, "scene.placement.file"));
    assert_eq!(missing[0].location.map(|l| l.line), Some(3));
    assert!(missing[0].reason.contains("init.csv: cannot read"), "{}", missing[0]);
    dir.write("init.csv", "x,y,vx\n0.1,0.1,0\n0.2,0.1,abc\n");
    let bad = &errors_at(&study)[0];
    assert!(bad.reason.ends_with("init.csv: line 3, column 3 (vx): \"abc\" is not a number"), "{bad}");
    dir.write("init.csv", "x,y\n");
    assert!(errors_at(&study)[0].reason.ends_with("line 1: the file has a header but no disks"));
    dir.write("init.csv", "x,y\n0.1,0.1\n0.5,0.1\n");
    assert!(errors_at(&study)[0].reason.starts_with("disk 2 (x = 0.5, y = 0.1, r = 0.01) is not inside the box"));
}

#[test]
fn a_placement_file_without_radii_refuses_a_radius_key_that_draws_radii() {
    let dir = StudyDir::new("drawn-radii");
    dir.write("init.csv", "x,y\n0.1,0.1\n0.2,0.1\n0.3,0.1\n");
    dir.write("init.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x y\n1 0.1 0.1\n");
    let mix = "particles.size_distribution = { kind = \"discrete\", radii = [0.002, 0.004], fractions = [1, 2] }\n";
    for (file, kind, radii) in [
        ("init.csv", "file", mix),
        ("init.csv", "file", "particles.radii = [0.004, 0.004, 0.004]\n"),
        ("init.dump", "lammps", "particles.radius_max = 0.02\n"),
    ] {
        let text = format!("[scene]\nplacement.kind = \"{kind}\"\nplacement.file = \"{file}\"\n{radii}");
        let errors = errors_at(&dir.write("s.toml", &text));
        assert_eq!((errors.len(), errors[0].key.as_str()), (1, "scene.placement.file"), "{errors:#?}");
        let key = radii.split(" =").next().unwrap();
        let reason = format!(
            "{key} draws radii for generated placements only: give every disk's radius in the file, or remove {key} \
             so that every disk gets particles.radius"
        );
        assert!(errors[0].reason.contains(file) && errors[0].reason.ends_with(&reason), "{}", errors[0]);
    }
}

#[test]
fn contact_file_problems_name_the_csv_line_column_and_key() {
    let dir = StudyDir::new("contacterr");
    let text =
        "[scene]\nplacement.kind = \"file\"\nplacement.file = \"init.csv\"\nplacement.contacts = \"contacts.csv\"\n";
    let study = dir.write("s.toml", text);
    dir.write("init.csv", "x,y,r\n0.1,0.01,0.01\n0.12,0.01,0.01\n");
    let missing = errors_at(&study);
    assert_eq!((missing.len(), missing[0].key.as_str()), (1, "scene.placement.contacts"));
    assert_eq!(missing[0].location.map(|l| l.line), Some(4));
    assert!(missing[0].reason.contains("contacts.csv: cannot read"), "{}", missing[0]);
    dir.write("contacts.csv", "first,second,tangential_spring\n0,1,1e-7\n0,2,0\n");
    let out_of_range = &errors_at(&study)[0];
    assert!(
        out_of_range.reason.ends_with(
            "contacts.csv: line 3, column 2 (second): disk 2 is out of range: the placement file has 2 disks (0 to 1)"
        ),
        "{out_of_range}"
    );
    dir.write("contacts.csv", "first,second,tangential_spring,law_state\n0,1,1e-7,0\n1,-1,-2e-7,0\n");
    let plan = study::load(&study).unwrap_or_else(|e| panic!("{e}"));
    let contacts = plan.runs[0].initial_contacts.as_deref().expect("the contact history is planned with the run");
    assert_eq!(contacts.len(), 2);
    let generated = "[scene]\nplacement.contacts = \"contacts.csv\"\n";
    let e = single_error("contactsrandom", generated, 2, "scene.placement.contacts");
    assert!(e.reason.contains("placement.kind = \"file\""), "{e}");
}

#[test]
fn all_problems_at_once_sorted_by_line() {
    let text = "colour = \"red\"\n[scene]\nparticles.count = 20\nmaterial.density = -1.0\nmaterial.wobble = 1\n\
                [sweep]\n\"material.friction\" = []\n\"run.duration\" = { log = [0, 1], steps = 2 }\n";
    let errors = errors("many", text);
    let found: Vec<(usize, &str)> = errors.iter().map(|e| (e.location.unwrap().line, e.key.as_str())).collect();
    assert_eq!(
        found,
        [
            (1, "colour"),
            (4, "scene.material.density"),
            (5, "scene.material.wobble"),
            (7, "sweep.\"material.friction\""),
            (8, "sweep.\"run.duration\"")
        ]
    );
    let shown = study::StudyErrors(errors).to_string();
    assert_eq!(shown.lines().count(), 5);
}

#[test]
fn a_base_scene_problem_is_reported_once_for_all_runs() {
    let text =
        "[scene]\nparticles.count = 20\nsettle.hold_time = -1.0\n[sweep]\n\"material.friction\" = [0.1, 0.2, 0.3]\n";
    let e = single_error("shared", text, 3, "scene.settle.hold_time");
    assert_eq!((e.run.as_deref(), e.runs_affected), (Some("r0000"), 3));
}

#[test]
fn an_empty_table_with_a_misspelt_name_is_not_ignored() {
    let e = single_error("emptytable", "[scene]\nparticles.count = 20\n[scene.materail]\n", 3, "scene.materail");
    assert!(e.reason.starts_with("unknown field `materail`"), "{e}");
}

#[test]
#[cfg(target_os = "linux")]
fn a_scene_too_large_for_memory_is_an_error_not_a_crash() {
    let text = "[scene]\nparticles.count = 100000000000\ndomain.width = 1000.0\ndomain.height = 1000.0\n";
    let e = single_error("huge", text, 2, "scene.particles.count");
    assert!(e.reason.starts_with("100000000000 disks need about 85.6 TB of memory to simulate"), "{e}");
    assert!(e.reason.contains("but this machine has") && e.reason.contains("(MemTotal in /proc/meminfo)"), "{e}");
}

#[test]
fn initial_disks_overlapping_beyond_the_divergence_limit_are_errors() {
    let dir = StudyDir::new("csvoverlap");
    let study = dir.write("s.toml", "[scene]\nplacement.kind = \"file\"\nplacement.file = \"init.csv\"\n");
    dir.write("init.csv", "x,y,r\n0.1,0.1,0.01\n0.3,0.1,0.01\n0.305,0.1,0.01\n");
    let e = &errors_at(&study)[0];
    assert_eq!((e.key.as_str(), e.location.map(|l| l.line)), ("scene.placement.file", Some(3)));
    assert_eq!(
        e.reason,
        "disks 2 and 3 (rows 2 and 3 of the file) overlap by 1.5 radii, beyond limits.max_overlap_ratio = 0.5: \
         the run would end as diverged at t = 0"
    );
    dir.write("init.csv", "x,y,r\n0.1,0.004,0.01\n0.2,0.1,0.01\n0.395,0.2,0.01\n");
    let e = &errors_at(&study)[0];
    assert_eq!(
        e.reason,
        "disk 1 (x = 0.1, y = 0.004, r = 0.01) crosses the floor by 0.6 radii, beyond limits.max_overlap_ratio = 0.5: \
         the run would end as diverged at t = 0; 2 overlaps beyond the limit in all"
    );
}

#[test]
fn unsafe_study_names_are_refused_with_the_rule() {
    for (name, problem) in [
        ("../../x", "contains '/'"),
        ("/abs/path", "contains '/'"),
        (".", "starts with '.'"),
        ("a\\u0000b", "contains '\\0'"),
        ("bell\\u0007", "contains '\\u{7}'"),
    ] {
        let text = format!("name = \"{name}\"\n{SMALL_SCENE}");
        let e = single_error("badname", &text, 1, "name");
        assert!(e.reason.contains(problem), "{name}: {e}");
        assert!(e.reason.contains(study::name::NAME_RULE), "{e}");
    }
    let long = format!("name = \"{}\"\n{SMALL_SCENE}", "n".repeat(560));
    assert!(single_error("longname", &long, 1, "name").reason.contains("has 560 characters"));
}

#[test]
fn an_unsafe_file_stem_asks_for_a_name() {
    let dir = StudyDir::new("stem");
    let errors = errors_at(&dir.write("my (draft).toml", SMALL_SCENE));
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].key, "name");
    assert!(errors[0].reason.contains("comes from the file name: set `name"), "{}", errors[0]);
}

#[test]
fn a_duplicate_key_is_named_with_its_table() {
    let e = single_error("dup", "[scene]\nparticles.count = 20\nparticles.count = 30\n", 3, "scene.particles.count");
    assert_eq!(e.reason, "TOML syntax: `particles.count` is given twice in this table: keep one of them");
}

#[test]
fn a_number_for_a_choice_lists_the_choices() {
    let text = format!("{SMALL_SCENE}[sweep]\n\"integrator.scheme\" = [1, 2]\n");
    let e = single_error("enum-axis", &text, SWEEP_LINE, "sweep.\"integrator.scheme\"");
    assert_eq!(e.reason, "must be `adams_bashforth_moulton` or `velocity_verlet` (a string in quotes)");
    let e = single_error(
        "enum-key",
        "[scene]\nparticles.count = 20\nintegrator.scheme = 1\n",
        3,
        "scene.integrator.scheme",
    );
    assert!(e.reason.starts_with("must be `adams_bashforth_moulton` or"), "{e}");
}

#[test]
fn a_whole_number_toml_cannot_hold_names_its_key() {
    let text = "[scene]\nparticles.count = 20\nplacement.seed = 18446744073709551616\n";
    let e = single_error("seed_out_of_range", text, 3, "scene.placement.seed");
    assert_eq!(
        e.reason,
        "18446744073709551616 is out of range: TOML whole numbers lie between -9223372036854775808 and 9223372036854775807"
    );
}

#[test]
#[cfg(target_os = "linux")]
fn too_many_frames_blame_the_frame_interval() {
    let text = "[scene]\nparticles.count = 20\nrun.frame_interval = 1e-12\n";
    let e = single_error("frames", text, 3, "scene.run.frame_interval");
    assert!(e.reason.contains("frames need about") && e.reason.contains("raise run.frame_interval"), "{e}");
}

#[test]
fn wrong_types_say_what_to_write_not_rust_types() {
    let errors = errors("plain", "[scene]\nparticles.count = 1.5\nmaterial.density = \"x\"\n");
    let reasons: Vec<&str> = errors.iter().map(|e| e.reason.as_str()).collect();
    assert_eq!(
        reasons,
        [
            "invalid type: floating point `1.5`, expected a whole number ≥ 0",
            "invalid type: string \"x\", expected a number"
        ]
    );
}

#[test]
fn a_byte_order_mark_is_accepted_in_studies_and_placement_files() {
    let dir = StudyDir::new("bom");
    dir.write("init.csv", "\u{feff}x,y,r\n0.05,0.05,0.002\n");
    let text = "\u{feff}[scene]\nplacement.kind = \"file\"\nplacement.file = \"init.csv\"\n";
    let plan = study::load(&dir.write("bom.toml", text)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plan.runs[0].scene.particles.count, 1);
}

#[test]
#[cfg(unix)]
fn an_endless_file_is_refused_as_a_device_or_by_size() {
    let text = "[scene]\nplacement.kind = \"file\"\nplacement.file = \"/dev/zero\"\n";
    let e = single_error("devzero", text, 3, "scene.placement.file");
    assert!(e.reason.ends_with("/dev/zero: cannot read: not a regular file (a device)"), "{e}");
    let errors = errors_at(Path::new("/dev/zero"));
    assert!(errors[0].reason.ends_with("the file is larger than the 4 MiB allowed"), "{}", errors[0]);
}

#[test]
fn bad_dropped_and_lowered_placements_name_their_key() {
    let reason = |line: &str, key: &str| single_error("placement", &format!("{SMALL_SCENE}{line}\n"), 5, key).reason;
    let lowered = "scene.placement.lowered_by";
    assert_eq!(reason("placement.lowered_by = -0.1", lowered), "must be a finite number >= 0, got -0.1");
    assert_eq!(
        reason("placement.lowered_by = 0.595", lowered),
        "0.595 m leaves 0.005 m of domain.height = 0.6 m for the disks, less than the largest diameter 0.02 m"
    );
    let dropped = "placement.kind = \"dropped\"\nplacement.lowered_by = 0.1";
    let e = single_error("lowered_dropped", &format!("{SMALL_SCENE}{dropped}\n"), 6, lowered);
    assert!(e.reason.starts_with("lowers a random or lattice placement: dropped disks start at rest"), "{e}");
    let sideways = reason("placement.kind = \"dropped\"\ngravity = [1.0, -9.81]", "scene.placement.kind");
    assert_eq!(
        sideways,
        "dropped placement rests each disk on what lies below it: it needs gravity = [0, g] with g < 0, got [1, -9.81]"
    );
}

#[test]
fn a_dropped_pile_above_the_box_is_refused_at_the_swept_kind() {
    // One row of 20 touching disks fits the 0.4 m box: the lattice passes, the dropped pile does not.
    let low = "domain.height = 0.03\nplacement.lattice_gap = 0\n";
    let text = format!("{SMALL_SCENE}{low}[sweep]\n\"placement.kind\" = [\"lattice\", \"dropped\"]\n");
    let e = single_error("too_low", &text, SWEEP_LINE + 2, "sweep.\"placement.kind\"");
    assert!(e.reason.starts_with("dropped placement fit only "), "{e}");
    assert!(e.reason.contains(" of 20 disks in the 0.4 m wide box below domain.height = 0.03 m"), "{e}");
    assert!(e.to_string().contains("(run r0001)"), "{e}");
}

#[test]
fn a_non_finite_number_in_an_unused_contact_models_table_is_refused_by_key() {
    for (text, value) in [("nan", "NaN"), ("inf", "inf")] {
        let study = format!("{SMALL_SCENE}[scene.contact.linear]\nnormal_stiffness = {text}\n");
        let errors = errors("unused_nan", &study);
        assert_eq!(errors.len(), 1, "{errors:#?}");
        assert_eq!(errors[0].key, "scene.contact.linear.normal_stiffness", "{}", errors[0]);
        assert_eq!(errors[0].location.map(|l| l.line), Some(6), "{}", errors[0]);
        assert!(errors[0].reason.contains(&format!("must be a finite number, got {value}")), "{}", errors[0]);
    }
}

/// A study of `count` stages named by 200 characters each (223 bytes of the stage table's
/// description a stage; 2 of them give the row's offsets past 255 bytes).
fn many_stages(count: usize) -> String {
    let mut text = SMALL_SCENE.to_string();
    for k in 0..count {
        text.push_str(&format!("[[scene.stages]]\nname = \"{:x<200}\"\nuntil.time = 1e-5\n", format!("s{k}_")));
    }
    text
}

#[test]
fn more_stages_than_a_results_file_can_describe_are_refused_at_check_with_the_limit() {
    // 8 + 293 x 223 = 65347 bytes fit in HDF5's 65535; 294 stages need 65570.
    let errors = errors("too_many_stages", &many_stages(294));
    assert_eq!(errors.len(), 1, "{errors:#?}");
    assert_eq!(errors[0].key, "scene.stages", "{}", errors[0]);
    assert!(
        errors[0].reason.starts_with("294 stages need 65570 bytes to describe their end times in the results file, past HDF5's limit of 65535 bytes"),
        "{}",
        errors[0]
    );
    // The most that fit are run and stored.
    let dir = StudyDir::new("most_stages");
    let study = dir.write("most.toml", &many_stages(293));
    let out = dir.path.join("out");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["run", study.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(out.join("most.h5").exists());
}
