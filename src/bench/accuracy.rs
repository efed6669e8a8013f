//! Work-precision: error against run time for each integrator over time steps `t_c/5 … t_c/400`.
//!
//! Two problems, each measured at every time step:
//! - a **binary Hertz impact** of two equal disks, undamped (against Hertz theory: contact duration,
//!   largest overlap, restitution 1) and damped with restitution 0.5 (against the same impact at
//!   `t_c / impact_reference_ratio`, converged to about 1e-9);
//! - a **deposition** (disks poured into a box until settled), whose settle time, pile height, packing
//!   fraction and final energies are compared with a run at `t_c / deposition_reference_ratio`. The pile is
//!   chaotic: a copy of the reference run with one disk moved by 1 nm gives the *chaos floor*, the
//!   difference no time step can remove.
//!
//! `t_c` is the Hertz contact time of each problem's hardest impact (theory for the impact, the
//! engine's estimate for the deposition). Run time is wall-clock, single thread.

use std::path::PathBuf;

use super::{
    BenchError, CsvRow, SCHEMES, markdown_table, placed_disks, ratio_grid, relative_error, scheme_name, timed,
    write_csv, write_file,
};
use crate::physics::RunStatus;
use crate::physics::config::{IntegratorKind, PlacementKind, SceneConfig};
use crate::physics::contact::HertzMindlin;
use crate::physics::material::{Materials, beta_from_restitution};
use crate::physics::particles::InitialDisk;
use crate::physics::quantity::{self, PACKING_FRACTION, PILE_HEIGHT, SETTLE_TIME};
use crate::physics::record::RunRecord;
use crate::physics::simulation::Simulation;
use crate::plot::bench::{LogLogSeries, log_log_chart};
use crate::plot::{ChartOptions, Format};

/// `∫₀¹ (1 − x^{5/2})^{−1/2} dx`: half the Hertz contact time in units of `δ_max / v`.
const HERTZ_TIME_INTEGRAL: f64 = 1.471_637_592_162_352_1;

/// Disk radius of the impact (m).
const IMPACT_RADIUS: f64 = 0.01;

/// What to measure.
#[derive(Clone, Debug)]
pub struct AccuracyOptions {
    /// Integrators.
    pub schemes: Vec<IntegratorKind>,
    /// Coarsest time step, as `t_c / dt`.
    pub coarsest_ratio: f64,
    /// Finest time step, as `t_c / dt`.
    pub finest_ratio: f64,
    /// Time steps per halving.
    pub per_halving: u32,
    /// Young's modulus of both problems (Pa).
    pub youngs_modulus: f64,
    /// Approach speed of the binary impact (m/s).
    pub impact_speed: f64,
    /// `t_c / dt` of the damped impact's reference.
    pub impact_reference_ratio: f64,
    /// Disks in the deposition.
    pub deposition_count: usize,
    /// Longest simulated time of a deposition (s); runs stop when settled.
    pub deposition_duration: f64,
    /// `t_c / dt` of the deposition's reference run.
    pub deposition_reference_ratio: f64,
    /// Where `accuracy.csv`, `accuracy.md` and the charts go.
    pub out_dir: PathBuf,
}

impl Default for AccuracyOptions {
    fn default() -> Self {
        Self {
            schemes: SCHEMES.to_vec(),
            coarsest_ratio: 5.0,
            finest_ratio: 400.0,
            per_halving: 2,
            youngs_modulus: 1e9,
            impact_speed: 3.0,
            impact_reference_ratio: 20_000.0,
            deposition_count: 300,
            deposition_duration: 2.0,
            deposition_reference_ratio: 1600.0,
            out_dir: PathBuf::from(super::LATEST_DIR),
        }
    }
}

