//! The page's sections between the answer and the runs: what was run, how the runs ended, the
//! per-point table, the study and pile-metric charts, and a charted run's section.

use std::collections::BTreeMap;
use std::path::Path;

use super::html::{self, escape, number};
use super::{ReportContext, Svgs};
use crate::output::{FileHeader, SummaryRow, Tables};
use crate::physics::RunStatus;
use crate::physics::warning::{ValidityWarning, WarningKind};
use crate::plot::results;
use crate::stats::points::Points;

/// What was run: study, fingerprint, version, dates, wall time, cores, and the study file itself.
pub(super) fn overview(header: &FileHeader, rows: &[SummaryRow], context: &ReportContext, tune: bool) -> String {
    let description = toml::from_str::<toml::Table>(&header.study_text)
        .ok()
        .and_then(|t| t.get("description").and_then(|d| d.as_str().map(str::to_string)));
    let run_seconds: f64 = rows.iter().map(|r| r.wall_time).sum();
    let measured: Vec<f64> = rows.iter().map(|r| r.cpu_time).filter(|t| t.is_finite()).collect();
    let cpu = match measured.len() {
        0 => "no CPU time measured".to_string(),
        n if n == rows.len() => format!("{} s CPU time", number(measured.iter().sum())),
        n => format!("{} s CPU time over the {n} runs that measured it", number(measured.iter().sum())),
    };
    let mut facts = vec![
        ("study", escape(&header.study_name)),
        ("fingerprint", format!("<code>{}</code>", escape(&header.fingerprint))),
        ("demsweep", escape(&header.demsweep_version)),
        ("results file created", escape(&header.created)),
        ("report written", escape(&crate::output::header::utc_now())),
        (
            "runs",
            match tune {
                true => format!("{} (a tune decides its runs as it goes: see below how they add up)", rows.len()),
                false => format!("{} of {} planned", rows.len(), header.planned_runs),
            },
        ),
        ("computing time", format!("{} s wall time summed over all runs; {cpu}", number(run_seconds))),
    ];
    if let Some(elapsed) = context.elapsed {
        facts.push(("wall time", format!("{} s (the last sweep into the file)", number(elapsed))));
    }
    if let Some(jobs) = context.jobs {
        facts.push(("cores", format!("{jobs} worker threads")));
    }
    let facts: String = facts.iter().map(|(k, v)| format!("<dt>{k}</dt><dd>{v}</dd>")).collect();
    format!(
        "<h1>{}</h1><p class=\"lead\">{}</p><dl class=\"facts\">{facts}</dl><details><summary>study file</summary><pre>{}</pre></details>",
        escape(&header.study_name),
        escape(description.as_deref().unwrap_or("")),
        escape(&header.study_text)
    )
}

/// How the runs ended (counts by status), their failure messages grouped, and their warnings by
/// kind: how many runs have one and the worst (largest over its limit); in a tune's report the
/// kind's name and key with the worst value, else the worst warning in full (what it means, its cure).
pub(super) fn outcomes(rows: &[SummaryRow], tune: bool) -> String {
    let mut statuses: BTreeMap<&str, usize> = BTreeMap::new();
    let mut worst: BTreeMap<WarningKind, (&ValidityWarning, &str)> = BTreeMap::new();
    let mut runs: BTreeMap<WarningKind, usize> = BTreeMap::new();
    let mut messages: BTreeMap<(&str, &str), usize> = BTreeMap::new();
    for row in rows {
        *statuses.entry(row.status.as_str()).or_default() += 1;
        for warning in &row.warnings {
            let entry = worst.entry(warning.kind).or_insert((warning, &row.id));
            if warning.excess() > entry.0.excess() {
                *entry = (warning, &row.id);
            }
        }
        let mut kinds: Vec<WarningKind> = row.warnings.iter().map(|w| w.kind).collect();
        kinds.sort_unstable();
        kinds.dedup();
        kinds.into_iter().for_each(|k| *runs.entry(k).or_default() += 1);
        if !row.message.is_empty() {
            *messages.entry((row.status.as_str(), &row.message)).or_default() += 1;
        }
    }
    let badges: String =
        statuses.iter().map(|(s, n)| format!("<span class=\"{}\">{n} {}</span>", escape(s), escape(s))).collect();
    let mut out = format!("<h2 id=\"outcomes\">How the runs ended</h2><p class=\"badges\">{badges}</p>");
    let grouped = |title: &str, entries: Vec<(String, usize)>| {
        let mut sorted = entries;
        sorted.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let rows: String =
            sorted.iter().map(|(m, n)| format!("<tr><td class=\"num\">{n}</td><td>{}</td></tr>", escape(m))).collect();
        format!(
            "<h3>{title}</h3><table><thead><tr><th>runs</th><th>message</th></tr></thead><tbody>{rows}</tbody></table>"
        )
    };
    if !messages.is_empty() {
        let entries = messages.into_iter().map(|((s, m), n)| (format!("{s}: {m}"), n)).collect();
        out += &grouped("Why runs failed or diverged", entries);
    }
    if worst.is_empty() {
        out += "<p class=\"note\">No run has a warning.</p>";
        return out;
    }
    let entries = worst
        .into_iter()
        .map(|(kind, (warning, id))| {
            let text = if tune {
                let (value, limit) = (warning.value, warning.limit);
                format!("{} ({}): worst {value:.4} against {limit} (run {id})", kind.name(), kind.limit_key())
            } else {
                format!("{} (worst: run {id}): {warning}", kind.name())
            };
            (text, runs.get(&kind).copied().unwrap_or(0))
        })
        .collect();
    out + &grouped("Warnings", entries)
}

