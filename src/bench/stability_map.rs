//! Stability map: where runs fail over time step × stiffness × damping, per integrator, and how
//! that compares with the engine's pre-run prediction ([`crate::physics::stability::assess`]).
//!
//! The scene is a small pour (a few dozen disks dropped into a narrow box with friction), so every
//! case has hard impacts, disks with several contacts and a settling pile. The damping axis is β,
//! from undamped through the usual restitutions (β < 1) to the paper's heavily overdamped β = 10
//! and beyond; the restitution EDEM's relation gives for each β is reported with it. Time steps run
//! from `t_c / coarsest_ratio` down to `t_c / finest_ratio` (`t_c`: the predicted Hertz contact time
//! of the scene's hardest impact) but stop three grid points below both the predicted safe step and
//! the first observed blow-up: cases far inside the stable region add nothing to the boundary and
//! cost the most. A case fails when its run, or the same run restarted mid-way from its own state
//! (disks and contact history, the step at the same fraction of the restart's own contact time), blows
//! up — ends as `diverged` (NaN, energy growth, or an overlap beyond `limits.max_overlap_ratio`) — or
//! is caught in a limit cycle: its energy balance is off by more than `limits.energy_balance_tolerance`,
//! or it never settles where a smaller step of its column does (a pile that keeps rattling).

use std::path::PathBuf;

use rayon::prelude::*;

use super::{
    BenchError, CsvRow, SCHEMES, markdown_table, placed_disks, ratio_grid, scheme_name, write_csv, write_file,
};
use crate::physics::config::{IntegratorKind, PlacementKind, SceneConfig};
use crate::physics::material::restitution_from_beta;
use crate::physics::particles::InitialDisk;
use crate::physics::simulation::Control;
use crate::physics::{RunStatus, run_scene_with_history};
use crate::plot::ChartOptions;
use crate::plot::bench::{MapPanel, stability_map_chart};

/// What to sweep.
#[derive(Clone, Debug)]
pub struct StabilityMapOptions {
    /// Integrators.
    pub schemes: Vec<IntegratorKind>,
    /// Young's moduli (Pa).
    pub youngs_moduli: Vec<f64>,
    /// Damping factors β.
    pub betas: Vec<f64>,
    /// Sliding friction coefficients μ.
    pub frictions: Vec<f64>,
    /// Largest time step, as `t_c / dt`.
    pub coarsest_ratio: f64,
    /// Smallest time step, as `t_c / dt`.
    pub finest_ratio: f64,
    /// Time steps per halving.
    pub per_halving: u32,
    /// Disks in the pour.
    pub count: usize,
    /// Longest simulated time of one case (s); stable cases stop when settled.
    pub duration: f64,
    /// When each case is also restarted from its own state (s); `None`: no restarts.
    pub restart_at: Option<f64>,
    /// Where `stability_map.csv` and `stability_map.md` go.
    pub out_dir: PathBuf,
}

impl Default for StabilityMapOptions {
    fn default() -> Self {
        Self {
            schemes: SCHEMES.to_vec(),
            youngs_moduli: vec![1e6, 1e8, 1e10],
            betas: vec![0.0, 0.07, 0.215, 0.59, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0],
            frictions: vec![0.0, 0.2, 0.5],
            coarsest_ratio: 0.5,
            finest_ratio: 4096.0,
            per_halving: 2,
            count: 24,
            duration: 0.4,
            restart_at: Some(0.2),
            out_dir: PathBuf::from(super::LATEST_DIR),
        }
    }
}

/// One column of the map: everything but the time step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Column {
    /// Integrator.
    pub scheme: IntegratorKind,
    /// Young's modulus (Pa).
    pub youngs_modulus: f64,
    /// Damping factor β.
    pub beta: f64,
    /// Sliding friction μ.
    pub friction: f64,
}