/// One observable of one problem at one scheme and time step.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyRow {
    /// `impact_undamped`, `impact_damped` or `deposition`.
    pub problem: &'static str,
    /// Integrator.
    pub scheme: IntegratorKind,
    /// `t_c / dt`.
    pub ratio: f64,
    /// Time step (s).
    pub time_step: f64,
    /// Wall-clock time of one run (s).
    pub run_time: f64,
    /// What is compared.
    pub observable: &'static str,
    /// Its value.
    pub value: f64,
    /// The theory's or the reference's value.
    pub reference: f64,
    /// `|value − reference| / |reference|`.
    pub relative_error: f64,
}

impl CsvRow for AccuracyRow {
    const COLUMNS: &'static [(&'static str, &'static str)] = &[
        ("problem", ""),
        ("scheme", ""),
        ("contact_time_over_dt", ""),
        ("time_step", "s"),
        ("run_time", "s"),
        ("observable", ""),
        ("value", ""),
        ("reference", ""),
        ("relative_error", ""),
    ];
    fn values(&self) -> Vec<String> {
        vec![
            self.problem.into(),
            scheme_name(self.scheme).into(),
            format!("{:.3}", self.ratio),
            format!("{:.6e}", self.time_step),
            format!("{:.6e}", self.run_time),
            self.observable.into(),
            format!("{:.10e}", self.value),
            format!("{:.10e}", self.reference),
            format!("{:.4e}", self.relative_error),
        ]
    }
}

