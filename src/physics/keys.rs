//! The scene's keys — every configuration field's dotted key, default, unit, allowed range and
//! description — from the one declaration of the configuration (its sections declared through
//! [`super::key_spec`]); defaults are the serialized [`SceneConfig::default`]. `demsweep keys`
//! prints them, and [`implausible_values`] finds values that are valid but implausible in their SI
//! unit.

use serde_json::Value;

use super::SceneConfig;
use super::key_spec::KeyDoc;
use super::size_distribution::SizeDistribution;

/// One scene key, ready to print.
#[derive(Clone, Debug, PartialEq)]
pub struct Key {
    /// Dotted key path, e.g. `material.youngs_modulus`.
    pub path: String,
    /// The default value as TOML would write it (`none` when unset).
    pub default: String,
    /// SI unit (empty when dimensionless).
    pub unit: &'static str,
    /// The allowed values in words (empty: any value of its type).
    pub range: String,
    /// What it is.
    pub description: String,
    /// The range a value in the SI unit plausibly lies in.
    pub plausible: Option<(f64, f64)>,
}

/// Every key of a scene, in declaration order.
pub fn scene_keys() -> Vec<Key> {
    let defaults = serde_json::to_value(SceneConfig::default()).unwrap_or(Value::Null);
    let mut keys = Vec::new();
    collect(SceneConfig::KEYS, "", &defaults, &mut keys);
    keys
}

fn collect(section: &[KeyDoc], prefix: &str, defaults: &Value, keys: &mut Vec<Key>) {
    for field in section {
        let path = format!("{prefix}{}", field.name);
        let default = defaults.get(field.name).unwrap_or(&Value::Null);
        if let Some(table) = field.spec.table {
            collect(table, &format!("{path}."), default, keys);
            continue;
        }
        let range = if field.spec.one_of.is_empty() {
            field.spec.range.to_string()
        } else {
            format!("one of {}", field.spec.one_of.join(", "))
        };
        let description = field.doc.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ");
        keys.push(Key {
            path,
            default: value_text(default),
            unit: field.spec.unit,
            range,
            description,
            plausible: field.spec.plausible,
        });
    }
}

/// A value as a study file would write it.
fn value_text(value: &Value) -> String {
    match value {
        Value::Null => "none".into(),
        Value::Number(n) if n.is_f64() => n.as_f64().map_or_else(|| n.to_string(), number_text),
        Value::Number(n) => n.to_string(),
        Value::String(s) => format!("\"{s}\""),
        Value::Array(items) => format!("[{}]", items.iter().map(value_text).collect::<Vec<_>>().join(", ")),
        other => other.to_string(),
    }
}

/// A number in short form: `1e9`, `0.01`, `2500`, `1e-5`.
fn number_text(x: f64) -> String {
    let plain = format!("{x}");
    let scientific = format!("{x:e}");
    if plain.len() > 5 && scientific.len() < plain.len() { scientific } else { plain }
}

/// A value of a key that is valid but implausible in its SI unit: likely written in another unit.
#[derive(Clone, Debug, PartialEq)]
pub struct ImplausibleValue {
    /// Dotted key path.
    pub key: String,
    /// The value as given (in the SI unit).
    pub value: f64,
    /// The SI unit.
    pub unit: &'static str,
    /// The plausible range in the SI unit.
    pub plausible: (f64, f64),
    /// What the value would be in SI had it been written in a likely other unit: (SI value, unit).
    pub suggestions: Vec<(f64, &'static str)>,
}

impl std::fmt::Display for ImplausibleValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (low, high) = self.plausible;
        let unit = self.unit;
        write!(
            f,
            "{} {unit} is implausible for this key (plausible: {} to {} {unit}); units are SI",
            number_text(self.value),
            number_text(low),
            number_text(high)
        )?;
        let meant: Vec<String> = self
            .suggestions
            .iter()
            .map(|(si, other)| format!("{} {unit} ({} {other})", number_text(*si), number_text(self.value)))
            .collect();
        if !meant.is_empty() {
            write!(f, ": did you mean {}?", meant.join(" or "))?;
        }
        Ok(())
    }
}

/// Other units a value of an SI unit is often written in, with their factor to SI.
const OTHER_UNITS: &[(&str, &[(&str, f64)])] = &[
    ("Pa", &[("GPa", 1e9), ("MPa", 1e6), ("kPa", 1e3)]),
    ("kg/m³", &[("g/cm³", 1e3)]),
    ("m", &[("mm", 1e-3), ("cm", 1e-2), ("µm", 1e-6)]),
    ("s", &[("ms", 1e-3), ("µs", 1e-6)]),
    ("N/m", &[("kN/m", 1e3), ("MN/m", 1e6)]),
];

