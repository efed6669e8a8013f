//! Contact laws composed of sub-models: a composition no preset has, chosen by the scene's keys,
//! against the analytic impact of a linear spring-dashpot.

mod common;

use common::*;
use demsweep::physics::config::{IntegratorKind, SceneConfig};
use demsweep::physics::contact::{AnyLaw, ContactLawKind, DampingKind, NormalKind, RollingKind, TangentialKind};
use demsweep::physics::material::restitution_from_beta;

const E: f64 = 1e7;
const R: f64 = 0.01;
/// Normal stiffness of the linear spring (N/m).
const STIFFNESS: f64 = 1e5;

/// Angular frequency of the undamped disk-wall contact, √(k/m) (1/s).
fn omega() -> f64 {
    (STIFFNESS / disk_mass(R)).sqrt()
}

/// A frictionless scene without gravity whose `[contact]` is `contact` (TOML), with tension allowed
/// (the textbook spring-dashpot, which pulls until the overlap is gone) and material β `beta`.
fn scene(contact: &str, beta: f64) -> SceneConfig {
    let dt = std::f64::consts::PI / omega() / 2000.0;
    let mut scene = free_scene(E, IntegratorKind::AdamsBashforthMoulton, dt);
    scene.material.beta = Some(beta);
    let table = format!("allow_tension = true\nlinear.normal_stiffness = {STIFFNESS:e}\n{contact}");
    scene.contact = toml::from_str(&table).expect("a [contact] table");
    scene
}

/// A disk hitting the floor at 1 m/s; returns (restitution, contact duration) from per-step overlaps.
fn wall_impact(scene: &SceneConfig) -> (f64, f64) {
    assert_eq!(scene.validate().map_err(|issues| format!("{issues:?}")), Ok(()));
    assert_eq!(scene.contact.preset(), None, "a composition no preset has: {}", scene.contact.law_name());
    floor_impact::<AnyLaw>(scene, R)
}

/// The damped oscillator of damping ratio ζ: restitution `exp(−πζ/√(1−ζ²))` and contact duration
/// `π / (ω √(1−ζ²))`, against the measured pair.
fn assert_oscillator(what: &str, zeta: f64, (restitution, duration): (f64, f64)) {
    let theory = (restitution_from_beta(zeta), std::f64::consts::PI / (omega() * (1.0 - zeta * zeta).sqrt()));
    let errors = [restitution / theory.0 - 1.0, duration / theory.1 - 1.0];
    println!("{what}: ζ {zeta:.4}, restitution {restitution:.5} (theory {:.5}); relative errors {errors:?}", theory.0);
    // The last step in contact applies its damping for the whole step: an error of order ζ ω dt in
    // the restitution, which depends on where the end falls within a step (2 000 steps per contact).
    assert!(errors[0].abs() < 0.003 && errors[1].abs() < 1e-4, "{what}: {errors:?}");
}

#[test]
fn linear_spring_with_viscoelastic_damping_is_the_damped_oscillator_of_its_dissipation_time() {
    // c = A k: the damping ratio is A ω / 2.
    for zeta in [0.05, 0.2, 0.4] {
        let dissipation_time = 2.0 * zeta / omega();
        let contact = format!(
            "normal = \"linear\"\ntangential = \"linear\"\ndamping = \"viscoelastic\"\n\
                               viscoelastic.dissipation_time = {dissipation_time:e}"
        );
        // The material's β plays no part.
        assert_oscillator("linear+viscoelastic", zeta, wall_impact(&scene(&contact, 0.7)));
    }
}

#[test]
fn linear_preset_with_the_papers_damping_damps_at_sqrt_five_sixths_beta() {
    // c = 2√(5/6) β √(k m*): the damping ratio is √(5/6) β, not β as with the preset's own damping.
    for beta in [0.1, 0.3] {
        let measured = wall_impact(&scene("law = \"linear\"\ndamping = \"paper\"", beta));
        assert_oscillator("linear+paper+linear", (5.0_f64 / 6.0).sqrt() * beta, measured);
    }
}

#[test]
fn a_tangential_spring_that_does_not_fit_the_normal_one_fails_the_check_by_key() {
    let mut scene = scene("law = \"hertz_mindlin\"\nnormal = \"linear\"", 0.3);
    let issues = scene.validate().expect_err("mindlin with a linear spring");
    assert_eq!(issues.iter().map(|i| i.key.as_str()).collect::<Vec<_>>(), ["contact.tangential"]);
    scene.contact.tangential = Some(TangentialKind::Linear);
    assert_eq!(scene.validate().map_err(|issues| format!("{issues:?}")), Ok(()));
    assert_eq!(scene.contact.law, ContactLawKind::HertzMindlin);
    assert_eq!(scene.contact.law_name(), "linear+paper+linear");
}

#[test]
fn docs_model_lists_every_model_of_the_table_and_each_presets_composition() {
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/model.md")).unwrap();
    let table = docs
        .split("<!-- contact-models:begin -->\n")
        .nth(1)
        .and_then(|rest| rest.split("<!-- contact-models:end -->").next());
    let cells = |row: &str| -> Vec<String> { row.split('|').map(|c| c.trim().trim_matches('`').to_string()).collect() };
    let rows: Vec<Vec<String>> =
        table.expect("docs/model.md's contact-models table").lines().skip(2).map(cells).collect();
    let listed: Vec<(String, String)> = rows.iter().map(|r| (r[1].clone(), r[2].clone())).collect();
    let mut expected = Vec::new();
    for (key, names) in [
        ("contact.normal", NormalKind::NAMES),
        ("contact.damping", DampingKind::NAMES),
        ("contact.tangential", TangentialKind::NAMES),
        ("contact.rolling", RollingKind::NAMES),
        ("contact.law", ContactLawKind::NAMES),
    ] {
        expected.extend(names.iter().map(|name| (key.to_string(), name.to_string())));
    }
    assert_eq!(listed, expected, "docs/model.md's table of contact models against contact/table.rs");
    for (row, &law) in rows.iter().filter(|r| r[1] == "contact.law").zip(ContactLawKind::ALL) {
        let c = law.composition();
        let composition = format!("{}` + `{}` + `{}", c.normal.name(), c.damping.name(), c.tangential.name());
        assert!(row[3].starts_with(&composition), "{law:?}: {}", row[3]);
    }
}
