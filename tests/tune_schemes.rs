//! The integrator scheme as a lever: on a stand-in where the paper's integrator (Adams-Bashforth-
//! Moulton) is stable to a smaller step than velocity Verlet and its time-step rungs never settle (a
//! limit cycle), the path ends at its first unsettled rung and the cheap corner takes velocity
//! Verlet at its own largest stable step, the answer.

mod tune_common;

use demsweep::physics::warning::{ValidityWarning, WarningKind};
use demsweep::study::ParamValue;
use demsweep::tune::model::{Evaluator, Job, Outcome, Role, RunFailure, Screen, SearchConfig, State, TuneError};
use demsweep::tune::search::search;
use tune_common::{dump, hash, normal, stand_in_config};

/// The first lever's fraction of the contact time at coordinate `u` (log range 0.01 to 0.2).
fn fraction(u: f64) -> f64 {
    0.01 * 20f64.powf(u)
}

/// The reference's fraction (with the paper's integrator).
const REFERENCE_FRACTION: f64 = 0.02;

/// The largest stable fraction of each scheme (the second lever: bin 0 the paper's integrator, bin 1
/// velocity Verlet).
fn stable(verlet: bool) -> f64 {
    if verlet { 0.12 } else { 0.054 }
}

/// Levers: the time step's fraction of the contact time and the scheme. A run costs 100 times the
/// reference's fraction over its own; it keeps the pile (metric 1, sd 0.01), except that the paper's
/// integrator above a fraction of 0.03 never settles (five times the cost unless cut). A fraction past
/// its scheme's stable one is predicted past the integrator's stable step. The standard settings are
/// (fraction, scheme) pairs: the first, the time step at its largest valid value with the user's
/// scheme, is the top of the time-step path.
struct StandIn {
    standards: Vec<(f64, bool)>,
    jobs: Vec<Job>,
}

impl StandIn {
    fn setting(&self, point: &[f64], standard: Option<usize>) -> (f64, bool) {
        match standard {
            Some(k) => self.standards[k],
            None => (fraction(point[0]), point[1] > 0.5),
        }
    }
}

impl Evaluator for StandIn {
    fn screen(&mut self, point: &[f64], standard: Option<usize>) -> Screen {
        let (f, verlet) = self.setting(point, standard);
        let warnings = match f > stable(verlet) {
            true => vec![ValidityWarning::new(WarningKind::IntegratorStability, f, stable(verlet))],
            false => Vec::new(),
        };
        Screen {
            identity: format!("{f} {verlet}"),
            predicted: Ok(warnings),
            resolved: Vec::new(),
            relative_cost: Some(REFERENCE_FRACTION / f),
        }
    }

    fn reference_identity(&mut self) -> String {
        format!("{REFERENCE_FRACTION} false")
    }

    fn step_down(&mut self, standard: usize, factor: f64) -> Option<usize> {
        let (f, verlet) = self.standards[standard];
        self.standards.push((f * factor, verlet));
        Some(self.standards.len() - 1)
    }

    fn evaluate(&mut self, jobs: &[Job]) -> Result<Vec<Outcome>, TuneError> {
        self.jobs.extend(jobs.iter().cloned());
        Ok(jobs
            .iter()
            .map(|job| {
                let (f, verlet) = match job.role {
                    Role::Reference => (REFERENCE_FRACTION, false),
                    _ => self.setting(&job.point, job.standard),
                };
                let key = hash(f.to_bits() ^ u64::from(verlet)) ^ job.seed.wrapping_mul(0x9e37_79b9);
                let settles = verlet || f <= 0.03;
                let cost = 100.0 * REFERENCE_FRACTION / f * if settles { 1.0 } else { 5.0 };
                let mut outcome = Outcome::settled(cost, vec![1.0 + 0.01 * normal(key)]);
                if !settles {
                    outcome.failure = Some(RunFailure::NotSettled);
                }
                if let Some(cap) = job.cap.filter(|&cap| cost > cap) {
                    (outcome.cost, outcome.failure) = (cap, Some(RunFailure::Cut { cap }));
                }
                outcome
            })
            .collect())
    }
}

fn config() -> SearchConfig {
    SearchConfig {
        levels: vec![None, Some(2)],
        home: vec![Some((REFERENCE_FRACTION / 0.01).ln() / 20f64.ln()), Some(0.25)],
        standards: 1,
        path: true,
        time_step: Some(0),
        ..stand_in_config()
    }
}

