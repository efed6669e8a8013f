//! The largest stable step of each integrator by damping ratio: polydisperse depositions (the disks
//! poured from up to the top of a 0.5 m box) at a ladder of contact-time fractions and restitutions,
//! each run straight through and restarted mid-way from its own state (disks and contact history,
//! the same scene: its step resolved afresh from the restart's own contact time). A case settles when
//! both settle with their energy balance within tolerance; the largest fraction at which every seed
//! settles is the scheme's stable step at that damping ratio, the measurement behind
//! [`crate::physics::stability::stable_contact_time_fraction`].

use std::path::PathBuf;

use rayon::prelude::*;

use super::stability_map::Outcome;
use super::{BenchError, CsvRow, markdown_table, scheme_name, write_csv, write_file};
use crate::physics::config::{IntegratorKind, PlacementKind, SceneConfig};
use crate::physics::simulation::Control;
use crate::physics::stability::stable_contact_time_fraction;
use crate::physics::{RunRecord, RunStatus, run_scene, run_scene_with_history};

/// What to measure.
#[derive(Clone, Debug)]
pub struct StableStepOptions {
    /// Integrators, each with the contact-time fractions it is run at.
    pub schemes: Vec<(IntegratorKind, Vec<f64>)>,
    /// Coefficients of restitution.
    pub restitutions: Vec<f64>,
    /// Placement seeds per case.
    pub seeds: u64,
    /// Disks poured.
    pub count: usize,
    /// When the run is interrupted and restarted (s).
    pub restart_at: f64,
    /// Longest simulated time of a run (s).
    pub duration: f64,
    /// Where `stable_step.csv` and `stable_step.md` go.
    pub out_dir: PathBuf,
}

impl Default for StableStepOptions {
    fn default() -> Self {
        let paper = vec![0.04, 0.05, 0.06, 0.07, 0.085, 0.1, 0.12];
        let verlet = vec![0.07, 0.1, 0.12, 0.15, 0.2, 0.25];
        Self {
            schemes: vec![(IntegratorKind::AdamsBashforthMoulton, paper), (IntegratorKind::VelocityVerlet, verlet)],
            restitutions: vec![1.0, 0.9, 0.7, 0.5, 0.4, 0.2, 0.1],
            seeds: 5,
            count: 300,
            restart_at: 0.3,
            duration: 3.0,
            out_dir: PathBuf::from(super::LATEST_DIR),
        }
    }
}

/// One deposition, straight through and restarted.
#[derive(Clone, Debug, PartialEq)]
pub struct StepCase {
    /// Integrator.
    pub scheme: IntegratorKind,
    /// Coefficient of restitution.
    pub restitution: f64,
    /// The predicted damping ratio of the scene's hardest impact.
    pub damping_ratio: f64,
    /// Δt / t_c asked for.
    pub fraction: f64,
    /// Placement seed.
    pub seed: u64,
    /// The straight run.
    pub straight: Ending,
    /// The run restarted from its state at the restart time.
    pub restarted: Ending,
    /// The restart's time step over the straight run's.
    pub step_ratio: f64,
    /// Whether the case settled both ways at a smaller fraction (with the same seed).
    pub settles_finer: bool,
}

/// How one run ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ending {
    /// Its status.
    pub status: RunStatus,
    /// When it settled (s from its start), NaN if it did not.
    pub settle_time: f64,
    /// Largest error of its energy balance, over the energy available.
    pub energy_balance_error: f64,
    /// The scene's `limits.energy_balance_tolerance`.
    pub tolerance: f64,
}

impl Ending {
    fn of(record: &RunRecord, tolerance: f64) -> Self {
        Self {
            status: record.status,
            settle_time: record.settle_time.unwrap_or(f64::NAN),
            energy_balance_error: record.energy_balance_error,
            tolerance,
        }
    }
}

impl StepCase {
    /// How its straight run ended.
    pub fn straight_outcome(&self) -> Outcome {
        self.outcome_of(&self.straight)
    }

    /// How its restart ended.
    pub fn restarted_outcome(&self) -> Outcome {
        self.outcome_of(&self.restarted)
    }

    fn outcome_of(&self, e: &Ending) -> Outcome {
        super::stability_map::outcome(e.status, e.energy_balance_error, e.tolerance, self.settles_finer)
    }