/// One case of the map.
#[derive(Clone, Debug, PartialEq)]
pub struct MapRow {
    /// The scene's column.
    pub column: Column,
    /// Restitution EDEM's relation gives for β (0 when overdamped).
    pub restitution: f64,
    /// Time step (s).
    pub time_step: f64,
    /// Predicted contact time of the hardest impact (s).
    pub contact_time: f64,
    /// Δt / t_c.
    pub dt_over_contact_time: f64,
    /// Predicted damping rate (1/s).
    pub damping_rate: f64,
    /// Δt × damping rate.
    pub dt_times_damping_rate: f64,
    /// The engine's predicted safe time step (s).
    pub safe_time_step: f64,
    /// Whether the pre-run estimate warned about the time step or the material.
    pub warned: bool,
    /// The pre-run warnings, joined.
    pub warnings: String,
    /// How the run ended.
    pub status: RunStatus,
    /// The run's message (why it diverged), empty otherwise.
    pub message: String,
    /// Simulated time reached (s).
    pub simulated_time: f64,
    /// Largest error of the energy balance, over the energy available.
    pub energy_balance_error: f64,
    /// The scene's `limits.energy_balance_tolerance`.
    pub energy_balance_tolerance: f64,
    /// The run restarted mid-way from its own state; `None` when not restarted (it ended first).
    pub restart: Option<Restart>,
    /// Whether a smaller step of the same column settled (a run that did not settle is then caught
    /// in a limit cycle, not slow); set once the column is complete.
    pub settles_finer: bool,
}

/// How a case's run went when restarted mid-way from its own state.
#[derive(Clone, Debug, PartialEq)]
pub struct Restart {
    /// Its time step (s): the case's Δt / t_c of the restart's own contact time.
    pub time_step: f64,
    /// How it ended.
    pub status: RunStatus,
    /// Largest error of its energy balance, over the energy available.
    pub energy_balance_error: f64,
}

/// How a case ended, its run and its restart together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Settled with its energy balance within tolerance.
    Settles,
    /// Did not settle in its duration, and no smaller step of its column did either.
    Unsettled,
    /// Never settled where a smaller step did, or its energy balance is off.
    LimitCycle,
    /// Diverged.
    BlowUp,
}

impl Outcome {
    /// Its place from best to worst.
    pub fn rank(self) -> usize {
        self as usize
    }

    /// In a table.
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Settles => "settles",
            Outcome::Unsettled => "unsettled",
            Outcome::LimitCycle => "limit_cycle",
            Outcome::BlowUp => "blow_up",
        }
    }
}

/// How one run ended: `tolerance` is its energy balance tolerance, `settles_finer` whether a smaller
/// step of its column settled.
pub(super) fn outcome(status: RunStatus, energy_balance_error: f64, tolerance: f64, settles_finer: bool) -> Outcome {
    match status {
        RunStatus::Diverged => Outcome::BlowUp,
        _ if energy_balance_error.abs() > tolerance => Outcome::LimitCycle,
        RunStatus::Settled => Outcome::Settles,
        _ if settles_finer => Outcome::LimitCycle,
        _ => Outcome::Unsettled,
    }
}

impl MapRow {
    /// Whether the run or its restart blew up.
    pub fn blew_up(&self) -> bool {
        self.outcome() == Outcome::BlowUp
    }

    /// How the case ended: the worse of its run and its restart.
    pub fn outcome(&self) -> Outcome {
        let tolerance = self.energy_balance_tolerance;
        let run = outcome(self.status, self.energy_balance_error, tolerance, self.settles_finer);
        let restart = self
            .restart
            .as_ref()
            .map_or(Outcome::Settles, |r| outcome(r.status, r.energy_balance_error, tolerance, self.settles_finer));
        let rank = |o: Outcome| {
            [Outcome::Settles, Outcome::Unsettled, Outcome::LimitCycle, Outcome::BlowUp].iter().position(|x| *x == o)
        };
        if rank(restart) > rank(run) { restart } else { run }
    }

    /// Whether the case failed: blew up or caught in a limit cycle.
    pub fn failed(&self) -> bool {
        matches!(self.outcome(), Outcome::BlowUp | Outcome::LimitCycle)
    }

