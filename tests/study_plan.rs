//! Study expansion: counts, order, ids, ranges, zip groups, replicates, placement files, bundled studies.

mod study_support;

use std::path::Path;
use std::sync::Arc;

use demsweep::physics::config::PlacementKind;
use demsweep::study::{self, ParamValue, Plan};
use study_support::{SMALL_SCENE, StudyDir, plan};

fn floats(plan: &Plan, axis: usize) -> Vec<f64> {
    plan.runs
        .iter()
        .map(|r| match &r.parameters[axis].1 {
            ParamValue::Float(v) => *v,
            other => panic!("not a float: {other:?}"),
        })
        .collect()
}

#[test]
fn product_runs_first_axis_slowest_with_padded_ids() {
    let text = format!(
        "{SMALL_SCENE}[sweep]\n\"material.restitution\" = [0.2, 0.5, 0.8]\n\
         \"material.friction\" = {{ linear = [0.0, 0.6], steps = 4 }}\n"
    );
    let p = plan("product", &text);
    assert_eq!(p.runs.len(), 12);
    let ids: Vec<&str> = p.runs.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(ids[..3], ["r0000", "r0001", "r0002"]);
    assert_eq!(ids[11], "r0011");
    assert!(p.runs.iter().enumerate().all(|(i, r)| r.index == i));
    assert_eq!(floats(&p, 0), [0.2, 0.2, 0.2, 0.2, 0.5, 0.5, 0.5, 0.5, 0.8, 0.8, 0.8, 0.8]);
    assert_eq!(floats(&p, 1)[..4], [0.0, 0.2, 0.4, 0.6]);
    let run = &p.runs[6];
    assert_eq!(run.parameters[0].0, "material.restitution");
    assert_eq!(run.parameters[1].0, "material.friction");
    assert_eq!((run.scene.material.restitution, run.scene.material.friction), (Some(0.5), 0.4));
    assert_eq!(run.scene.particles.count, 20, "unswept keys keep the base scene's values");
}

#[test]
fn log_axis_hits_decades_and_ends_exactly() {
    let text = format!("{SMALL_SCENE}[sweep]\n\"material.youngs_modulus\" = {{ log = [1e8, 1e10], steps = 5 }}\n");
    let p = plan("log", &text);
    let e: Vec<f64> = p.runs.iter().map(|r| r.scene.material.youngs_modulus).collect();
    assert_eq!((e[0], e[2], e[4]), (1e8, 1e9, 1e10));
    assert!((e[1] / 10f64.powf(8.5) - 1.0).abs() < 1e-11, "{}", e[1]);
    assert_eq!(floats(&p, 0), e);
}

#[test]
fn zip_groups_vary_together_at_their_first_axis() {
    let text = format!(
        "{SMALL_SCENE}[sweep]\n\"material.restitution\" = [0.2, 0.5, 0.8]\n\"material.density\" = [1000, 2000]\n\
         \"material.friction\" = [0.1, 0.3, 0.5]\nzip = [\"material.restitution\", \"material.friction\"]\n"
    );
    let p = plan("zip", &text);
    assert_eq!(p.runs.len(), 6);
    let pairs: Vec<(f64, f64, f64)> = p
        .runs
        .iter()
        .map(|r| (r.scene.material.restitution.unwrap(), r.scene.material.density, r.scene.material.friction))
        .collect();
    assert_eq!(
        pairs,
        [
            (0.2, 1000.0, 0.1),
            (0.2, 2000.0, 0.1),
            (0.5, 1000.0, 0.3),
            (0.5, 2000.0, 0.3),
            (0.8, 1000.0, 0.5),
            (0.8, 2000.0, 0.5)
        ]
    );
    assert_eq!(p.runs[1].parameters[1], ("material.density".to_string(), ParamValue::Int(2000)));
}