/// The per-point table of the runs of `tables` and their statistics: rows built in the browser from
/// embedded JSON; a note names the points CSV when the grid has more points than the table holds.
pub(super) fn points_section(tables: &Tables, charted: &[&str], points_csv: &Path) -> String {
    let points = Points::new(&tables.summary);
    let table = html::PointsTable::new(&points, &tables.points, charted);
    let left_out = match table.shown() {
        (shown, total) if shown < total => format!(
            "<p class=\"note\" id=\"points-left-out\">{shown} of {total} grid points shown ({} at most, spread evenly over the grid); every point is in {} and in `demsweep summary --by-point`.</p>",
            html::MAX_POINT_ROWS,
            escape(&points_csv.file_name().unwrap_or_default().to_string_lossy())
        ),
        _ => String::new(),
    };
    let statuses: String =
        RunStatus::RECORDED.iter().map(|s| format!("<option value=\"{s}\">with {s} runs</option>")).collect();
    format!(
        "<h2 id=\"grid-points\">Grid points</h2><p class=\"note\">One row per grid point (the runs that differ only by placement seed): mean ± 95 % confidence half-width over its runs, in the unit of its column's header (hover over a header for what it is). Click a column header to sort; click again to reverse. Tick a header group under \"columns\" to show its columns.</p>{left_out}\
         <div class=\"controls\"><label>show <select id=\"status-filter\"><option value=\"\">all points</option>{statuses}</select></label>\
         <span id=\"column-groups\" title=\"Show or hide a header group's columns.\">columns:</span></div>\
         <div class=\"scroll\"><table id=\"points\">{}<tbody></tbody></table></div>\
         <script type=\"application/json\" id=\"points-data\">{}</script>",
        table.header(),
        table.json()
    )
}

/// The study charts, each as inline SVG.
pub(super) fn charts_section(svgs: &Svgs) -> String {
    let mut out = String::from("<h2 id=\"charts\">Settle time</h2>");
    for (_, svg) in &svgs.drawn.charts {
        out += &format!("<div class=\"chart\">{svg}</div>");
    }
    for note in &svgs.drawn.notes {
        out += &format!("<p class=\"note\">{}</p>", escape(note));
    }
    out
}

/// The pile-metric charts (per-point means with 95 % intervals against each swept axis), two abreast.
pub(super) fn pile_charts_section(svgs: &Svgs) -> String {
    if svgs.drawn.charts.is_empty() {
        return String::new();
    }
    let charts: String = svgs.drawn.charts.iter().map(|(_, svg)| format!("<div class=\"chart\">{svg}</div>")).collect();
    format!(
        "<h2 id=\"pile-metrics\">Pile metrics</h2><p class=\"note\">Mean over the runs at each value of the two chart axes (replicates and further swept parameters) with its 95 % interval, against each of them; each series is shifted a little along x so that intervals at one value stay apart.</p><div class=\"grid2\">{charts}</div>"
    )
}

/// A charted run: its energies, unbalanced force ratio, stress profile and pile, and its deposition's
/// player.
pub(super) fn run_section(row: &SummaryRow, svgs: &Svgs) -> String {
    let charts: String = svgs.drawn.charts.iter().map(|(_, svg)| format!("<div class=\"chart\">{svg}</div>")).collect();
    let notes: String = svgs.drawn.notes.iter().map(|n| format!("<p class=\"note\">{}</p>", escape(n))).collect();
    let mut settle = row.settle_time.map_or("not settled".to_string(), |t| format!("settled at {} s", number(t)));
    if let Some(t) = row.final_value("physics_start_time").filter(|t| *t > 0.0) {
        settle = format!("its protocol's stages ended at {} s; {settle}", number(t));
    }
    format!(
        "<section id=\"run-{id}\"><h3>{}</h3><p class=\"note\">{settle}; {} steps; {} s of computing; {} warnings</p><div class=\"grid2\">{charts}{}</div>{notes}</section>",
        escape(&results::run_subject(row)),
        row.steps,
        number(row.wall_time),
        row.warnings.len(),
        svgs.player.as_deref().unwrap_or(""),
        id = escape(&row.id),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warnings_are_grouped_by_kind_with_the_worst_of_each() {
        let overlap = |value| ValidityWarning::new(WarningKind::Overlap, value, 0.1);
        let energy = ValidityWarning::new(WarningKind::EnergyBalance, 0.05, 0.01);
        let mut rows: Vec<SummaryRow> = (0..3).map(|i| SummaryRow::failed(i, &format!("r{i}"), &[], "")).collect();
        rows[0].warnings = vec![overlap(0.12), overlap(0.13)];
        rows[1].warnings = vec![overlap(0.31), energy];
        let page = outcomes(&rows, false);
        let worst = escape(&overlap(0.31).to_string());
        let group = format!("<td class=\"num\">2</td><td>measured overlap (worst: run r1): {worst}</td>");
        assert!(page.contains(&group), "one row for both runs' overlaps, the worst in full: {page}");
        assert!(page.contains("<td class=\"num\">1</td><td>energy-balance error (worst: run r1): "), "{page}");
        let tune = outcomes(&rows, true);
        let short = "measured overlap (limits.overlap_warning_ratio): worst 0.3100 against 0.1 (run r1)";
        assert!(tune.contains(short), "{tune}");
        assert!(outcomes(&rows[2..], false).contains("No run has a warning."));
    }
}
