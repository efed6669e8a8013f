//! The warnings of a sweep's runs, grouped by kind for the person running it.

use std::collections::HashMap;

use crate::physics::warning::{ValidityWarning, WarningKind};

/// One kind of warning: the first run's warning and how many runs have one.
#[derive(Clone, Debug, PartialEq)]
pub struct WarningGroup {
    /// The warning as the first run that had it gave it.
    pub example: ValidityWarning,
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
    index: HashMap<WarningKind, usize>,
}

impl WarningDigest {
    /// Adds the warnings of run `id` (a kind it has twice counts once).
    pub fn add(&mut self, id: &str, warnings: &[ValidityWarning]) {
        let mut seen = Vec::new();
        for warning in warnings {
            if seen.contains(&warning.kind) {
                continue;
            }
            match self.index.get(&warning.kind) {
                Some(&k) => self.groups[k].runs += 1,
                None => {
                    self.index.insert(warning.kind, self.groups.len());
                    let group = WarningGroup { example: warning.clone(), first_run: id.to_string(), runs: 1 };
                    self.groups.push(group);
                }
            }
            seen.push(warning.kind);
        }
        self.runs += usize::from(!warnings.is_empty());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_by_kind_and_counts_runs() {
        let overlap = |value| ValidityWarning::new(WarningKind::Overlap, value, 0.1);
        let energy = ValidityWarning::new(WarningKind::EnergyBalance, 0.17, 0.01);
        let mut digest = WarningDigest::default();
        digest.add("r0", &[overlap(0.81), energy, overlap(0.9)]);
        digest.add("r1", &[]);
        digest.add("r2", &[overlap(0.93)]);
        assert_eq!(digest.runs, 2);
        let shown: Vec<(WarningKind, f64, &str, usize)> =
            digest.groups.iter().map(|g| (g.example.kind, g.example.value, g.first_run.as_str(), g.runs)).collect();
        assert_eq!(shown, [(WarningKind::Overlap, 0.81, "r0", 2), (WarningKind::EnergyBalance, 0.17, "r0", 1)]);
    }
}