    /// Whether neither run failed: both settled, or neither where no smaller step settles either.
    pub fn settles(&self) -> bool {
        let fine = |o: Outcome| matches!(o, Outcome::Settles | Outcome::Unsettled);
        fine(self.straight_outcome()) && fine(self.restarted_outcome())
    }
}

impl CsvRow for StepCase {
    const COLUMNS: &'static [(&'static str, &'static str)] = &[
        ("scheme", ""),
        ("restitution", ""),
        ("damping_ratio", ""),
        ("contact_time_fraction", ""),
        ("seed", ""),
        ("straight", ""),
        ("straight_settle_time", "s"),
        ("straight_energy_balance_error", ""),
        ("restarted", ""),
        ("restarted_settle_time", "s"),
        ("restarted_energy_balance_error", ""),
        ("step_ratio", ""),
    ];
    fn values(&self) -> Vec<String> {
        let ending = |o: Outcome, e: &Ending| {
            [o.as_str().to_string(), format!("{:.4}", e.settle_time), format!("{:.2e}", e.energy_balance_error)]
        };
        let mut cells = vec![
            scheme_name(self.scheme).into(),
            self.restitution.to_string(),
            format!("{:.3}", self.damping_ratio),
            self.fraction.to_string(),
            self.seed.to_string(),
        ];
        cells.extend(ending(self.straight_outcome(), &self.straight));
        cells.extend(ending(self.restarted_outcome(), &self.restarted));
        cells.push(format!("{:.3}", self.step_ratio));
        cells
    }
}

/// The deposition of one case.
pub fn deposition(options: &StableStepOptions, scheme: IntegratorKind, restitution: f64, fraction: f64) -> SceneConfig {
    let mut s = SceneConfig::default();
    (s.particles.count, s.particles.radius, s.particles.radius_max) = (options.count, 0.004, Some(0.008));
    (s.domain.width, s.domain.height) = (0.3 * (options.count as f64 / 300.0).sqrt(), 0.5);
    s.material.restitution = Some(restitution);
    s.integrator.scheme = scheme;
    s.integrator.contact_time_fraction = Some(fraction);
    s.run.duration = options.duration;
    s
}

/// Runs every case, writes `stable_step.csv` (every case) and `stable_step.md` (per scheme and
/// restitution, the cases that settle at each fraction and the largest fraction at which all do).
pub fn stable_step(options: &StableStepOptions) -> Result<Vec<StepCase>, BenchError> {
    let mut cases = Vec::new();
    for (scheme, fractions) in &options.schemes {
        for &restitution in &options.restitutions {
            for &fraction in fractions {
                cases.extend((0..options.seeds).map(|seed| (*scheme, restitution, fraction, seed)));
            }
        }
    }
    let mut rows: Vec<StepCase> = cases
        .par_iter()
        .map(|&(scheme, restitution, fraction, seed)| step_case(options, scheme, restitution, fraction, seed))
        .collect::<Result<_, _>>()?;
    let settled: Vec<(IntegratorKind, f64, f64, u64)> = rows
        .iter()
        .filter(|r| r.straight.status == RunStatus::Settled && r.restarted.status == RunStatus::Settled)
        .map(|r| (r.scheme, r.restitution, r.fraction, r.seed))
        .collect();
    for r in &mut rows {
        let same = |s: &&(IntegratorKind, f64, f64, u64)| (s.0, s.1, s.3) == (r.scheme, r.restitution, r.seed);
        r.settles_finer = settled.iter().filter(same).any(|s| s.2 < r.fraction);
    }
    write_csv(&options.out_dir.join("stable_step.csv"), &rows)?;
    write_file(&options.out_dir.join("stable_step.md"), &summary(options, &rows))?;
    Ok(rows)
}

/// One case: the deposition straight through, and interrupted at the restart time and restarted.
fn step_case(
    options: &StableStepOptions,
    scheme: IntegratorKind,
    restitution: f64,
    fraction: f64,
    seed: u64,
) -> Result<StepCase, BenchError> {
    let mut scene = deposition(options, scheme, restitution, fraction);
    scene.placement.seed = seed;
    let tolerance = scene.limits.energy_balance_tolerance;
    let go = &mut |_: &_| Control::Continue;
    let straight = run_scene(&scene, None, go)?;
    let mut first = scene.clone();
    (first.run.duration, first.run.stop_at_settle) = (options.restart_at, false);
    let state = run_scene(&first, None, go)?.final_state;
    let mut rest = scene.clone();
    rest.placement.kind = PlacementKind::File;
    (rest.placement.file, rest.placement.contacts) = (Some("state.csv".into()), Some("state_contacts.csv".into()));
    rest.run.duration = scene.run.duration - options.restart_at;
    let restarted = run_scene_with_history(&rest, Some(state.initial_disks()), Some(&state.initial_contacts()), go)?;
    Ok(StepCase {
        scheme,
        restitution,
        damping_ratio: straight.stability.damping_ratio,
        fraction,
        seed,
        straight: Ending::of(&straight, tolerance),
        restarted: Ending::of(&restarted, tolerance),
        step_ratio: restarted.time_step / straight.time_step,
        settles_finer: false,
    })
}

