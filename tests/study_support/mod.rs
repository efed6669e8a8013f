//! Helpers for the study tests: studies written as strings into a private temporary folder.
#![allow(dead_code)] // each test file uses a different subset

use std::path::{Path, PathBuf};

use demsweep::physics::SceneConfig;
use demsweep::study::{self, OutputOptions, Plan, PlannedRun, StudyError};

/// A temporary folder for study files, removed when dropped.
pub struct StudyDir {
    /// The folder.
    pub path: PathBuf,
}

impl StudyDir {
    /// A fresh, empty folder unique to this call (`name`, process and a count: two tests that pick
    /// the same name must not share a folder, as they run at the same time).
    pub fn new(name: &str) -> Self {
        static MADE: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let count = MADE.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!("demsweep-study-{name}-{}-{count}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap();
        Self { path }
    }

    /// Writes `text` to `file` in the folder and returns its path.
    pub fn write(&self, file: &str, text: &str) -> PathBuf {
        let path = self.path.join(file);
        std::fs::write(&path, text).unwrap();
        path
    }
}

impl Drop for StudyDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}

/// A small, fast base scene (20 disks, 10 ms) to put sweeps on.
pub const SMALL_SCENE: &str = "[scene]\nparticles.count = 20\nrun.duration = 0.01\nintegrator.time_step = 1e-5\n";

/// Loads `text` as the study `name`.toml; panics with the errors if it is invalid.
pub fn plan(name: &str, text: &str) -> Plan {
    let dir = StudyDir::new(name);
    study::load(&dir.write(&format!("{name}.toml"), text)).unwrap_or_else(|e| panic!("{e}"))
}

/// The errors of the invalid study `text`; panics if it loads.
pub fn errors(name: &str, text: &str) -> Vec<StudyError> {
    let dir = StudyDir::new(name);
    errors_at(&dir.write(&format!("{name}.toml"), text))
}

/// The errors of the invalid study at `path`.
pub fn errors_at(path: &Path) -> Vec<StudyError> {
    match study::load(path) {
        Ok(plan) => panic!("expected errors, got a plan of {} runs", plan.runs.len()),
        Err(errors) => errors.0,
    }
}

/// The only error of an invalid study, checked to be at `line` with `key`.
pub fn single_error(name: &str, text: &str, line: usize, key: &str) -> StudyError {
    let errors = errors(name, text);
    assert_eq!(errors.len(), 1, "{errors:#?}");
    let error = errors.into_iter().next().unwrap();
    assert_eq!(error.location.map(|l| l.line), Some(line), "{error}");
    assert_eq!(error.key, key, "{error}");
    error
}

/// A plan of `name`.toml built in code, one run per scene (no study file behind it).
pub fn plan_in_code(name: &str, scenes: Vec<SceneConfig>) -> Plan {
    let runs = scenes
        .into_iter()
        .enumerate()
        .map(|(index, scene)| PlannedRun::new(format!("r{index:06}"), index, Vec::new(), scene, None))
        .collect();
    let (study_path, name) = (PathBuf::from(format!("{name}.toml")), name.to_string());
    Plan {
        study_path,
        study_text: String::new(),
        name,
        fingerprint: String::new(),
        output: OutputOptions::default(),
        runs,
        warnings: Vec::new(),
    }
}