    /// Whether its run, and its restart if any, settled with the energy balance within tolerance.
    fn settled(&self) -> bool {
        self.outcome() == Outcome::Settles
    }

    /// What ended a failed case: `nan`, `overlap`, `energy_growth` (a blow-up of the run; `restart`
    /// when only the restart blew up) or `limit_cycle` (empty when it did not fail).
    pub fn failure(&self) -> &'static str {
        match self.message.split_whitespace().next() {
            _ if !self.failed() => "",
            _ if !self.blew_up() => "limit_cycle",
            _ if self.status != RunStatus::Diverged => "restart",
            Some("non-finite") => "nan",
            Some("overlap") => "overlap",
            _ => "energy_growth",
        }
    }
}

impl CsvRow for MapRow {
    const COLUMNS: &'static [(&'static str, &'static str)] = &[
        ("scheme", ""),
        ("youngs_modulus", "Pa"),
        ("beta", ""),
        ("friction", ""),
        ("restitution", ""),
        ("time_step", "s"),
        ("contact_time", "s"),
        ("dt_over_contact_time", ""),
        ("damping_rate", "1/s"),
        ("dt_times_damping_rate", ""),
        ("safe_time_step", "s"),
        ("warned", ""),
        ("status", ""),
        ("energy_balance_error", ""),
        ("restart_time_step", "s"),
        ("restart_status", ""),
        ("restart_energy_balance_error", ""),
        ("outcome", ""),
        ("failure", ""),
        ("simulated_time", "s"),
        ("message", ""),
        ("warnings", ""),
    ];
    fn values(&self) -> Vec<String> {
        vec![
            scheme_name(self.column.scheme).into(),
            format!("{:e}", self.column.youngs_modulus),
            self.column.beta.to_string(),
            self.column.friction.to_string(),
            format!("{:.4}", self.restitution),
            format!("{:.4e}", self.time_step),
            format!("{:.4e}", self.contact_time),
            format!("{:.4e}", self.dt_over_contact_time),
            format!("{:.4e}", self.damping_rate),
            format!("{:.4e}", self.dt_times_damping_rate),
            format!("{:.4e}", self.safe_time_step),
            self.warned.to_string(),
            self.status.as_str().into(),
            format!("{:.3e}", self.energy_balance_error),
            self.restart.as_ref().map_or(String::new(), |r| format!("{:.4e}", r.time_step)),
            self.restart.as_ref().map_or(String::new(), |r| r.status.as_str().into()),
            self.restart.as_ref().map_or(String::new(), |r| format!("{:.3e}", r.energy_balance_error)),
            self.outcome().as_str().into(),
            self.failure().into(),
            format!("{:.5}", self.simulated_time),
            self.message.clone(),
            self.warnings.clone(),
        ]
    }
}

/// The observed and predicted boundary of one column of the map.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    /// The column.
    pub column: Column,
    /// Predicted contact time (s).
    pub contact_time: f64,
    /// Predicted damping rate (1/s).
    pub damping_rate: f64,
    /// Predicted safe time step (s).
    pub safe_time_step: f64,
    /// Largest time step below which no case failed (s); `None` when the smallest failed.
    pub largest_stable: Option<f64>,
    /// Smallest time step that failed (s); `None` when none did.
    pub smallest_unstable: Option<f64>,
    /// What ended the smallest time step that failed (see [`MapRow::failure`]).
    pub failure: &'static str,
    /// Cases that failed without a pre-run warning.
    pub unwarned_failures: usize,
    /// Cases warned about that settled, restart included.
    pub warned_stable: usize,
}

/// The pour of one column (its time step is set per case).
pub fn map_scene(options: &StabilityMapOptions, column: &Column) -> SceneConfig {
    let mut s = SceneConfig::default();
    s.domain.width = 0.12;
    s.domain.height = 0.25;
    s.particles.count = options.count;
    s.material.youngs_modulus = column.youngs_modulus;
    s.material.beta = Some(column.beta);
    s.material.friction = column.friction;
    s.integrator.scheme = column.scheme;
    s.run.duration = options.duration;
    s.run.sample_interval = 5e-4;
    s.settle.hold_time = 0.02;
    s
}

