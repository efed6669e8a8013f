//! A lever range clipped at a validity limit holds on the placement seeds the tune's runs use: the
//! first 128 of the search's and of the verification's (they start past the run budget), more than a
//! tune of the default budget runs.

use demsweep::tune::model::first_verification_seed;
use demsweep::tune::validity::predicted_warnings;
use demsweep::tune::{LeverRange, load};
use std::path::Path;

#[test]
fn a_clipped_stiffness_holds_on_every_seed_a_tune_of_the_default_budget_runs() {
    // Uniform radii poured from 0.25 m: the softest Young's modulus the overlap limit allows depends on
    // the hardest impact, which differs from seed to seed.
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("results/bench/tune_scenes/uniform_damping_stiffness.toml");
    let spec = load(&file).expect("the bench's tune file loads");
    let lever = spec.levers.iter().find(|l| l.key == "material.youngs_modulus").expect("the stiffness lever");
    let LeverRange::Log { low, .. } = lever.range else { panic!("a log range: {:?}", lever.range) };
    assert!(low > 1e8, "the range was clipped: {low}");
    let first = first_verification_seed(spec.search.budget, spec.search.reference_seeds());
    for seed in (0..128).chain(first..first + 128) {
        let mut scene = spec.reference.clone();
        scene.material.youngs_modulus = low;
        scene.placement.seed = spec.reference.placement.seed + seed;
        let warnings = predicted_warnings(&scene, None).expect("it can start");
        assert!(warnings.is_empty(), "seed {seed} at E = {low}: {warnings:?}");
    }
}
