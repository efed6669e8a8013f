//! What a caller does with a scene whichever its contact law: run it, resolve its time step,
//! predict its stability. Each goes through the law table's one dispatch
//! ([`ContactConfig::dispatch`](super::contact::ContactConfig::dispatch)).

use std::fmt;
use std::sync::atomic::AtomicBool;

use super::config::{ConfigIssue, SceneConfig};
use super::contact::{LawVisitor, RegisteredLaw};
use super::material::Materials;
use super::parallel::Threads;
use super::particles::{InitialContact, InitialDisk, Particles};
use super::placement::PlacementError;
use super::record::RunRecord;
use super::run_state::{Checkpoints, NoCheckpoints, RunState, StateError};
use super::simulation::{Control, Progress, Simulation};
use super::stability::{self, StabilityReport};
use super::time_step::{self, ResolvedTimeStep, with_time_step};
use super::walls::BoxWalls;
use super::warning::ValidityWarning;

/// Why a scene could not be run; its text is made where a person reads it.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// The scene breaks its own rules (every issue found).
    InvalidScene(Vec<ConfigIssue>),
    /// Its random or lattice placement could not place the disks.
    Placement(PlacementError),
    /// There is no disk to run.
    NoDisks,
    /// The scene names a contact history (`placement.contacts`, this file) that the caller did not give.
    HistoryNotGiven {
        /// The file the scene names.
        file: String,
    },
    /// A contact history was given for a scene that names none.
    HistoryNotNamed,
    /// A saved run state does not read back into this scene's simulation.
    Checkpoint(StateError),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::InvalidScene(issues) => {
                let texts: Vec<String> = issues.iter().map(ToString::to_string).collect();
                write!(f, "{}", texts.join("; "))
            }
            RunError::Placement(e) => write!(f, "{e}"),
            RunError::NoDisks => write!(f, "particles.count: a scene needs at least one disk, got 0"),
            RunError::HistoryNotGiven { file } => {
                write!(f, "placement.contacts: the contact history {file} was not read")
            }
            RunError::HistoryNotNamed => {
                write!(f, "placement.contacts: a contact history given to a scene that names none")
            }
            RunError::Checkpoint(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RunError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RunError::Placement(e) => Some(e),
            _ => None,
        }
    }
}

/// Builds and runs one scene with the contact law it names. `disks`: explicit initial states
/// (file placement), or `None` to generate them from the scene's placement.
pub fn run_scene(
    scene: &SceneConfig,
    disks: Option<Vec<InitialDisk>>,
    observer: &mut dyn FnMut(&Progress) -> Control,
) -> Result<RunRecord, RunError> {
    run_scene_with_history(scene, disks, None, observer)
}

/// [`run_scene`] with the contacts starting from the history `contacts` (a restart from a pile, see
/// [`Simulation::with_history`]): the history the scene's `placement.contacts` names, read by the
/// caller (an error if the scene names one and none is given, or the other way round).
pub fn run_scene_with_history(
    scene: &SceneConfig,
    disks: Option<Vec<InitialDisk>>,
    contacts: Option<&[InitialContact]>,
    observer: &mut dyn FnMut(&Progress) -> Control,
) -> Result<RunRecord, RunError> {
    run_scene_on(scene, disks, contacts, Threads::default(), &AtomicBool::new(false), observer)
}

/// [`run_scene_with_history`] on `threads` (of the current rayon pool; the results are the same
/// bits on any number: see [`super::parallel`]), interrupted within a step of `stop` being set (see
/// [`Simulation::run_until`]).
pub fn run_scene_on(
    scene: &SceneConfig,
    disks: Option<Vec<InitialDisk>>,
    contacts: Option<&[InitialContact]>,
    threads: Threads,
    stop: &AtomicBool,
    observer: &mut dyn FnMut(&Progress) -> Control,
) -> Result<RunRecord, RunError> {
    run_scene_resumable(scene, (disks, contacts), threads, stop, observer, (None, &mut NoCheckpoints))
}