#[test]
fn paper_integrator_rungs_that_never_settle_leave_the_answer_to_velocity_verlet_at_its_own_step() {
    let mut stand_in = StandIn { standards: vec![(0.1, false)], jobs: Vec::new() };
    let config = config();
    let result = search(&config, &mut stand_in).unwrap();
    // The path's first rung (stepped down to the paper's integrator's stable step) never settles: the
    // path ends there.
    assert_eq!(result.path.0.len(), 1, "one rung: {:?}\n{}", result.path, dump(&result));
    let rung = &result.candidates[result.path.0[0]];
    assert!(rung.runs.iter().all(|o| o.failure.is_some()), "{}", dump(&result));
    // The first lever-space point run is velocity Verlet's cheap corner, at its own stable step.
    let first = result.candidates.iter().find(|c| c.standard.is_none() && !c.runs.is_empty()).expect("a point ran");
    let f = fraction(first.point[0]);
    assert!(first.point[1] > 0.5 && f > 0.08 && f <= stable(true), "the corner {:?}\n{}", first.point, dump(&result));
    let best = &result.candidates[result.recommended.unwrap_or_else(|| panic!("no answer:\n{}", dump(&result)))];
    let verified = result.assess_verification(best).expect("verified");
    assert_eq!(verified.state, State::Feasible);
    let cost = verified.cost / result.reference_cost();
    assert!(best.point[1] > 0.5 && cost < 0.25, "{cost} at {:?}\n{}", best.point, dump(&result));
}

/// A tune file whose levers are the integrator and the fraction of the contact time, the contacts
/// lightly damped (restitution 0.7): velocity Verlet is stable to a larger step than the paper's
/// integrator.
const SCHEME_TUNE: &str = r#"name = "schemes"
[scene]
domain.width = 0.1
domain.height = 0.2
particles.count = 40
particles.radius = 0.004
material.youngs_modulus = 1e10
material.restitution = 0.7
integrator.contact_time_fraction = 0.02
run.duration = 1.0
[levers]
"integrator.scheme" = ["adams_bashforth_moulton", "velocity_verlet"]
"integrator.contact_time_fraction" = { log = [0.01, 0.3] }
[keep]
packing_fraction_interior = 0.02
"#;

fn load_scheme_tune() -> demsweep::tune::spec::TuneSpec {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("tune_schemes_ranges");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("schemes.toml");
    std::fs::write(&path, SCHEME_TUNE).unwrap();
    demsweep::tune::load(&path).expect("the scheme tune file checks")
}

/// The scene of `values` and the kinds of validity warnings its reference placement predicts.
fn predicted(spec: &demsweep::tune::spec::TuneSpec, values: &[(String, ParamValue)]) -> Vec<WarningKind> {
    let scene = spec.scene(values).unwrap();
    demsweep::tune::validity::predicted_warnings(&scene, None).unwrap().into_iter().map(|w| w.kind).collect()
}

#[test]
fn each_scheme_has_its_own_time_step_top_and_the_range_keeps_the_largest() {
    let spec = load_scheme_tune();
    let fraction = &spec.levers[1];
    let demsweep::tune::spec::LeverRange::Log { high, .. } = fraction.range else { panic!("{:?}", fraction.range) };
    // Two time-step rungs first, one per scheme, the larger step first; then no other rung.
    let rungs: Vec<(ParamValue, f64)> = spec.standards[..2]
        .iter()
        .map(|s| match s.values.as_slice() {
            [(scheme_key, scheme), (step_key, ParamValue::Float(step))] => {
                assert_eq!(
                    (scheme_key.as_str(), step_key.as_str()),
                    ("integrator.scheme", "integrator.contact_time_fraction")
                );
                (scheme.clone(), *step)
            }
            other => panic!("{other:?}"),
        })
        .collect();
    let verlet = ParamValue::Text("velocity_verlet".into());
    let paper = ParamValue::Text("adams_bashforth_moulton".into());
    assert_eq!((&rungs[0].0, &rungs[1].0), (&verlet, &paper), "{rungs:?}");
    assert!(rungs[0].1 > 1.3 * rungs[1].1, "{rungs:?}");
    // The range's top is velocity Verlet's, not clipped at the paper integrator's stable step.
    assert_eq!(high, rungs[0].1);
    // Each top is valid at its own scheme; velocity Verlet's step is past the paper integrator's limit.
    let step = |x: f64| ("integrator.contact_time_fraction".to_string(), ParamValue::Float(x));
    let scheme = |s: &ParamValue| ("integrator.scheme".to_string(), s.clone());
    assert!(predicted(&spec, &[scheme(&verlet), step(rungs[0].1)]).is_empty());
    assert!(predicted(&spec, &[scheme(&paper), step(rungs[1].1)]).is_empty());
    assert!(predicted(&spec, &[scheme(&paper), step(rungs[0].1)]).contains(&WarningKind::IntegratorStability));
}
