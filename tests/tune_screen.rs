//! Tune's screen of candidates and `check` use the same, law-aware stability prediction: on a soft
//! linear-law scene both see the same impact overlap (the screen's as a typed warning's value, the
//! check's in its text at the digits it prints).

use demsweep::physics::warning::WarningKind;
use demsweep::tune::{Evaluator, TuneOptions};

/// A scene whose linear contacts (k_n = 1e3 N/m) are far too soft for a 0.3 m fall.
const SCENE: &str = r#"[scene]
particles.count = 30
particles.radius = 0.005
domain.width = 0.1
domain.height = 0.3
contact.law = "linear"
contact.linear.normal_stiffness = 1e3
integrator.time_step = 1e-5
run.duration = 0.5
"#;

/// The number after `prefix` in `text` (up to the next space).
fn number_after(text: &str, prefix: &str) -> f64 {
    let start = text.find(prefix).unwrap_or_else(|| panic!("{prefix:?} in {text:?}")) + prefix.len();
    text[start..].split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn tune_screen_and_check_predict_the_same_overlap_on_a_linear_law_scene() {
    let dir = std::env::temp_dir().join(format!("demsweep_tune_screen_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("soft_linear.toml");
    std::fs::write(&study, format!("name = \"soft_linear\"\n{SCENE}")).unwrap();
    let plan = demsweep::study::load(&study).expect("the study loads");
    let warning =
        plan.warnings.iter().map(|w| w.reason.clone()).find(|w| w.contains("would overlap")).expect("a warning");
    let checked = number_after(&warning, "would overlap ");

    let tune = dir.join("soft_linear_tune.toml");
    let levers = "[levers]\n\"material.restitution\" = { linear = [0.2, 0.8] }\n[keep]\npile_height = 0.25\n";
    std::fs::write(&tune, format!("name = \"soft_linear_tune\"\n{SCENE}{levers}")).unwrap();
    let spec = demsweep::tune::load(&tune).expect("the tune file loads");
    let options = TuneOptions { out_dir: Some(dir.clone()), ..Default::default() };
    let mut evaluator = demsweep::tune::RunEvaluator::new(&spec, &options);
    let screened = evaluator.screen(&[0.5], None).predicted.expect("the scene starts");
    let overlap = screened.iter().find(|w| w.kind == WarningKind::ImpactOverlap).expect("an impact overlap warning");
    let predicted: f64 = format!("{:.3}", overlap.value).parse().unwrap();
    println!("check: {checked} radii; tune's screen: {predicted} radii");
    assert!(checked > 1.0, "a soft linear contact overlaps by more than a radius: {checked}");
    assert_eq!(checked, predicted);
    std::fs::remove_dir_all(&dir).ok();
}