/// [`run_scene_on`] (`start`: its disks and contacts) from the saved state `from` if given (see
/// [`Simulation::resume`]), handing `checkpoints` its state as it asks (see
/// [`Simulation::run_resumable`]). A state that does not read back is [`RunError::Checkpoint`].
pub fn run_scene_resumable(
    scene: &SceneConfig,
    start: (Option<Vec<InitialDisk>>, Option<&[InitialContact]>),
    threads: Threads,
    stop: &AtomicBool,
    observer: &mut dyn FnMut(&Progress) -> Control,
    (from, checkpoints): (Option<&RunState>, &mut dyn Checkpoints),
) -> Result<RunRecord, RunError> {
    let (disks, contacts) = start;
    if let Err(issues) = scene.validate() {
        return Err(RunError::InvalidScene(issues));
    }
    let disks = match disks {
        Some(d) => d,
        None => super::placement::generate(scene).map_err(RunError::Placement)?,
    };
    if disks.is_empty() {
        return Err(RunError::NoDisks);
    }
    match (&scene.placement.contacts, contacts) {
        (Some(file), None) => return Err(RunError::HistoryNotGiven { file: file.clone() }),
        (None, Some(_)) => return Err(RunError::HistoryNotNamed),
        _ => {}
    }
    struct Run<'a> {
        scene: &'a SceneConfig,
        disks: &'a [InitialDisk],
        contacts: &'a [InitialContact],
        threads: Threads,
        stop: &'a AtomicBool,
        observer: &'a mut dyn FnMut(&Progress) -> Control,
        from: Option<&'a RunState>,
        checkpoints: &'a mut dyn Checkpoints,
    }
    impl LawVisitor for Run<'_> {
        type Output = Result<RunRecord, RunError>;
        fn visit<L: RegisteredLaw>(self, law: &L) -> Self::Output {
            let mut simulation = Simulation::with_history(self.scene, self.disks, self.contacts, law.clone());
            simulation.set_threads(self.threads);
            let resumed = self.from.map(|state| simulation.resume(state)).transpose().map_err(RunError::Checkpoint)?;
            Ok(simulation.run_resumable(resumed, self.stop, self.observer, self.checkpoints))
        }
    }
    let contacts = contacts.unwrap_or_default();
    scene.contact.dispatch(Run { scene, disks: &disks, contacts, threads, stop, observer, from, checkpoints })
}

/// The time step a (validated) scene will run with; `disks`: the initial disks of a file placement.
pub fn scene_time_step(scene: &SceneConfig, disks: Option<&[InitialDisk]>) -> ResolvedTimeStep {
    struct Resolve<'a>(&'a SceneConfig, Option<&'a [InitialDisk]>);
    impl LawVisitor for Resolve<'_> {
        type Output = ResolvedTimeStep;
        fn visit<L: RegisteredLaw>(self, law: &L) -> ResolvedTimeStep {
            time_step::resolve(law, self.0, self.1)
        }
    }
    scene.contact.dispatch(Resolve(scene, disks))
}

/// The pre-run stability estimate of a scene starting from `disks` with its own contact law,
/// without building a simulation (a time step capped by the damping-rate limit is its first warning).
pub fn predict_stability(scene: &SceneConfig, disks: &[InitialDisk]) -> StabilityReport {
    let resolved = scene_time_step(scene, Some(disks));
    let scene = &with_time_step(scene, resolved.dt);
    let materials = Materials::from_scene(scene);
    let particles = Particles::new(disks, materials.density, scene.particles.thickness);
    let walls = BoxWalls::new(&scene.domain);
    struct Assess<'a>(&'a SceneConfig, &'a Particles, &'a Materials, &'a BoxWalls);
    impl LawVisitor for Assess<'_> {
        type Output = StabilityReport;
        fn visit<L: RegisteredLaw>(self, law: &L) -> StabilityReport {
            stability::assess(law, self.0, self.1, self.2, self.3)
        }
    }
    let mut report = scene.contact.dispatch(Assess(scene, &particles, &materials, &walls));
    report.warnings.splice(0..0, resolved.warning);
    report
}

/// The validity warnings predicted for the stages of `scene` from `disks` beyond `own` (the scene's
/// own prediction): each stage as the scene with its keys ([`SceneConfig::in_stage`]), so that a
/// stage's time step and damping meet the rules a scene's meet; a stage that changes nothing they
/// look at adds none. Each with the index of its stage, in stage order.
pub fn predict_stage_warnings(
    scene: &SceneConfig,
    disks: &[InitialDisk],
    own: &[ValidityWarning],
) -> Vec<(usize, ValidityWarning)> {
    let stage_warnings = |(k, stage)| {
        let predicted = predict_stability(&scene.in_stage(stage), disks).warnings;
        predicted.into_iter().filter(|w| !own.contains(w)).map(move |w| (k, w))
    };
    scene.stages.iter().enumerate().flat_map(stage_warnings).collect()
}