/// Named observables of one run.
type Observables = Vec<(&'static str, f64)>;

/// Runs the benchmark; writes `accuracy.csv`, `accuracy.md` and `work_precision_*.png`.
pub fn accuracy(options: &AccuracyOptions) -> Result<Vec<AccuracyRow>, BenchError> {
    let mut rows = impact_rows(options, 0.0)?;
    rows.extend(impact_rows(options, beta_from_restitution(0.5))?);
    let (deposition, floor) = deposition_rows(options)?;
    rows.extend(deposition);
    write_csv(&options.out_dir.join("accuracy.csv"), &rows)?;
    let impact = vec!["contact_duration", "max_overlap", "restitution"];
    let problems = [("impact_undamped", impact.clone()), ("impact_damped", impact), ("deposition", resolvable(&floor))];
    for (problem, counted) in &problems {
        chart(options, &rows, problem, counted)?;
    }
    write_file(&options.out_dir.join("accuracy.md"), &summary(options, &rows, &problems, &floor))?;
    Ok(rows)
}

/// The impact scene: no gravity, 1 m box, two disks (set per run).
fn impact_scene(options: &AccuracyOptions, beta: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.domain.width = 1.0;
    s.domain.height = 1.0;
    s.gravity = [0.0, 0.0];
    s.material.youngs_modulus = options.youngs_modulus;
    s.material.beta = Some(beta);
    s.material.friction = 0.0;
    s.placement.kind = PlacementKind::File;
    s.placement.file = Some("in-memory".into());
    s
}

/// Hertz theory of the head-on impact: (largest overlap, contact duration).
fn hertz_theory(scene: &SceneConfig, speed: f64) -> (f64, f64) {
    let e_star = Materials::from_scene(scene).particle.e_star;
    let m_star =
        0.5 * scene.material.density * std::f64::consts::PI * IMPACT_RADIUS.powi(2) * scene.particles.thickness;
    let stiffness = 4.0 / 3.0 * e_star * (0.5 * IMPACT_RADIUS).sqrt();
    let overlap = (5.0 * m_star * speed * speed / (4.0 * stiffness)).powf(0.4);
    (overlap, 2.0 * HERTZ_TIME_INTEGRAL * overlap / speed)
}

/// Rows of the impact with damping `beta` at every scheme and time step.
fn impact_rows(options: &AccuracyOptions, beta: f64) -> Result<Vec<AccuracyRow>, BenchError> {
    let mut scene = impact_scene(options, beta);
    let speed = options.impact_speed;
    let (overlap, duration) = hertz_theory(&scene, speed);
    let (problem, reference) = if beta == 0.0 {
        ("impact_undamped", vec![("contact_duration", duration), ("max_overlap", overlap), ("restitution", 1.0)])
    } else {
        scene.integrator.time_step = Some(duration / options.impact_reference_ratio);
        ("impact_damped", binary_impact(&scene, speed))
    };
    let mut rows = Vec::new();
    for &scheme in &options.schemes {
        for ratio in ratio_grid(options.coarsest_ratio, options.finest_ratio, options.per_halving) {
            scene.integrator.scheme = scheme;
            scene.integrator.time_step = Some(duration / ratio);
            let (observed, run_time) = repeated_timing(|| binary_impact(&scene, speed));
            let at = Setting {
                problem,
                scheme,
                ratio,
                time_step: scene.integrator.fixed_time_step().unwrap_or_default(),
                run_time,
            };
            rows.extend(at.compare(&observed, &reference));
        }
    }
    Ok(rows)
}

/// Where a comparison was made.
struct Setting {
    problem: &'static str,
    scheme: IntegratorKind,
    ratio: f64,
    time_step: f64,
    run_time: f64,
}

impl Setting {
    /// One row per observable.
    fn compare(&self, observed: &Observables, reference: &Observables) -> Vec<AccuracyRow> {
        observed
            .iter()
            .zip(reference)
            .map(|((name, value), (_, reference))| AccuracyRow {
                problem: self.problem,
                scheme: self.scheme,
                ratio: self.ratio,
                time_step: self.time_step,
                run_time: self.run_time,
                observable: name,
                value: *value,
                reference: *reference,
                relative_error: relative_error(*value, *reference),
            })
            .collect()
    }
}

/// Runs `f` until at least 20 ms have passed; its result and the shortest seconds per call (the
/// machine may be shared: the shortest call is the least disturbed one).
fn repeated_timing<T>(mut f: impl FnMut() -> T) -> (T, f64) {
    let (mut value, mut shortest) = timed(&mut f);
    let mut total = shortest;
    while total < 0.02 {
        let (v, t) = timed(&mut f);
        (value, shortest, total) = (v, shortest.min(t), total + t);
    }
    (value, shortest)
}

/// Head-on impact of two equal disks approaching at `speed`, starting 0.1 R apart: contact duration
/// and largest overlap (interpolated between steps) and restitution.
fn binary_impact(scene: &SceneConfig, speed: f64) -> Observables {
    let r = IMPACT_RADIUS;
    let gap = 0.1 * r;
    let disks = [
        InitialDisk { x: 0.4, y: 0.5, r, vx: 0.5 * speed, ..Default::default() },
        InitialDisk { x: 0.4 + 2.0 * r + gap, y: 0.5, r, vx: -0.5 * speed, ..Default::default() },
    ];
    let mut sim = Simulation::<HertzMindlin>::new(scene, &disks);
    let overlap_now = |sim: &Simulation<HertzMindlin>| 2.0 * r - (sim.particles().x[1] - sim.particles().x[0]);
    let mut overlaps = vec![(0.0, -gap)];
    while overlaps.last().is_some_and(|(_, d)| *d <= 0.0) || overlaps.iter().all(|(_, d)| *d <= 0.0) {
        sim.advance(false);
        overlaps.push((sim.time(), overlap_now(&sim)));
    }
    let start = overlaps.iter().position(|(_, d)| *d > 0.0).expect("the disks meet");
    while overlaps.last().is_some_and(|(_, d)| *d > 0.0) {
        sim.advance(false);
        overlaps.push((sim.time(), overlap_now(&sim)));
    }
    let end = overlaps.len() - 1;
    let duration = zero_crossing(&overlaps, end) - zero_crossing(&overlaps, start);
    let rebound = sim.particles().vx[1] - sim.particles().vx[0];
    vec![
        ("contact_duration", duration),
        ("max_overlap", refined_peak(&overlaps[start - 1..=end])),
        ("restitution", rebound / speed),
    ]
}

/// Time at which a sampled signal crosses zero between samples `k − 1` and `k` (linear).
fn zero_crossing(samples: &[(f64, f64)], k: usize) -> f64 {
    let ((t0, v0), (t1, v1)) = (samples[k - 1], samples[k]);
    t0 + (t1 - t0) * v0 / (v0 - v1)
}

/// Largest value of a sampled signal, refined by a parabola through the largest sample and its
/// neighbours.
fn refined_peak(samples: &[(f64, f64)]) -> f64 {
    let k = (1..samples.len() - 1).max_by(|a, b| samples[*a].1.total_cmp(&samples[*b].1)).unwrap_or(0);
    if k == 0 {
        return samples.iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
    }
    let (a, b, c) = (samples[k - 1].1, samples[k].1, samples[k + 1].1);
    let curvature = a - 2.0 * b + c;
    if curvature == 0.0 { b } else { b - 0.125 * (a - c) * (a - c) / curvature }
}

/// The deposition: polydisperse disks poured into a 0.4 m box with friction and e = 0.5.
pub fn deposition_scene(options: &AccuracyOptions) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.domain.width = 0.4;
    s.domain.height = 0.6;
    s.particles.count = options.deposition_count;
    s.particles.radius = 0.008;
    s.particles.radius_max = Some(0.012);
    s.placement.seed = 7;
    s.material.youngs_modulus = options.youngs_modulus;
    s.material.restitution = Some(0.5);
    s.material.friction = 0.5;
    s.run.duration = options.deposition_duration;
    s.run.stop_at_settle = true;
    s
}