/// `value` in a unit of `factor` to SI, to 13 significant digits: `5 µm` is `5e-6 m`, not the
/// `4.9999999999999996e-6` that the product is in floating point.
fn in_si(value: f64, factor: f64) -> f64 {
    let si = value * factor;
    format!("{si:.12e}").parse().unwrap_or(si)
}

/// The values of `scene` outside their key's plausible SI range, each with the values it would have
/// in SI had it been written in a likely other unit (those that fall inside the range). The lengths of
/// `particles.radii` and `particles.size_distribution` are judged as `particles.radius` is (the
/// first implausible entry of a list).
pub fn implausible_values(scene: &SceneConfig) -> Vec<ImplausibleValue> {
    let Ok(values) = serde_json::to_value(scene) else { return Vec::new() };
    let keys = scene_keys();
    let mut found: Vec<ImplausibleValue> = keys
        .iter()
        .filter_map(|key| {
            let value = key.path.split('.').try_fold(&values, |v, part| v.get(part)).and_then(Value::as_f64)?;
            implausible(key, key.path.clone(), value)
        })
        .collect();
    if let Some(radius) = keys.iter().find(|k| k.path == "particles.radius") {
        for (path, list) in radius_lists(scene) {
            found.extend(list.iter().find_map(|value| implausible(radius, path.to_string(), *value)));
        }
    }
    found
}

/// `value` at `path` when it lies outside the plausible range of `key`, with its likely units.
fn implausible(key: &Key, path: String, value: f64) -> Option<ImplausibleValue> {
    let (low, high) = key.plausible?;
    if !value.is_finite() || (low..=high).contains(&value) {
        return None;
    }
    let others = OTHER_UNITS.iter().find(|(unit, _)| *unit == key.unit).map_or(&[][..], |(_, others)| others);
    let suggestions =
        others.iter().map(|(unit, factor)| (in_si(value, *factor), *unit)).filter(|(si, _)| (low..=high).contains(si));
    Some(ImplausibleValue {
        suggestions: suggestions.collect(),
        key: path,
        value,
        unit: key.unit,
        plausible: (low, high),
    })
}

/// The radii a scene lists, and the lengths of its size distribution, by key.
fn radius_lists(scene: &SceneConfig) -> [(&'static str, Vec<f64>); 6] {
    let p = &scene.particles;
    let d = p.size_distribution.as_ref();
    let length = |get: fn(&SizeDistribution) -> Option<f64>| d.and_then(get).into_iter().collect();
    [
        ("particles.radii", p.radii.clone().unwrap_or_default()),
        ("particles.size_distribution.radii", d.and_then(|d| d.radii.clone()).unwrap_or_default()),
        ("particles.size_distribution.mean", length(|d| d.mean)),
        ("particles.size_distribution.std", length(|d| d.std)),
        ("particles.size_distribution.min", length(|d| d.min)),
        ("particles.size_distribution.max", length(|d| d.max)),
    ]
}

/// The keys as a Markdown table (the docs' key table is this, verbatim).
pub fn markdown_table(keys: &[Key]) -> String {
    let mut table = String::from("| key | default | unit | allowed | description |\n|---|---|---|---|---|\n");
    for k in keys {
        let unit = if k.unit.is_empty() { "-" } else { k.unit };
        let range = if k.range.is_empty() { "-".to_string() } else { k.range.replace('|', "\\|") };
        table.push_str(&format!("| `{}` | `{}` | {unit} | {range} | {} |\n", k.path, k.default, k.description));
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_modulus_in_gpa_and_a_density_in_g_per_cm3_are_caught_with_their_si_values() {
        let mut scene = SceneConfig::default();
        scene.material.youngs_modulus = 10.0;
        scene.material.density = 2.5;
        let found = implausible_values(&scene);
        let keys: Vec<&str> = found.iter().map(|f| f.key.as_str()).collect();
        assert_eq!(keys, ["material.density", "material.youngs_modulus"]);
        assert_eq!(found[0].suggestions, vec![(2500.0, "g/cm³")]);
        assert_eq!(found[1].suggestions[0], (1e10, "GPa"));
        assert!(found[1].to_string().contains("units are SI: did you mean 1e10 Pa (10 GPa)"), "{}", found[1]);
        assert!(implausible_values(&SceneConfig::default()).is_empty(), "the defaults are plausible");
    }

    #[test]
    fn a_radius_in_micrometres_is_suggested_in_its_meaningful_digits() {
        let mut scene = SceneConfig::default();
        scene.particles.radius = 5.0;
        let found = implausible_values(&scene);
        let radius = found.iter().find(|f| f.key == "particles.radius").expect("5 m is an implausible radius");
        assert!(radius.suggestions.contains(&(5e-6, "µm")), "{:?}", radius.suggestions);
        let text = radius.to_string();
        assert!(text.contains("did you mean 0.005 m (5 mm) or 0.05 m (5 cm) or 5e-6 m (5 µm)?"), "{text}");
    }
}