/// Runs the map, writes `stability_map.csv` (every case) and `stability_map.md` (boundaries), and
/// returns the cases and the boundaries.
pub fn stability_map(options: &StabilityMapOptions) -> Result<(Vec<MapRow>, Vec<Boundary>), BenchError> {
    let columns = columns(options);
    let results: Vec<Result<Vec<MapRow>, BenchError>> = columns.par_iter().map(|c| map_column(options, c)).collect();
    let rows: Vec<MapRow> = results.into_iter().collect::<Result<Vec<_>, _>>()?.into_iter().flatten().collect();
    let boundaries: Vec<Boundary> = columns.iter().map(|c| boundary(&rows, c)).collect();
    write_csv(&options.out_dir.join("stability_map.csv"), &rows)?;
    write_file(&options.out_dir.join("stability_map.md"), &summary(options, &rows, &boundaries))?;
    chart(options, &rows, &boundaries)?;
    Ok((rows, boundaries))
}

/// Every combination of scheme, stiffness, β and μ.
fn columns(o: &StabilityMapOptions) -> Vec<Column> {
    let mut columns = Vec::new();
    for &scheme in &o.schemes {
        for &youngs_modulus in &o.youngs_moduli {
            for &beta in &o.betas {
                for &friction in &o.frictions {
                    columns.push(Column { scheme, youngs_modulus, beta, friction });
                }
            }
        }
    }
    columns
}

/// One column of the map: the time steps of one scene from coarse to fine, stopping three steps below
/// both the predicted safe step and the last blow-up.
fn map_column(options: &StabilityMapOptions, column: &Column) -> Result<Vec<MapRow>, BenchError> {
    let mut scene = map_scene(options, column);
    let disks = placed_disks(&scene)?;
    let contact_time = crate::physics::predict_stability(&scene, &disks).contact_time;
    let mut rows: Vec<MapRow> = Vec::new();
    let mut stable_below = 0;
    for ratio in ratio_grid(options.coarsest_ratio, options.finest_ratio, options.per_halving) {
        scene.integrator.time_step = Some(contact_time / ratio);
        let row = map_case(column, &scene, &disks, options.restart_at)?;
        let predicted_safe = row.time_step <= row.safe_time_step;
        let steady = !row.failed() || row.outcome() == Outcome::Unsettled;
        stable_below = if steady && predicted_safe { stable_below + 1 } else { 0 };
        rows.push(row);
        if stable_below > 2 {
            break;
        }
    }
    // From the finest step up: whether a smaller step than each settled.
    let mut settles_finer = false;
    for row in rows.iter_mut().rev() {
        row.settles_finer = settles_finer;
        settles_finer |= row.settled();
    }
    Ok(rows)
}

/// Runs one case, and restarts it at `restart_at` (s) from its own state if it runs that long.
fn map_case(
    column: &Column,
    scene: &SceneConfig,
    disks: &[InitialDisk],
    restart_at: Option<f64>,
) -> Result<MapRow, BenchError> {
    let rec = super::run(scene, disks)?;
    let st = &rec.stability;
    let restart = match restart_at {
        Some(at) if rec.simulated_time > at => Some(restarted(scene, disks, at, st.dt_over_contact_time)?),
        _ => None,
    };
    Ok(MapRow {
        column: *column,
        restitution: restitution_from_beta(column.beta),
        time_step: scene.integrator.fixed_time_step().unwrap_or_default(),
        contact_time: st.contact_time,
        dt_over_contact_time: st.dt_over_contact_time,
        damping_rate: st.damping_rate,
        dt_times_damping_rate: st.dt_times_damping_rate,
        safe_time_step: st.safe_time_step,
        warned: !st.warnings.is_empty(),
        warnings: st.warnings.iter().map(ToString::to_string).collect::<Vec<_>>().join(" | "),
        status: rec.status,
        message: rec.message.unwrap_or_default(),
        simulated_time: rec.simulated_time,
        energy_balance_error: rec.energy_balance_error,
        energy_balance_tolerance: scene.limits.energy_balance_tolerance,
        restart,
        settles_finer: false,
    })
}