/// The deposition's observables; all NaN when the run diverged.
fn deposition_observables(rec: &RunRecord) -> Observables {
    let h = &rec.history;
    let observables = vec![
        (SETTLE_TIME.name, rec.settle_time.unwrap_or(f64::NAN)),
        (PILE_HEIGHT.name, rec.pile[PILE_HEIGHT.name]),
        (PACKING_FRACTION.name, rec.pile[PACKING_FRACTION.name]),
        ("final_potential_energy", RunRecord::last(&h.potential)),
        ("final_elastic_energy", RunRecord::last(&h.elastic)),
        ("final_dissipated_energy", RunRecord::last(&h.dissipated)),
    ];
    let diverged = rec.status == RunStatus::Diverged;
    observables.into_iter().map(|(name, value)| (name, if diverged { f64::NAN } else { value })).collect()
}

/// Copies of the reference deposition, each with another disk moved by 1 nm, for the chaos floor.
const CHAOS_COPIES: usize = 3;

/// Deposition rows at every scheme and time step, and the chaos floor (largest relative difference
/// per observable between the reference and its 1 nm-perturbed copies).
fn deposition_rows(options: &AccuracyOptions) -> Result<(Vec<AccuracyRow>, Observables), BenchError> {
    let mut scene = deposition_scene(options);
    let disks = placed_disks(&scene)?;
    let contact_time = crate::physics::predict_stability(&scene, &disks).contact_time;
    let observe = |scene: &SceneConfig, disks: &[InitialDisk]| -> Result<(Observables, f64), BenchError> {
        let (rec, seconds) = timed(|| super::run(scene, disks));
        Ok((deposition_observables(&rec?), seconds))
    };
    scene.integrator.time_step = Some(contact_time / options.deposition_reference_ratio);
    let (reference, _) = observe(&scene, &disks)?;
    let mut floor: Observables = reference.iter().map(|(n, _)| (*n, 0.0)).collect();
    for moved in 0..CHAOS_COPIES.min(disks.len()) {
        let mut nudged = disks.clone();
        nudged[moved].x += 1e-9;
        let (perturbed, _) = observe(&scene, &nudged)?;
        for ((_, worst), ((_, v), (_, r))) in floor.iter_mut().zip(perturbed.iter().zip(&reference)) {
            *worst = worst.max(relative_error(*v, *r));
        }
    }
    let mut rows = Vec::new();
    for &scheme in &options.schemes {
        for ratio in ratio_grid(options.coarsest_ratio, options.finest_ratio, options.per_halving) {
            scene.integrator.scheme = scheme;
            scene.integrator.time_step = Some(contact_time / ratio);
            let (observed, run_time) = observe(&scene, &disks)?;
            let at = Setting {
                problem: "deposition",
                scheme,
                ratio,
                time_step: scene.integrator.fixed_time_step().unwrap_or_default(),
                run_time,
            };
            rows.extend(at.compare(&observed, &reference));
        }
    }
    Ok((rows, floor))
}

