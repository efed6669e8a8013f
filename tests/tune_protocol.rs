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