/// `scene` run from `disks` to `at` (s), then restarted from its state (disks and contact history)
/// for the rest of its duration with the step at `fraction` of the restart's own contact time.
fn restarted(scene: &SceneConfig, disks: &[InitialDisk], at: f64, fraction: f64) -> Result<Restart, BenchError> {
    let mut first = scene.clone();
    (first.run.duration, first.run.stop_at_settle) = (at, false);
    let state = super::run(&first, disks)?.final_state;
    let mut rest = scene.clone();
    rest.placement.kind = PlacementKind::File;
    (rest.placement.file, rest.placement.contacts) = (Some("state.csv".into()), Some("state_contacts.csv".into()));
    rest.run.duration = scene.run.duration - at;
    let restart_disks = state.initial_disks();
    rest.integrator.time_step = Some(fraction * crate::physics::predict_stability(&rest, &restart_disks).contact_time);
    let observe = &mut |_: &_| Control::Continue;
    let rec = run_scene_with_history(&rest, Some(restart_disks), Some(&state.initial_contacts()), observe)?;
    Ok(Restart { time_step: rec.time_step, status: rec.status, energy_balance_error: rec.energy_balance_error })
}

/// The boundary of one column from its rows.
fn boundary(rows: &[MapRow], key: &Column) -> Boundary {
    let mut column: Vec<&MapRow> = rows.iter().filter(|r| r.column == *key).collect();
    column.sort_by(|a, b| a.time_step.total_cmp(&b.time_step));
    let first = column[0];
    let smallest_unstable = column.iter().find(|r| r.failed());
    let largest_stable = column.iter().take_while(|r| !r.failed()).map(|r| r.time_step).fold(None, |_, dt| Some(dt));
    Boundary {
        column: *key,
        contact_time: first.contact_time,
        damping_rate: first.damping_rate,
        safe_time_step: first.safe_time_step,
        largest_stable,
        smallest_unstable: smallest_unstable.map(|r| r.time_step),
        failure: smallest_unstable.map_or("", |r| r.failure()),
        unwarned_failures: column.iter().filter(|r| r.failed() && !r.warned).count(),
        warned_stable: column.iter().filter(|r| r.settled() && r.warned).count(),
    }
}

/// `dt / t_c` and `dt × rate` of a time step, as table cells.
fn in_units(dt: Option<f64>, b: &Boundary) -> [String; 2] {
    match dt {
        Some(dt) => [short(dt / b.contact_time), short(dt * b.damping_rate)],
        None => ["—".into(), "—".into()],
    }
}

/// Draws `stability_map.png`: one panel per scheme and friction, Δt/t_c against β, every case a dot
/// (stable) or a cross (blew up), all stiffnesses together, and the predicted safe Δt/t_c as a line.
fn chart(options: &StabilityMapOptions, rows: &[MapRow], boundaries: &[Boundary]) -> Result<(), BenchError> {
    let beta_index = |beta: f64| options.betas.iter().position(|b| *b == beta).unwrap_or(0) as f64;
    let mut panels = Vec::new();
    for &scheme in &options.schemes {
        for &friction in &options.frictions {
            let of_panel = |c: &Column| c.scheme == scheme && c.friction == friction;
            let cases = rows
                .iter()
                .filter(|r| of_panel(&r.column))
                .map(|r| (beta_index(r.column.beta), r.dt_over_contact_time, r.failed()))
                .collect();
            let predicted = options
                .betas
                .iter()
                .map(|beta| {
                    let safe = boundaries
                        .iter()
                        .filter(|b| of_panel(&b.column) && b.column.beta == *beta)
                        .map(|b| b.safe_time_step / b.contact_time)
                        .fold(f64::INFINITY, f64::min);
                    (beta_index(*beta), safe)
                })
                .collect();
            panels.push(MapPanel { title: format!("{}, μ = {friction}", scheme_name(scheme)), cases, predicted });
        }
    }
    let labels: Vec<String> = options.betas.iter().map(|b| b.to_string()).collect();
    let size = ChartOptions {
        width: 600 * options.frictions.len().max(1) as u32,
        height: 450 * options.schemes.len().max(1) as u32 + 40,
        subject: Some("dots: stable, crosses: blew up or never came to rest, line: predicted safe step".into()),
        ..Default::default()
    };
    let path = options.out_dir.join("stability_map.png");
    stability_map_chart(&panels, options.frictions.len(), ("β", &labels), "Δt / t_c", &size, &path)
        .map_err(BenchError::from)
}

