//! `demsweep keys` is the configuration's own declaration: every key a scene serializes is listed
//! (and nothing else), each stated range is the one `validate` enforces, each listed word of a text
//! key is accepted, the docs' key table is the command's output, and `check` warns of a value
//! implausible in its SI unit with what it would be in the likely unit.

use std::process::Command;

use demsweep::physics::SceneConfig;
use demsweep::physics::keys::{Key, markdown_table, scene_keys};
use serde_json::Value;

/// The default scene with one stage (named `s`, ending after 1 s), as JSON: the keys of a stage are
/// listed as `stages.KEY`, those of its first.
fn scene() -> Value {
    let mut scene = serde_json::to_value(SceneConfig::default()).unwrap();
    let stage: demsweep::physics::config::StageConfig = toml::from_str("name = \"s\"\nuntil.time = 1.0").unwrap();
    scene["stages"] = serde_json::json!([stage]);
    scene
}

/// The dotted paths of the leaves of a serialized scene (an empty table has none; an array of
/// tables has its first table's).
fn leaves(value: &Value, prefix: &str, out: &mut Vec<String>) {
    match value {
        Value::Object(fields) => {
            for (name, field) in fields {
                leaves(field, &format!("{prefix}{name}."), out);
            }
        }
        Value::Array(items) if items.first().is_some_and(Value::is_object) => leaves(&items[0], prefix, out),
        _ => out.push(prefix.trim_end_matches('.').to_string()),
    }
}

/// The key `validate` names for listed key `path` (a stage's keys under its name).
fn validated_key(path: &str) -> String {
    path.strip_prefix("stages.").map_or(path.to_string(), |rest| format!("stages.s.{rest}"))
}

/// The value at key `part` of `v` (the first table of an array of tables).
fn step<'a>(v: &'a mut Value, part: &str) -> &'a mut Value {
    let inner = v.get_mut(part).unwrap();
    if inner.is_array() { &mut inner[0] } else { inner }
}

/// The scene of [`scene`] with `path` set to `value`, if it deserializes.
fn with(path: &str, value: Value) -> Option<SceneConfig> {
    let mut scene = scene();
    let (parents, last) = path.rsplit_once('.').map_or(("", path), |(p, l)| (p, l));
    let table = parents.split('.').filter(|p| !p.is_empty()).fold(&mut scene, step);
    table[last] = value;
    // A law's parameters (`contact.<law>.<name>`) are those of the chosen law.
    if let ["contact", law, _] = path.split('.').collect::<Vec<_>>()[..] {
        scene["contact"]["law"] = Value::String(law.to_string());
    }
    serde_json::from_value(scene).ok()
}

/// Whether the default scene with `path` set to `value` is refused, by its type or by `validate`
/// naming the key.
fn refused(path: &str, value: f64) -> bool {
    let Some(scene) = with(path, serde_json::json!(value)) else { return true };
    scene.validate().is_err_and(|issues| issues.iter().any(|i| i.key == validated_key(path)))
}

/// Values just outside the bounds a range states (`> 0`, `>= 1`, `(-1, 0.5]`, `[0, 1)`).
fn outside(range: &str) -> Vec<f64> {
    let below = |x: f64| x - 1e-9 * x.abs().max(1.0);
    let above = |x: f64| x + 1e-9 * x.abs().max(1.0);
    if let Some(x) = range.strip_prefix(">= ").and_then(|x| x.parse().ok()) {
        return vec![below(x)];
    }
    if let Some(x) = range.strip_prefix("> ").and_then(|x| x.parse::<f64>().ok()) {
        return vec![x];
    }
    let Some((low, high)) = range.get(1..range.len().saturating_sub(1)).and_then(|r| r.split_once(", ")) else {
        return Vec::new();
    };
    let (Ok(low), Ok(high)) = (low.parse::<f64>(), high.parse::<f64>()) else { return Vec::new() };
    let low = if range.starts_with('[') { below(low) } else { low };
    let high = if range.ends_with(']') { above(high) } else { high };
    vec![low, high]
}

#[test]
fn every_serialized_key_is_listed_and_nothing_else() {
    let mut serialized = Vec::new();
    leaves(&scene(), "", &mut serialized);
    let mut listed: Vec<String> = scene_keys().into_iter().map(|k| k.path).collect();
    serialized.sort();
    listed.sort();
    assert_eq!(listed, serialized);
    for key in scene_keys() {
        assert!(!key.description.is_empty(), "{}: no description (its doc comment)", key.path);
    }
}

#[test]
fn every_stated_numeric_range_is_the_one_validate_enforces() {
    let mut checked = 0;
    for Key { path, range, .. } in scene_keys() {
        for value in outside(&range) {
            assert!(refused(&path, value), "{path} = {value} is outside `{range}` but accepted");
            checked += 1;
        }
    }
    assert!(checked > 30, "only {checked} bounds checked: the range parser is broken");
}

#[test]
fn every_listed_word_of_a_text_key_is_accepted_and_no_other() {
    let mut checked = 0;
    for key in scene_keys() {
        let Some(words) = key.range.strip_prefix("one of ") else { continue };
        for word in words.split(", ") {
            let scene = with(&key.path, Value::String(word.into()));
            assert!(scene.is_some(), "{} = \"{word}\" is listed but not read", key.path);
            checked += 1;
        }
        assert!(with(&key.path, Value::String("no_such_word".into())).is_none(), "{}", key.path);
    }
    assert!(checked >= 10, "{checked}");
}

#[test]
fn the_docs_key_table_is_the_commands_output() {
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep")).args(["keys", "--markdown"]).output().unwrap();
    assert!(out.status.success());
    let printed = String::from_utf8(out.stdout).unwrap();
    assert_eq!(printed, markdown_table(&scene_keys()));
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/studies.md")).unwrap();
    let table = docs.split("<!-- keys:begin -->\n").nth(1).and_then(|rest| rest.split("<!-- keys:end -->").next());
    assert_eq!(table, Some(printed.as_str()), "docs/studies.md's key table should be `demsweep keys --markdown`");
}

#[test]
fn check_warns_of_a_modulus_in_gpa_and_a_density_in_g_per_cm3() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("keys_units");
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("units.toml");
    std::fs::write(&study, "[scene]\nmaterial.youngs_modulus = 10\nmaterial.density = 2.5\nparticles.radius = 0.004\n")
        .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_demsweep")).arg("check").arg(&study).output().unwrap();
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "warnings do not fail the check:\n{said}");
    let modulus = said.lines().find(|l| l.contains("scene.material.youngs_modulus")).expect(&said);
    assert!(modulus.contains("units are SI") && modulus.contains("did you mean 1e10 Pa (10 GPa)"), "{modulus}");
    let density = said.lines().find(|l| l.contains("scene.material.density")).expect(&said);
    assert!(density.contains("did you mean 2500 kg/m³ (2.5 g/cm³)"), "{density}");
    assert!(!said.contains("particles.radius"), "a plausible radius is not warned about:\n{said}");
}
