//! Tune over protocols: stage keys, stage end conditions, `placement.lowered_by` and
//! `placement.kind` as levers of one tune file.

use std::path::Path;

use demsweep::study::ParamValue;

const FILE: &str = "results/bench/tune_scenes/protocol_fill_kind.toml";

#[test]
fn a_protocol_tune_file_loads_with_stage_and_placement_levers() {
    let spec = demsweep::tune::load(Path::new(FILE)).expect("the protocol tune file checks");
    let keys: Vec<&str> = spec.levers.iter().map(|l| l.key.as_str()).collect();
    assert_eq!(keys, ["stages.fill.damping.local", "stages.fill.until.time", "placement.lowered_by", "placement.kind"]);
    let stage = &spec.reference.stages[0];
    assert_eq!((stage.name.as_str(), stage.until.time, stage.damping.local), ("fill", Some(0.3), Some(0.1)));
}

#[test]
fn a_dropped_placement_combines_with_a_lowered_by_lever() {
    let spec = demsweep::tune::load(Path::new(FILE)).unwrap();
    for (kind_u, kind) in [(0.25, "random"), (0.75, "dropped")] {
        let values = spec.values(&[0.5, 0.5, 1.0, kind_u]);
        let lowered = values.iter().find(|(k, _)| k == "placement.lowered_by").map(|(_, v)| v.clone());
        let expected = if kind == "random" { 0.2 } else { 0.0 };
        assert_eq!(lowered, Some(ParamValue::Float(expected)), "{kind}: {values:?}");
        let scene = spec.scene(&values).unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert_eq!(scene.placement.lowered_by, expected);
        assert_eq!(scene.stages[0].until.time, Some(0.275), "the stage end condition is a lever");
        assert_eq!(scene.stages[0].damping.local, Some(0.3), "the stage key is a lever");
    }
}

#[test]
fn stage_levers_take_the_reference_stage_values() {
    let spec = demsweep::tune::load(Path::new(FILE)).unwrap();
    let values: Vec<(String, ParamValue)> = spec.reference_values().into_iter().map(|(k, v, _)| (k, v)).collect();
    let value = |key: &str| values.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
    assert_eq!(value("stages.fill.damping.local"), Some(ParamValue::Float(0.1)));
    assert_eq!(value("stages.fill.until.time"), Some(ParamValue::Float(0.3)));
    let home = spec.reference_coordinates();
    assert!((home[0].unwrap() - 0.1 / 0.6).abs() < 1e-9, "{home:?}");
    assert!((home[1].unwrap() - 0.25 / 0.45).abs() < 1e-9, "{home:?}");
}

#[test]
fn lowering_the_start_settles_sooner() {
    assert_eq!(demsweep::tune::ladder::dissipation("placement.lowered_by"), 1.0);
    assert_eq!(demsweep::tune::ladder::dissipation("stages.fill.damping.local"), 0.0);
}

/// A 30-disk deposition whose levers are a fill stage's local damping and end time.
const STAGE_TUNE: &str = r#"name = "stage_levers"
[scene]
particles.count = 30
particles.radius = 0.005
domain.width = 0.1
domain.height = 0.15
material.youngs_modulus = 5e10
material.restitution = 0.5
integrator.time_step = 7e-6
run.duration = 1.0
run.sample_interval = 2e-3
settle.hold_time = 0.03

[[scene.stages]]
name = "fill"
until.time = 0.1
damping.local = 0.1

[levers]
"stages.fill.damping.local" = { linear = [0.0, 0.6] }
"stages.fill.until.time" = { linear = [0.05, 0.3] }

[keep]
pile_height = 0.25

[search]
seeds = 2
max_seeds = 4
reference_seeds = 4
verify_seeds = 3
budget = 40
seed = 3
"#;

#[test]
fn a_tune_with_stage_levers_meets_its_brute_force_ladder() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("tune_protocol_ladder");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("stage_levers.toml");
    std::fs::write(&file, STAGE_TUNE).unwrap();
    let options = demsweep::bench::tune::TuneBenchOptions {
        tunes: vec![file],
        out_dir: dir.join("out"),
        work_dir: dir.join("work"),
        ladder_seeds: 2,
        ..Default::default()
    };
    let rows = demsweep::bench::tune::tune_bench(&options).expect("the tune and its ladder run");
    let row = &rows[0];
    // The ladder runs over the stage's keys and finds a cheaper stage setting than the reference's.
    assert!(row.ladder_best.contains("stages.fill."), "{}", row.ladder_best);
    assert!(row.ladder_ratio < 1.0, "{}", row.ladder_ratio);
    // Tune's verified answer within 1.25x of it (no answer counts as the reference's cost), within its spend.
    assert!(
        row.goal_met,
        "tune {} ({}) against the ladder's {} ({})",
        row.tune_answer, row.tune_ratio, row.ladder_best, row.ladder_ratio
    );
}
