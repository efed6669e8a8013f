//! HTML pieces of the report: the page around the sections, escaping, numbers, and the tables.

use serde_json::{Value, json};

use crate::output::table::{Column, ColumnData, SummaryTable, significant};
use crate::physics::RunStatus;
use crate::physics::quantity::{self, Report};
use crate::plot::results::spread;
use crate::stats::points::Points;

use super::table::{Cell, Table};

/// Header group of the swept values.
const POINT_GROUP: &str = "grid point";
/// Header group of the run counts (all, and by status).
const RUNS_GROUP: &str = "runs";
/// Header group of the warning count and the run ids.
const LAST_GROUP: &str = "warnings & run ids";
/// Header groups shown at first (the reader checks the others on): the grid point, the quantities'
/// groups declared shown (settle time and cost, the pile's geometry), and the run ids, so that the
/// table fits a 1280 px page.
fn shown_groups() -> Vec<&'static str> {
    let declared = quantity::per_run().filter_map(|q| match q.role.report {
        Report::Opens { group, shown: true } => Some(group),
        _ => None,
    });
    [POINT_GROUP].into_iter().chain(declared).chain([LAST_GROUP]).collect()
}

/// Grid points the page's table holds at most, spread evenly over the grid (the first and the last
/// kept): this bounds the page's size, memory and time whatever the grid (a 160 000-point table
/// would be half a gigabyte of rows to build and nobody's overview); every point stays in the
/// points CSV and `demsweep summary --by-point`.
pub const MAX_POINT_ROWS: usize = 5000;

/// The columns shown per point, with their units, descriptions and header groups: the declared
/// quantities but those [`Report::Hidden`], each in the group opened last before it (in the order of
/// [`quantity::per_run`]), and the warning count.
fn point_metrics() -> impl Iterator<Item = (&'static str, &'static str, &'static str, &'static str)> {
    let mut group = "";
    let shown = quantity::per_run().filter_map(move |q| {
        if let Report::Opens { group: opened, .. } = q.role.report {
            group = opened;
        }
        (q.role.report != Report::Hidden).then_some((q.name, q.unit, q.description, group))
    });
    shown.chain([("warnings", "", "Validity warnings of the point's runs.", LAST_GROUP)])
}

/// A page being assembled: sections in order, then the closing script.
pub struct Page {
    html: String,
}

impl Page {
    /// A page titled after the study.
    pub fn new(title: &str) -> Self {
        let html = format!(
            "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
             {}<title>{} — demsweep report</title><style>{}</style></head><body><main>",
            crate::output::guard::HTML_MARK,
            escape(title),
            include_str!("report.css")
        );
        Self { html }
    }

    /// Appends a section.
    pub fn push(&mut self, section: &str) {
        self.html += section;
    }

    /// The complete document.
    pub fn finish(self) -> String {
        format!("{}</main><script>{}</script></body></html>", self.html, include_str!("report.js"))
    }
}

/// Text made safe for HTML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out += "&amp;",
            '<' => out += "&lt;",
            '>' => out += "&gt;",
            '"' => out += "&quot;",
            c => out.push(c),
        }
    }
    out
}

/// A number to 4 significant digits (see [`significant`]), `–` when missing.
pub fn number(x: f64) -> String {
    if x.is_nan() { "–".into() } else { significant(x, 4) }
}

/// A float for the page's data: 5 significant digits (the page shows 4), `null` when not finite.
fn short(x: f64) -> Value {
    if x.is_finite() { format!("{x:.4e}").parse::<f64>().map_or(Value::Null, |v| json!(v)) } else { Value::Null }
}

/// The per-point table's columns and rows, for the page's script (see `report.js`).
pub struct PointsTable {
    columns: Vec<Value>,
    /// Each shown point's row as JSON text (a few hundred bytes where its `Value` takes kilobytes).
    rows: Vec<String>,
    /// Grid points in all, shown or not.
    total: usize,
}