/// Deposition observables count towards its work-precision error only when their chaos floor is
/// below this: a time step cannot make the others more accurate.
const RESOLVABLE_FLOOR: f64 = 0.01;

/// The observables whose chaos floor is below [`RESOLVABLE_FLOOR`].
fn resolvable(floor: &Observables) -> Vec<&'static str> {
    floor.iter().filter(|(_, e)| *e < RESOLVABLE_FLOOR).map(|(n, _)| *n).collect()
}

/// One point per scheme and time step of a problem: (run time, largest relative error over the
/// observables in `counted`, `t_c/dt`), in time-step order.
fn work_precision(
    rows: &[AccuracyRow],
    problem: &str,
    scheme: IntegratorKind,
    counted: &[&str],
) -> Vec<(f64, f64, f64)> {
    let mut points: Vec<(f64, f64, f64)> = Vec::new();
    let counts = |r: &&AccuracyRow| r.problem == problem && r.scheme == scheme && counted.contains(&r.observable);
    for row in rows.iter().filter(counts) {
        match points.last_mut() {
            Some(last) if last.2 == row.ratio => last.1 = worse(last.1, row.relative_error),
            _ => points.push((row.run_time, row.relative_error, row.ratio)),
        }
    }
    points
}

/// The larger error, NaN (a diverged run) counting as the worst.
fn worse(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) }
}

/// Draws `work_precision_<problem>.png`: largest relative error against run time, per scheme.
fn chart(options: &AccuracyOptions, rows: &[AccuracyRow], problem: &str, counted: &[&str]) -> Result<(), BenchError> {
    let series: Vec<LogLogSeries> = options
        .schemes
        .iter()
        .map(|s| LogLogSeries {
            label: scheme_name(*s).into(),
            points: work_precision(rows, problem, *s, counted).iter().map(|(t, e, _)| (*t, *e)).collect(),
        })
        .collect();
    let chart = ChartOptions { format: Format::Png, subject: Some(problem.replace('_', " ")), ..Default::default() };
    let path = options.out_dir.join(format!("work_precision_{problem}.png"));
    log_log_chart(
        "Work-precision",
        &quantity::labelled("run_time", "s"),
        "largest relative error",
        &series,
        &chart,
        &path,
    )
    .map_err(BenchError::from)
}

/// The fastest (scheme, `t_c/dt`, run time, error) reaching `target` error for a problem.
fn fastest(options: &AccuracyOptions, rows: &[AccuracyRow], (problem, counted): &Problem, target: f64) -> Vec<String> {
    let best = options
        .schemes
        .iter()
        .flat_map(|s| work_precision(rows, problem, *s, counted).into_iter().map(move |p| (*s, p)))
        .filter(|(_, (_, error, _))| *error <= target)
        .min_by(|a, b| a.1.0.total_cmp(&b.1.0));
    match best {
        Some((scheme, (time, error, ratio))) => vec![
            problem.to_string(),
            format!("{target:.0e}"),
            scheme_name(scheme).into(),
            format!("t_c/{ratio:.0}"),
            format!("{time:.3e}"),
            format!("{error:.2e}"),
        ],
        None => {
            vec![problem.to_string(), format!("{target:.0e}"), "none in range".into(), "".into(), "".into(), "".into()]
        }
    }
}