#[test]
fn several_zip_groups() {
    let text = format!(
        "{SMALL_SCENE}[sweep]\n\"material.restitution\" = [0.2, 0.8]\n\"material.friction\" = [0.1, 0.5]\n\
         \"material.density\" = [1000.0, 2000.0, 3000.0]\n\"material.rolling_friction\" = [0.0, 0.1, 0.2]\n\
         zip = [[\"material.restitution\", \"material.friction\"], [\"material.density\", \"material.rolling_friction\"]]\n"
    );
    let p = plan("zip2", &text);
    assert_eq!(p.runs.len(), 6);
    let m = &p.runs[5].scene.material;
    assert_eq!((m.restitution, m.friction, m.density, m.rolling_friction), (Some(0.8), 0.5, 3000.0, 0.2));
}

#[test]
fn replicates_get_consecutive_seeds_fastest() {
    let text =
        format!("{SMALL_SCENE}placement.seed = 100\n[sweep]\n\"material.friction\" = [0.1, 0.5]\nreplicates = 3\n");
    let p = plan("replicates", &text);
    assert_eq!(p.runs.len(), 6);
    let seeds: Vec<u64> = p.runs.iter().map(|r| r.scene.placement.seed).collect();
    assert_eq!(seeds, [100, 101, 102, 100, 101, 102]);
    assert_eq!(
        p.runs[4].parameters,
        [
            ("material.friction".to_string(), ParamValue::Float(0.5)),
            ("placement.seed".to_string(), ParamValue::Int(101))
        ]
    );
}

#[test]
fn nested_and_quoted_axis_keys_are_the_same_axis_and_strings_sweep_enums() {
    let text = format!(
        "{SMALL_SCENE}[sweep]\nmaterial.friction = [0.1, 0.5]\n\"integrator.scheme\" = [\"adams_bashforth_moulton\", \"velocity_verlet\"]\n"
    );
    let p = plan("nested", &text);
    assert_eq!(p.runs.len(), 4);
    assert_eq!(p.runs[1].parameters[0].0, "material.friction");
    assert_eq!(p.runs[1].parameters[1].1, ParamValue::Text("velocity_verlet".into()));
    assert_eq!(p.runs[1].scene.integrator.scheme, demsweep::physics::config::IntegratorKind::VelocityVerlet);
}

#[test]
fn same_study_same_ids_and_fingerprint_and_text_changes_the_fingerprint() {
    let text = format!("{SMALL_SCENE}[sweep]\n\"material.friction\" = {{ linear = [0.1, 0.5], steps = 3 }}\n");
    let (a, b) = (plan("stable", &text), plan("stable", &text));
    let ids = |p: &Plan| p.runs.iter().map(|r| (r.id.clone(), r.parameters.clone())).collect::<Vec<_>>();
    assert_eq!(ids(&a), ids(&b));
    assert_eq!(a.fingerprint, b.fingerprint);
    assert_eq!(a.fingerprint.len(), 16);
    let c = plan("stable", &format!("{text}# a comment\n"));
    assert_ne!(a.fingerprint, c.fingerprint);
    assert_eq!(a.study_text, text);
}

#[test]
fn single_run_study_takes_name_output_and_cost() {
    let p = plan("single", &format!("{SMALL_SCENE}[output]\nframes = false\n"));
    assert_eq!(p.name, "single");
    assert_eq!(p.runs.len(), 1);
    assert_eq!(p.runs[0].id, "r0000");
    assert!(p.runs[0].parameters.is_empty());
    assert_eq!(p.runs[0].estimated_cost, 20.0 * 1000.0);
    assert_eq!(p.total_cost(), 20.0 * 1000.0);
    assert!(p.output.histories && p.output.final_states && !p.output.frames);
    let named = plan("named", &format!("name = \"my study\"\n{SMALL_SCENE}"));
    assert_eq!(named.name, "my study");
}