impl PointsTable {
    /// The table of `points` (at most [`MAX_POINT_ROWS`] of them, spread over the grid) with their
    /// statistics `stats` (the points table of [`Points::table`], one row per point in order);
    /// `charted`: runs that have a section of their own.
    pub fn new(points: &Points, stats: &SummaryTable, charted: &[&str]) -> Self {
        let summary = points.summary();
        let status = summary.column("status").map(|c| &c.data);
        let ids = summary.column("run_id").map(|c| &c.data);
        let metrics: Vec<_> = point_metrics().filter(|(m, ..)| points.metric_names().contains(m)).collect();
        let column = |name: &str, kind: &str, (unit, description): (&str, &str), group: &str| json!({"name": name, "kind": kind, "unit": unit, "description": description, "group": group});
        let swept = "Swept value of the grid point.";
        let mut columns: Vec<Value> = points
            .coordinates()
            .iter()
            .map(|c| {
                let unit = quantity::unit(&c.name).unwrap_or("");
                column(&c.name, if c.data.is_numeric() { "number" } else { "text" }, (unit, swept), POINT_GROUP)
            })
            .collect();
        columns.push(column("n", "number", ("", "Runs at the grid point (placement seeds)."), RUNS_GROUP));
        columns.extend(
            RunStatus::RECORDED.iter().map(|s| column(s.as_str(), "number", ("", "Runs that ended so."), RUNS_GROUP)),
        );
        columns.extend(
            metrics.iter().map(|&(m, unit, description, group)| column(m, "number", (unit, description), group)),
        );
        columns.push(column(
            "runs",
            "run",
            ("", "The point's run ids; a link to the run's section when it has one."),
            LAST_GROUP,
        ));
        let statistics: Vec<[Option<&Column>; 3]> = (metrics.iter())
            .map(|(m, ..)| ["n", "mean", "ci95"].map(|statistic| stats.column(&format!("{m}_{statistic}"))))
            .collect();
        let rows = spread(points.len(), MAX_POINT_ROWS)
            .into_iter()
            .map(|p| {
                let runs = points.rows(p);
                let text = |row: usize, data: Option<&ColumnData>| data.map(|d| d.text(row)).unwrap_or_default();
                let statuses: Vec<String> = runs.iter().map(|&r| text(r, status)).collect();
                let mut cells: Vec<Value> = points
                    .coordinates()
                    .iter()
                    .map(|c| match points.coordinate(p, &c.name) {
                        Some(x) if c.data.is_numeric() => short(x),
                        _ => json!(points.coordinate_text(p, &c.name)),
                    })
                    .collect();
                cells.push(json!(runs.len()));
                cells.extend(
                    RunStatus::RECORDED.iter().map(|s| json!(statuses.iter().filter(|t| *t == s.as_str()).count())),
                );
                for [n, mean, half_width] in &statistics {
                    let value = |c: &Option<&Column>| c.and_then(|c| c.data.number(p)).unwrap_or(f64::NAN);
                    let described = value(n) > 0.0;
                    cells.push(if described {
                        json!([short(value(mean)), short(value(half_width))])
                    } else {
                        Value::Null
                    });
                }
                let run_ids: Vec<String> = runs.iter().map(|&r| text(r, ids)).collect();
                let linked = run_ids.iter().find(|id| charted.contains(&id.as_str()));
                cells.push(json!([linked, run_ids.join(" ")]));
                let mut present: Vec<&String> = statuses.iter().collect();
                present.sort();
                present.dedup();
                json!({"statuses": present, "cells": cells}).to_string()
            })
            .collect();
        Self { columns, rows, total: points.len() }
    }

    /// `(shown, total)`: grid points in the table and in the results.
    pub fn shown(&self) -> (usize, usize) {
        (self.rows.len(), self.total)
    }