/// Errors of every observable of a problem per scheme and time step, as a Markdown table.
fn error_table(rows: &[AccuracyRow], problem: &str) -> String {
    let of_problem: Vec<&AccuracyRow> = rows.iter().filter(|r| r.problem == problem).collect();
    if of_problem.is_empty() {
        return String::new();
    }
    let same_run = |r: &&&AccuracyRow| r.scheme == of_problem[0].scheme && r.ratio == of_problem[0].ratio;
    let observables: Vec<&str> = of_problem.iter().take_while(same_run).map(|r| r.observable).collect();
    let run_time = quantity::labelled("run_time", "s");
    let mut header = vec!["scheme", "dt", run_time.as_str()];
    header.extend(&observables);
    let table: Vec<Vec<String>> = of_problem
        .chunks(observables.len())
        .map(|group| {
            let first = group[0];
            let mut cells = vec![
                scheme_name(first.scheme).into(),
                format!("t_c/{:.0}", first.ratio),
                format!("{:.3e}", first.run_time),
            ];
            cells.extend(group.iter().map(|r| format!("{:.2e}", r.relative_error)));
            cells
        })
        .collect();
    markdown_table(&header, &table)
}

/// A problem's name and the observables its work-precision error counts.
type Problem = (&'static str, Vec<&'static str>);

/// The Markdown summary.
fn summary(options: &AccuracyOptions, rows: &[AccuracyRow], problems: &[Problem], floor: &Observables) -> String {
    let targets = [[1e-2, 1e-3, 1e-4], [1e-2, 1e-3, 1e-4], [1e-1, 3e-2, 1e-2]];
    let best: Vec<Vec<String>> = problems
        .iter()
        .zip(targets)
        .flat_map(|(problem, targets)| targets.map(|t| fastest(options, rows, problem, t)))
        .collect();
    let floor_rows: Vec<Vec<String>> = floor.iter().map(|(n, e)| vec![n.to_string(), format!("{e:.2e}")]).collect();
    let scene = deposition_scene(options);
    format!(
        "# Work-precision benchmark\n\n\
         Regenerate: `demsweep bench accuracy --update-results` (writes this folder: `accuracy.csv`, `accuracy.md`, \
         `work_precision_*.png`).\n\n\
         Problems: a head-on impact of two disks (R = {IMPACT_RADIUS} m, E = {:e} Pa, ν = 0.3, {} m/s) undamped \
         against Hertz theory and with e = 0.5 against the same impact at t_c/{}; and a deposition of {} disks \
         (R {}–{} m, e = 0.5, μ = 0.5, {} m wide box, stopped when settled) against a run at t_c/{}. Time steps \
         t_c/{} … t_c/{}; errors are relative (NaN: the run diverged); a problem's error is the largest over its observables, for the deposition over \
         those whose chaos floor is below {RESOLVABLE_FLOOR} (every observable is in `accuracy.csv` and below). Run times: wall clock, one thread, on the machine that wrote this file.\n\n\
         ## Fastest setting for a target accuracy\n\n{}\n\
         ## Chaos floor of the deposition\n\nThe reference deposition against copies with one disk moved by 1 nm (largest of {CHAOS_COPIES}): \
         differences below these cannot be attributed to the time step.\n\n{}\n\
         ## Binary impact, undamped\n\n{}\n## Binary impact, e = 0.5\n\n{}\n## Deposition\n\n{}",
        options.youngs_modulus,
        options.impact_speed,
        options.impact_reference_ratio,
        options.deposition_count,
        scene.particles.radius,
        scene.largest_radius(),
        scene.domain.width,
        options.deposition_reference_ratio,
        options.coarsest_ratio,
        options.finest_ratio,
        markdown_table(
            &["problem", "error ≤", "scheme", "dt", quantity::labelled("run_time", "s").as_str(), "error"],
            &best
        ),
        markdown_table(&["observable", "relative difference"], &floor_rows),
        error_table(rows, "impact_undamped"),
        error_table(rows, "impact_damped"),
        error_table(rows, "deposition"),
    )
}