#[test]
fn ids_widen_beyond_ten_thousand_runs() {
    let text = "[scene]\nparticles.count = 2\nrun.duration = 1e-4\n[sweep]\n\
                \"material.friction\" = { linear = [0.0, 1.0], steps = 101 }\n\
                \"material.rolling_friction\" = { linear = [0.0, 1.0], steps = 101 }\n";
    let p = plan("wide", text);
    assert_eq!(p.runs.len(), 10_201);
    assert_eq!((p.runs[0].id.as_str(), p.runs[10_200].id.as_str()), ("r00000", "r10200"));
    assert_eq!(p.runs[10_200].scene.material.rolling_friction, 1.0);
    assert_eq!(p.runs[102].scene.material.friction, 0.01);
}

#[test]
fn placement_file_sets_count_and_is_shared_by_runs() {
    let dir = StudyDir::new("csvplan");
    std::fs::create_dir(dir.path.join("init")).unwrap();
    dir.write("init/three.csv", "x,y,vy\n0.1,0.1,0\n0.2,0.1,-1.5\n0.3,0.1,0\n");
    let text = "[scene]\nplacement.kind = \"file\"\nplacement.file = \"init/three.csv\"\nrun.duration = 0.01\n\
                [sweep]\n\"material.friction\" = [0.1, 0.5]\n";
    let p = study::load(&dir.write("csv.toml", text)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(p.runs.len(), 2);
    let (a, b) = (p.runs[0].initial.as_ref().unwrap(), p.runs[1].initial.as_ref().unwrap());
    assert!(Arc::ptr_eq(a, b));
    assert_eq!(a.len(), 3);
    assert_eq!((a[1].x, a[1].vy, a[1].r), (0.2, -1.5, 0.01));
    assert_eq!(p.runs[0].scene.particles.count, 3);
    assert_eq!(p.runs[0].scene.placement.kind, PlacementKind::File);
    assert_eq!(p.runs[0].estimated_cost, 3.0 * 1000.0);
}

#[test]
fn bundled_studies_load() {
    let studies = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies");
    let load = |name: &str| study::load(&studies.join(name)).unwrap_or_else(|e| panic!("{e}"));
    let damping = load("damping_sweep.toml");
    assert_eq!(damping.runs.len(), 5 * 2 * 8, "5 restitutions x 2 frictions x 8 seeds");
    assert!(damping.runs.iter().all(|r| r.scene.run.stop_at_settle));
    let said: Vec<String> = damping.warnings.iter().map(ToString::to_string).collect();
    assert!(said.is_empty(), "the README's first study runs without warnings: {said:?}");
    let sf = load("stiffness_friction.toml");
    assert_eq!(sf.runs.len(), 9);
    assert_eq!(sf.runs[8].scene.material.youngs_modulus, 2e11);
    let step_ratio = sf.runs[0].time_step / sf.runs[8].time_step;
    assert!((step_ratio / 100f64.powf(0.4) - 1.0).abs() < 1e-3, "dt follows the contact time: {step_ratio}");
    assert!(sf.runs[0].estimated_cost < sf.runs[8].estimated_cost / 6.0, "soft runs are cheaper");
    let paper = load("paper_table1.toml");
    assert_eq!(paper.runs.len(), 1);
    let s = &paper.runs[0].scene;
    let m = &s.material;
    assert_eq!((m.density, m.youngs_modulus, m.shear_modulus, m.beta), (1000.0, 20000.0, Some(20000.0), Some(10.0)));
    assert_eq!((m.friction, m.rolling_friction, m.poisson_ratio), (0.5, 0.5, None));
    assert_eq!((s.particles.radius, s.particles.count, s.gravity), (0.01, 300, [0.0, -9.81]));
    assert_eq!((s.integrator.time_step, s.run.duration, s.run.stop_at_settle), (Some(1e-4), 3.0, false));
    assert_eq!((s.domain.width, s.domain.height), (0.4, 0.6));
    assert_eq!(s.run.frame_times, [0.0, 0.23, 0.45, 3.0]);
}