    /// The table's column groups (one `<colgroup>` per header group, so that a rule can part them)
    /// and its header: a row of header groups over a row of columns, each column with its kind,
    /// unit and description.
    pub fn header(&self) -> String {
        let text = |c: &Value, key: &str| c[key].as_str().unwrap_or("").to_string();
        let mut spans: Vec<(String, usize)> = Vec::new();
        for c in &self.columns {
            match spans.last_mut() {
                Some((group, span)) if *group == text(c, "group") => *span += 1,
                _ => spans.push((text(c, "group"), 1)),
            }
        }
        let colgroups: String =
            spans.iter().map(|(_, span)| format!("<colgroup span=\"{span}\"></colgroup>")).collect();
        let groups: String =
            spans.iter().map(|(group, span)| format!("<th colspan=\"{span}\">{}</th>", escape(group))).collect();
        let columns: String = self
            .columns
            .iter()
            .map(|c| {
                let name = escape(&text(c, "name"));
                let label = escape(&quantity::labelled(&text(c, "name"), &text(c, "unit")));
                format!(
                    "<th data-kind=\"{}\" title=\"{} Click to sort by {name}.\">{}</th>",
                    escape(&text(c, "kind")),
                    escape(&text(c, "description")),
                    label.replace('_', "_<wbr>").replace('.', ".<wbr>"),
                )
            })
            .collect();
        format!("{colgroups}<thead><tr class=\"groups\">{groups}</tr><tr class=\"columns\">{columns}</tr></thead>")
    }

    /// The data the page's script renders, as JSON safe inside a `<script>` element.
    pub fn json(&self) -> String {
        let columns = serde_json::to_string(&self.columns).expect("JSON values serialise");
        let shown_groups = json!(shown_groups());
        format!("{{\"columns\":{columns},\"rows\":[{}],\"shown_groups\":{shown_groups}}}", self.rows.join(","))
            .replace("</", "<\\/")
    }
}

/// A table as a plain HTML table; real numbers to 4 significant digits.
pub fn static_table(table: &Table) -> String {
    if table.columns.is_empty() {
        return String::new();
    }
    let head: String = table.columns.iter().map(|name| format!("<th>{}</th>", escape(name))).collect();
    let cell = |cell: &Cell| match cell {
        Cell::Number(x) => format!("<td class=\"num\">{}</td>", number(*x)),
        Cell::Whole(n) => format!("<td class=\"num\">{n}</td>"),
        other => format!("<td>{}</td>", escape(&other.to_string())),
    };
    let body: String =
        table.rows.iter().map(|row| format!("<tr>{}</tr>", row.iter().map(cell).collect::<String>())).collect();
    format!("<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::SummaryRow;
    use crate::study::ParamValue;

    #[test]
    fn a_grid_larger_than_the_table_shows_its_points_spread_with_the_first_and_the_last() {
        let total = MAX_POINT_ROWS + 1234;
        let rows: Vec<SummaryRow> = (0..total)
            .map(|i| {
                let friction = vec![("material.friction".to_string(), ParamValue::Float(i as f64))];
                SummaryRow::failed(i, &format!("r{i:05}"), &friction, "")
            })
            .collect();
        let summary = SummaryTable::from_rows(&rows);
        let points = Points::new(&summary);
        assert_eq!(points.len(), total, "one point per run");
        let table = PointsTable::new(&points, &points.table(), &[]);
        assert_eq!(table.shown(), (MAX_POINT_ROWS, total));
        let first_cells: Vec<f64> = table
            .rows
            .iter()
            .map(|r| serde_json::from_str::<Value>(r).unwrap()["cells"][0].as_f64().unwrap())
            .collect();
        assert_eq!(first_cells.first(), Some(&0.0));
        assert_eq!(first_cells.last(), Some(&((total - 1) as f64)));
        assert!(first_cells.windows(2).all(|w| w[1] > w[0] && w[1] - w[0] <= 2.0), "evenly spread, in grid order");
        let small = SummaryTable::from_rows(&rows[..10]);
        let points = Points::new(&small);
        assert_eq!(PointsTable::new(&points, &points.table(), &[]).shown(), (10, 10), "a small grid whole");
    }

    #[test]
    fn header_groups_start_at_declared_quantities_and_hold_neighbouring_columns() {
        let opened = quantity::per_run().filter(|q| matches!(q.role.report, Report::Opens { .. })).count();
        let mut groups: Vec<&str> = point_metrics().map(|(.., group)| group).collect();
        assert!(!groups.contains(&""), "every shown quantity has a group");
        groups.dedup();
        let mut distinct = groups.clone();
        distinct.sort();
        distinct.dedup();
        assert_eq!(groups.len(), distinct.len(), "each group's columns side by side: {groups:?}");
        assert_eq!(groups.len(), opened + 1, "{groups:?}");
    }
}
