//! The tables of per-run quantities and history series in docs/results.md (the result-files chapter
//! of the guide) are the declarations of
//! `physics::quantity`, row for row (name, unit, description), so the two cannot drift apart.

use demsweep::physics::quantity::{self, Declaration, HISTORY_SERIES};

/// The rows of the docs/results.md table whose header line is `header`, as `(name, unit, description)`.
fn readme_table(header: &str) -> Vec<(String, String, String)> {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/results.md")).unwrap();
    let lines = readme.lines().skip_while(|l| l.trim() != header).skip(2);
    lines
        .take_while(|l| l.starts_with('|'))
        .map(|line| {
            let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
            assert_eq!(cells.len(), 3, "a row of three cells: {line}");
            (cells[0].trim_matches('`').to_string(), cells[1].to_string(), cells[2].to_string())
        })
        .collect()
}

/// The rows the chapter must have for these declarations (a dimensionless unit written `-`).
fn rows(declared: impl Iterator<Item = Declaration>) -> Vec<(String, String, String)> {
    declared
        .map(|q| {
            let unit = if q.unit.is_empty() { "-" } else { q.unit };
            (q.name.to_string(), unit.to_string(), q.description.to_string())
        })
        .collect()
}

fn markdown(rows: &[(String, String, String)]) -> String {
    rows.iter().map(|(n, u, d)| format!("| `{n}` | {u} | {d} |\n")).collect()
}

#[test]
fn readme_lists_every_per_run_quantity_with_its_unit() {
    let expected = rows(quantity::per_run());
    let found = readme_table("| quantity | unit | description |");
    assert_eq!(found, expected, "docs/results.md's per-run quantities should read:\n{}", markdown(&expected));
}

#[test]
fn readme_lists_every_history_series_with_its_unit() {
    let expected = rows(HISTORY_SERIES.iter().map(|s| s.quantity.declaration()));
    let found = readme_table("| series | unit | description |");
    assert_eq!(found, expected, "docs/results.md's history series should read:\n{}", markdown(&expected));
}