/// The Markdown summary.
fn summary(options: &StableStepOptions, rows: &[StepCase]) -> String {
    let header = ["scheme", "e", "ζ", "settle (straight / restarted) at Δt/t_c", "measured edge", "engine's limit"];
    let mut table = Vec::new();
    for (scheme, fractions) in &options.schemes {
        for &restitution in &options.restitutions {
            let of = |f: f64| -> Vec<&StepCase> {
                rows.iter().filter(|r| r.scheme == *scheme && r.restitution == restitution && r.fraction == f).collect()
            };
            let Some(ratio) = of(fractions[0]).first().map(|r| r.damping_ratio) else { continue };
            let cells: Vec<String> = fractions
                .iter()
                .map(|&f| {
                    let cases = of(f);
                    let count =
                        |pick: fn(&StepCase) -> Outcome| cases.iter().filter(|c| pick(c) == Outcome::Settles).count();
                    let worst =
                        cases.iter().map(|c| worse(c)).max_by_key(|o| o.rank()).filter(|o| *o != Outcome::Settles);
                    let (straight, restarted) = (count(StepCase::straight_outcome), count(StepCase::restarted_outcome));
                    let worst = worst.map(|w| format!(" ({})", w.as_str())).unwrap_or_default();
                    let error = cases
                        .iter()
                        .flat_map(|c| [c.straight.energy_balance_error, c.restarted.energy_balance_error])
                        .map(f64::abs)
                        .fold(0.0, f64::max);
                    format!("{f}: {straight}/{restarted}{worst}, {}", percent(error))
                })
                .collect();
            let edge = fractions.iter().take_while(|&&f| of(f).iter().all(|c| c.settles())).last();
            table.push(vec![
                scheme_name(*scheme).to_string(),
                restitution.to_string(),
                format!("{ratio:.3}"),
                cells.join(", "),
                edge.map_or("—".into(), |f| f.to_string()),
                format!("{:.3}", stable_contact_time_fraction(*scheme, ratio)),
            ]);
        }
    }
    format!(
        "# The largest stable step by damping ratio\n\nRegenerate: `demsweep bench stable-step --update-results` \
         (writes `stable_step.csv`, `stable_step.md`).\n\n{} polydisperse disks (radii 4–8 mm) poured into a \
         {:.2} m wide, 0.5 m tall box, E = 1 GPa, μ = 0.5, for up to {} s; each case is run straight through and \
         restarted at {} s from its own state (the same scene, its step resolved from the restart's own contact \
         time), on {} placement seeds. A run settles when it comes to rest with its energy balance within \
         `limits.energy_balance_tolerance`; otherwise it is a limit cycle (it never comes to rest where a smaller \
         step of the same seed does, or the integration breaks the energy balance), a blow-up, or unsettled (it \
         does not come to rest at any step: the physics, not the step). Each cell: how many seeds settle straight through \
         / restarted, the worst failure, and the largest energy-balance error of all its runs. The measured edge is the largest fraction at which every seed \
         settles both ways; the engine's limit is `stable_contact_time_fraction` at the scene's damping ratio ζ \
         (its margin below the edge included). Every case is in `stable_step.csv`.\n\n{}\n",
        options.count,
        0.3 * (options.count as f64 / 300.0).sqrt(),
        options.duration,
        options.restart_at,
        options.seeds,
        markdown_table(&header, &table)
    )
}

/// A fraction as a percentage: one decimal below 10 %, none above.
fn percent(x: f64) -> String {
    let p = 100.0 * x;
    if p < 10.0 { format!("{p:.1} %") } else { format!("{p:.0} %") }
}

/// The worse outcome of a case's two runs.
fn worse(case: &StepCase) -> Outcome {
    let (a, b) = (case.straight_outcome(), case.restarted_outcome());
    if b.rank() > a.rank() { b } else { a }
}
