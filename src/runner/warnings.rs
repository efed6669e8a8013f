//! The warnings of a sweep's runs, grouped by kind (the same text but for its numbers) for the person
//! running it.

use std::collections::HashMap;

use crate::study::warning_kind;

/// One kind of warning: the first run's text and how many runs have one.
#[derive(Clone, Debug, PartialEq)]
pub struct WarningGroup {
    /// The warning as the first run that had it gave it.
    pub example: String,
    /// That run's id.
    pub first_run: String,
    /// How many runs have a warning of this kind.
    pub runs: usize,
}

/// Warnings of finished runs by kind, in the order they were first seen.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WarningDigest {
    /// The kinds.
    pub groups: Vec<WarningGroup>,
    /// Runs with at least one warning.
    pub runs: usize,
    index: HashMap<String, usize>,
}

impl WarningDigest {
    /// Adds the warnings of run `id` (a kind it has twice counts once).
    pub fn add(&mut self, id: &str, warnings: &[String]) {
        let mut seen = Vec::new();
        for text in warnings {
            let kind = warning_kind(text);
            if seen.contains(&kind) {
                continue;
            }
            match self.index.get(&kind) {
                Some(&k) => self.groups[k].runs += 1,
                None => {
                    self.index.insert(kind.clone(), self.groups.len());
                    self.groups.push(WarningGroup { example: text.clone(), first_run: id.to_string(), runs: 1 });
                }
            }
            seen.push(kind);
        }
        self.runs += usize::from(!warnings.is_empty());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_by_kind_and_counts_runs() {
        let mut digest = WarningDigest::default();
        digest.add("r0", &["overlap 0.81 radii".into(), "energy off 17 %".into(), "overlap 0.9 radii".into()]);
        digest.add("r1", &[]);
        digest.add("r2", &["overlap 0.93 radii".into()]);
        assert_eq!(digest.runs, 2);
        let shown: Vec<(&str, &str, usize)> =
            digest.groups.iter().map(|g| (g.example.as_str(), g.first_run.as_str(), g.runs)).collect();
        assert_eq!(shown, [("overlap 0.81 radii", "r0", 2), ("energy off 17 %", "r0", 1)]);
    }
}
