//! Reading a study: a file or a text checked and expanded into its plan, and the study text of a
//! single scene.

use std::path::Path;

use super::errors::StudyErrors;
use super::{Plan, file, plan};

/// Reads, checks and expands a study file into its plan.
pub fn load(path: &Path) -> Result<Plan, StudyErrors> {
    expand(&file::StudyFile::read(path)?)
}

/// Checks and expands a study given as text, as [`load`] does a file holding it; `path` names it in
/// errors (and relative placement files are found from its folder).
pub fn load_text(path: &Path, text: String) -> Result<Plan, StudyErrors> {
    expand(&file::StudyFile::new(path, text))
}

fn expand(study: &file::StudyFile) -> Result<Plan, StudyErrors> {
    let doc = file::Document::parse(study).map_err(StudyErrors::sorted)?;
    plan::build(study, &doc)
}

/// Which placement seeds a single scene runs with (see [`scene_study`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Seeds {
    /// One run, with the scene's own `placement.seed`.
    Scene,
    /// `n` runs, seeds `placement.seed`, `placement.seed + 1`, … (a study's `replicates = n`).
    Replicates(usize),
    /// One run per seed (a study's `"placement.seed" = [...]`).
    List(Vec<i64>),
}

/// The name of the study [`scene_study`] writes.
pub const SCENE_STUDY_NAME: &str = "scene";

/// The text of a study that runs one scene (`scene`: the keys of a study's `[scene]`) with `seeds`:
/// `check`, `run` and [`load_text`] of it report and run exactly what a study file holding it would.
pub fn scene_study(scene: toml::Table, seeds: &Seeds) -> String {
    let mut study = toml::Table::new();
    study.insert("name".into(), toml::Value::String(SCENE_STUDY_NAME.into()));
    study.insert("scene".into(), toml::Value::Table(scene));
    let sweep = match seeds {
        Seeds::Scene => None,
        Seeds::Replicates(n) => Some(("replicates", toml::Value::Integer(*n as i64))),
        Seeds::List(seeds) => {
            Some(("placement.seed", toml::Value::Array(seeds.iter().map(|&s| toml::Value::Integer(s)).collect())))
        }
    };
    if let Some((key, value)) = sweep {
        study.insert("sweep".into(), toml::Value::Table(toml::Table::from_iter([(key.to_string(), value)])));
    }
    toml::to_string(&study).expect("a table of TOML values serializes")
}

/// The TOML text `text` (named `path` in errors) as a table; its syntax errors located as in a study.
pub fn parse_table(path: &Path, text: String) -> Result<toml::Table, StudyErrors> {
    let doc = file::Document::parse(&file::StudyFile::new(path, text)).map_err(StudyErrors::sorted)?;
    Ok(doc.root)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(text: &str) -> toml::Table {
        parse_table(Path::new("<scene>"), text.to_string()).unwrap()
    }

    #[test]
    fn a_scene_study_runs_its_seeds_and_reports_problems_as_a_study_file_would() {
        let text = scene_study(scene("particles.count = 12\n[placement]\nseed = 7\n"), &Seeds::List(vec![3, 9]));
        let plan = load_text(Path::new("<scene>"), text).unwrap();
        let seeds: Vec<u64> = plan.runs.iter().map(|r| r.scene.placement.seed).collect();
        assert_eq!((plan.name.as_str(), seeds), (SCENE_STUDY_NAME, vec![3, 9]));
        let text = scene_study(scene("[placement]\nseed = 7\n"), &Seeds::Replicates(3));
        let seeds: Vec<u64> =
            load_text(Path::new("s"), text).unwrap().runs.iter().map(|r| r.scene.placement.seed).collect();
        assert_eq!(seeds, [7, 8, 9]);
        assert_eq!(load_text(Path::new("s"), scene_study(scene(""), &Seeds::Scene)).unwrap().runs.len(), 1);

        let text = scene_study(scene("material.frction = 0.5\n"), &Seeds::Scene);
        let errors = load_text(Path::new("<scene>"), text.clone()).unwrap_err();
        assert_eq!(errors.0.len(), 1);
        assert_eq!(errors.0[0].key, "scene.material.frction");
        assert_eq!(errors.0[0].file, Path::new("<scene>"));
        let dir = std::env::temp_dir().join(format!("demsweep-scene-study-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("scene.toml");
        std::fs::write(&file, &text).unwrap();
        let from_file = load(&file).unwrap_err();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(from_file.0[0].reason, errors.0[0].reason);
        assert_eq!(from_file.0[0].location, errors.0[0].location);
    }

    #[test]
    fn toml_syntax_errors_of_a_scene_are_located_in_its_text() {
        let errors = parse_table(Path::new("<scene>"), "a = 1\nb = = 2\n".into()).unwrap_err();
        assert_eq!(errors.0[0].location.map(|l| l.line), Some(2));
        assert!(errors.to_string().starts_with("<scene>:2:"), "{errors}");
    }
}