/// Three significant digits, in exponent form below 0.01.
fn short(x: f64) -> String {
    if x != 0.0 && x.abs() < 0.01 { format!("{x:.2e}") } else { format!("{x:.3}") }
}

/// The Markdown summary: per column, the predicted and observed boundary.
fn summary(options: &StabilityMapOptions, rows: &[MapRow], boundaries: &[Boundary]) -> String {
    let header = [
        "scheme",
        "E (Pa)",
        "β",
        "e",
        "μ",
        "t_c (s)",
        "rate (1/s)",
        "safe dt/t_c",
        "safe dt×rate",
        "stable dt/t_c",
        "stable dt×rate",
        "failed dt/t_c",
        "failed dt×rate",
        "failure",
        "unwarned failures",
        "warned but stable",
    ];
    let table: Vec<Vec<String>> = boundaries
        .iter()
        .map(|b| {
            let safe = in_units(Some(b.safe_time_step), b);
            let stable = in_units(b.largest_stable, b);
            let unstable = in_units(b.smallest_unstable, b);
            let mut cells = vec![
                scheme_name(b.column.scheme).to_string(),
                format!("{:e}", b.column.youngs_modulus),
                b.column.beta.to_string(),
                format!("{:.3}", restitution_from_beta(b.column.beta)),
                b.column.friction.to_string(),
                format!("{:.3e}", b.contact_time),
                format!("{:.3e}", b.damping_rate),
            ];
            cells.extend(safe.into_iter().chain(stable).chain(unstable));
            cells.push(b.failure.to_string());
            cells.push(b.unwarned_failures.to_string());
            cells.push(b.warned_stable.to_string());
            cells
        })
        .collect();
    let count = |o: Outcome| rows.iter().filter(|r| r.outcome() == o).count();
    let (blow_ups, cycles, unsettled) = (count(Outcome::BlowUp), count(Outcome::LimitCycle), count(Outcome::Unsettled));
    let unwarned: usize = boundaries.iter().map(|b| b.unwarned_failures).sum();
    let margin = boundaries
        .iter()
        .filter_map(|b| b.smallest_unstable.map(|dt| dt / b.safe_time_step))
        .filter(|m| *m >= 1.0)
        .fold(f64::INFINITY, f64::min);
    let restarts = options
        .restart_at
        .map_or("no restarts".to_string(), |at| format!("each restarted at {at} s from its own state"));
    format!(
        "# Stability map\n\nRegenerate: `demsweep bench stability --update-results` (writes `stability_map.csv`, \
         `stability_map.md`, `stability_map.png`).\n\n{} cases ({} disks poured into a 0.12 m box, up to {} s each, \
         {restarts}): {blow_ups} blew up and {cycles} never came to rest where a smaller step did or broke the energy \
         balance (limit cycles), {unwarned} of these without a pre-run warning; {unsettled} did not settle at any \
         step of their column. Where a column fails only above the predicted safe step, the smallest failure is \
         {margin:.2} times that step or more.\n\n\
         Columns: the engine's predicted safe time step, the largest time step below which no case failed, and the \
         smallest that failed, each as Δt/t_c and Δt × damping rate (t_c and rate: the engine's prediction for the \
         scene's hardest impact). Every case is in `stability_map.csv`.\n\n{}\n",
        rows.len(),
        options.count,
        options.duration,
        markdown_table(&header, &table)
    )
}
