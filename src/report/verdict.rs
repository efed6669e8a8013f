//! The answer at the top of the page: the grid points that settle fastest, and, when the study names
//! a reference point, which points make the same pile at what cost.

use super::html::{escape, number};
use crate::output::SummaryTable;
use crate::physics::quantity;
use crate::stats::compare::{self, Comparison};
use crate::stats::points::Points;
use crate::stats::{Decision, Describe};

/// Grid points the answer at the top of the page lists at most.
const VERDICT_POINTS: usize = 5;

/// The answer first: the grid points that settle fastest (mean settle time over their settled runs
/// with its 95 % interval, and their cost), and whether each can be told apart from the fastest
/// (its interval above the fastest's) or not (the intervals overlap: more seeds would decide); then,
/// when the study names a reference point (`spec`), which points are equivalent to it.
pub(super) fn verdict(summary: &SummaryTable, spec: Option<&str>) -> String {
    let points = Points::new(summary);
    let answer = first_answer(&points, spec);
    let reference = spec.map_or(String::new(), |spec| reference_section(&points, spec));
    let mut settled: Vec<(usize, Describe)> = (0..points.len())
        .map(|p| (p, points.describe(p, quantity::SETTLE_TIME.name)))
        .filter(|(_, d)| d.n > 0 && d.mean.is_finite())
        .collect();
    if settled.is_empty() {
        return format!(
            "<h2 id=\"verdict\">The answer</h2>{answer}<p class=\"verdict\">No grid point has a settled run: nothing \
             settles in this sweep (see how the runs ended below).</p>{reference}"
        );
    }
    settled.sort_by(|a, b| a.1.mean.total_cmp(&b.1.mean));
    let fastest = &settled[0].1;
    let fastest_top = fastest.mean + fastest.half_width_95.max(0.0);
    let rows: String = settled
        .iter()
        .take(VERDICT_POINTS)
        .enumerate()
        .map(|(rank, (point, d))| {
            let runs = points.rows(*point).len();
            let cost = points.describe(*point, "particle_steps");
            let judged = match rank {
                0 => "the fastest".to_string(),
                _ if !d.half_width_95.is_finite() || !fastest.half_width_95.is_finite() => {
                    "one settled run: no interval to compare".to_string()
                }
                _ if d.mean - d.half_width_95 > fastest_top => "slower than the fastest (the intervals are apart)".into(),
                _ => "not told apart from the fastest (the intervals overlap)".into(),
            };
            format!(
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{} of {runs}</td><td class=\"num\">{}</td><td>{judged}</td></tr>",
                escape(&points.label(*point)),
                escape(&crate::stats::points::plus_minus(Some(d.mean), Some(d.half_width_95))),
                d.n,
                number(cost.mean),
            )
        })
        .collect();
    let undecided = settled.iter().skip(1).filter(|(_, d)| d.mean - d.half_width_95 <= fastest_top).count();
    let summary_line = match undecided {
        0 => "The fastest grid point settles sooner than every other: its 95 % interval lies below theirs.".to_string(),
        n => format!(
            "{n} other grid point(s) cannot be told apart from the fastest at these seeds: their 95 % intervals \
             overlap; more replicates would decide."
        ),
    };
    format!(
        "<h2 id=\"verdict\">The answer</h2>{answer}<p class=\"verdict\">Fastest-settling grid points (mean settle time \
         over the settled runs, ± the 95 % confidence half-width). {summary_line}</p>\
         <table class=\"verdict\"><thead><tr><th>grid point</th><th>{}</th><th>settled runs</th>\
         <th>{}</th><th></th></tr></thead><tbody>{rows}</tbody></table>{reference}",
        escape(&quantity::label(quantity::SETTLE_TIME.name)),
        escape(&quantity::label("particle_steps_mean")),
    )
}

/// The study's question answered in one paragraph (`<p id="answer">`). With a reference point
/// (`spec`): the cheapest grid point faster than the reference (by the cost ratio) that makes an
/// equivalent pile, or, when none of the faster points does, the nearest miss and the metric that
/// moved most. Without one: the cheapest point, and that its pile was not compared.
fn first_answer(points: &Points, spec: Option<&str>) -> String {
    let text = match spec.map(|spec| ReferenceVerdict::new(points, spec)) {
        Some(Ok(verdict)) => reference_answer(points, &verdict),
        Some(Err(_)) | None => cheapest_answer(points, spec.is_some()),
    };
    format!("<p class=\"verdict answer\" id=\"answer\">{text}</p>")
}

/// The answer against the reference point (see [`first_answer`]).
fn reference_answer(points: &Points, verdict: &ReferenceVerdict) -> String {
    let comparison = &verdict.comparison;
    let reference = escape(&points.label(comparison.reference));
    let cost = &comparison.cost_column;
    let faster: Vec<usize> = (0..comparison.points.len()).filter(|&i| comparison.points[i].cost.ratio < 1.0).collect();
    let costs = |p: &compare::PointComparison| {
        let ratios = format!(
            "{} of the reference's {cost} and {} of its wall time",
            compare::ratio(&p.cost),
            compare::ratio(&p.wall_time)
        );
        (ratios, if ratios_disagree(p) { vec![points.label(p.point)] } else { Vec::new() })
    };
    if let Some(&best) = verdict.equivalent.iter().find(|i| faster.contains(i)) {
        let point = &comparison.points[best];
        let (ratios, disagreeing) = costs(point);
        return format!(
            "<b>{}</b> is the fastest grid point that makes the same pile as the reference ({reference}): every kept \
             metric is equivalent, at {ratios}.{}",
            escape(&points.label(point.point)),
            disagreement(&disagreeing, cost)
        );
    }
    let deviation = |i: &usize| comparison.points[*i].deviation(&comparison.kept);
    let Some(&miss) = faster.iter().min_by(|a, b| deviation(a).total_cmp(&deviation(b))) else {
        return format!(
            "No grid point is faster than the reference ({reference}) by {cost}: keep the reference's settings."
        );
    };
    let point = &comparison.points[miss];
    let moved = (0..comparison.kept.len())
        .max_by(|&a, &b| {
            let share = |k: usize| point.tests[k].difference.abs() / comparison.kept[k].margin;
            share(a).total_cmp(&share(b))
        })
        .map_or(String::new(), |k| {
            let (kept, test) = (&comparison.kept[k], &point.tests[k]);
            let decision = match test.decision {
                Decision::Different => "different",
                _ => "not shown equivalent (more seeds would decide)",
            };
            format!(
                ": its {} moved by {} from the reference's {} (the margin is ± {}), {decision}",
                escape(&kept.tolerance.metric),
                number(test.difference),
                number(kept.reference.mean),
                number(kept.margin)
            )
        });
    let (ratios, disagreeing) = costs(point);
    format!(
        "None of the {} faster grid points makes the same pile as the reference ({reference}). The nearest miss is \
         <b>{}</b>, at {ratios}{moved}.{}",
        faster.len(),
        escape(&points.label(point.point)),
        disagreement(&disagreeing, cost)
    )
}

/// The answer without a comparable reference: the point with settled runs of the lowest mean
/// cost, and that its pile was not compared (`named`: the study names a reference that could not be compared).
fn cheapest_answer(points: &Points, named: bool) -> String {
    let cost = if points.metric_names().contains(&"particle_steps") { "particle_steps" } else { "steps" };
    let cheapest = (0..points.len())
        .filter(|&p| points.describe(p, quantity::SETTLE_TIME.name).n > 0)
        .map(|p| (p, points.describe(p, cost)))
        .filter(|(_, d)| d.mean.is_finite())
        .min_by(|a, b| a.1.mean.total_cmp(&b.1.mean));
    let why = if named {
        "the study's reference point could not be compared (see below)"
    } else {
        "the study names no reference point (<code>[report] reference</code>, docs/studies.md)"
    };
    let Some((point, d)) = cheapest else {
        return format!("No grid point has a settled run, so none is the fastest; the pile was not compared: {why}.");
    };
    format!(
        "<b>{}</b> is the fastest grid point: {} {cost} per run (mean ± 95 % half-width). The pile was not compared: \
         {why}, so whether it makes the same pile as your usual settings is not known.",
        escape(&points.label(point)),
        escape(&crate::stats::points::plus_minus(Some(d.mean), Some(d.half_width_95))),
    )
}

/// Which ratio to trust, for the points (`labels`) whose cost and wall-time ratios disagree; empty
/// when there are none.
fn disagreement(labels: &[String], cost: &str) -> String {
    if labels.is_empty() {
        return String::new();
    }
    format!(
        " <span class=\"note\">For {}, the {cost} and wall-time ratios disagree (their 95 % intervals do not \
         overlap): trust the {cost} ratio. It counts the work done (disks × time steps), the same on any machine; \
         wall time also counts whatever else the machine was running, which on a shared or busy machine moves it by \
         more than the difference. Wall time is worth a second look only where the work per step differs (another \
         contact law, many more contacts), measured on an idle machine.</span>",
        escape(&labels.join(", "))
    )
}

/// Whether a point's cost and wall-time ratios disagree: their 95 % intervals do not overlap.
fn ratios_disagree(point: &compare::PointComparison) -> bool {
    let (c, w) = (&point.cost, &point.wall_time);
    c.high < w.low || w.high < c.low
}

/// The points compared with the study's reference point (`demsweep compare`, default tolerances),
/// sorted by their decision over every kept metric (TOST at 90 %).
#[derive(Debug)]
struct ReferenceVerdict {
    /// Every other point against the reference.
    comparison: Comparison,
    /// Indices into `comparison.points`, each list cheapest first: equivalent on every kept metric.
    equivalent: Vec<usize>,
    /// Different on at least one kept metric.
    different: Vec<usize>,
    /// Neither: more seeds would decide.
    undecided: Vec<usize>,
}

impl ReferenceVerdict {
    fn new(points: &Points, spec: &str) -> Result<Self, crate::stats::CompareError> {
        let comparison = compare::compare(points, spec, &[])?;
        let (mut equivalent, mut different, mut undecided) = (Vec::new(), Vec::new(), Vec::new());
        for (i, point) in comparison.points.iter().enumerate() {
            match () {
                _ if point.acceptable() => equivalent.push(i),
                _ if point.tests.iter().any(|t| t.decision == Decision::Different) => different.push(i),
                _ => undecided.push(i),
            }
        }
        let cheapest_first = |list: &mut Vec<usize>| {
            list.sort_by(|&a, &b| comparison.points[a].cost.ratio.total_cmp(&comparison.points[b].cost.ratio))
        };
        [&mut equivalent, &mut different, &mut undecided].into_iter().for_each(cheapest_first);
        Ok(Self { comparison, equivalent, different, undecided })
    }
}

/// The answer about the study's reference point: which points make the same pile, at what cost.
fn reference_section(points: &Points, spec: &str) -> String {
    let verdict = match ReferenceVerdict::new(points, spec) {
        Ok(verdict) => verdict,
        Err(reason) => {
            return format!(
                "<h3 id=\"reference\">Against the reference point</h3><p class=\"note\">The study's reference ({}) \
                 cannot be compared: {}</p>",
                escape(spec),
                escape(&reason.to_string())
            );
        }
    };
    let comparison = &verdict.comparison;
    let kept: Vec<String> = comparison
        .kept
        .iter()
        .map(|k| format!("{} within {} %", k.tolerance.metric, number(100.0 * k.tolerance.relative)))
        .collect();
    // Long names and intervals wrap (at underscores, before the interval) so the table fits the page.
    let wrapped = |text: &str| escape(text).replace('_', "_<wbr>").replacen(" [", "<br>[", 1);
    let metric_headers: String =
        comparison.kept.iter().map(|k| format!("<th>{}</th>", wrapped(&k.tolerance.metric))).collect();
    let cost = &comparison.cost_column;
    let cost_header = wrapped(cost);
    let row = |i: &usize, judged: &str| {
        let point = &comparison.points[*i];
        let decisions: String = point.tests.iter().map(|t| format!("<td>{}</td>", t.decision.as_str())).collect();
        format!(
            "<tr><td>{}</td>{decisions}<td class=\"num\">{}</td><td class=\"num\">{}</td><td>{judged}</td></tr>",
            escape(&points.label(point.point)),
            wrapped(&compare::ratio(&point.cost)),
            wrapped(&compare::ratio(&point.wall_time)),
        )
    };
    let rows: String =
        [(&verdict.equivalent, "equivalent"), (&verdict.undecided, "undecided"), (&verdict.different, "different")]
            .iter()
            .flat_map(|(list, judged)| list.iter().map(move |i| row(i, judged)))
            .collect();
    let notes: String = comparison.notes.iter().map(|n| format!(" {}.", escape(n))).collect();
    let disagreeing: Vec<String> =
        comparison.points.iter().filter(|p| ratios_disagree(p)).map(|p| points.label(p.point)).collect();
    let disagreeing = match disagreement(&disagreeing, cost) {
        note if note.is_empty() => note,
        note => format!("<p class=\"note\" id=\"ratios-disagree\">{}</p>", note.trim_start()),
    };
    format!(
        "<h3 id=\"reference\">Against the reference point</h3><p class=\"verdict\" id=\"reference-verdict\">Reference: \
         {}. {} of {} other grid points make an equivalent pile (TOST, 90 % intervals of the difference inside \
         the margins: {}); {} differ, {} are undecided (more seeds would decide).{notes} Cost: {cost} and wall time \
         relative to the reference, with 95 % intervals.</p><table class=\"verdict\" id=\"reference-table\"><thead><tr>\
         <th>grid point</th>{metric_headers}<th>{cost_header} ratio</th><th>wall time ratio</th><th>pile</th></tr></thead>\
         <tbody>{rows}</tbody></table>{disagreeing}",
        escape(&points.label(comparison.reference)),
        verdict.equivalent.len(),
        comparison.points.len(),
        escape(&kept.join(", ")),
        verdict.different.len(),
        verdict.undecided.len(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::table::{Column, ColumnData};

    /// Six runs at each friction 0.2, 0.4, 0.6: the packing fraction of 0.4 within 0.1 % of 0.2's
    /// at half the particle-steps, that of 0.6 10 % higher.
    fn summary() -> SummaryTable {
        summary_of(&[(0.2, 0.80, 2e6, 1.0), (0.4, 0.8004, 1e6, 1.0), (0.6, 0.88, 2e6, 1.0)])
    }

    /// Six runs at each (friction, packing fraction, particle-steps, wall seconds per 1e7 particle-steps).
    fn summary_of(grid: &[(f64, f64, f64, f64)]) -> SummaryTable {
        let (mut friction, mut packing, mut cost, mut wall) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (point, (mu, level, steps, speed)) in grid.iter().enumerate() {
            for seed in 0..6 {
                let noise = [-2.0, 1.0, 0.5, -0.5, 1.5, -0.5][(seed + point) % 6] * 1e-4;
                friction.push(*mu);
                packing.push(level + noise);
                cost.push(steps * (1.0 + noise));
                wall.push(steps * (1.0 + noise) * 1e-7 * speed);
            }
        }
        let n = friction.len();
        let column = |name: &str, data| Column { name: name.to_string(), data };
        SummaryTable {
            columns: vec![
                column("index", ColumnData::Int((0..n as i64).collect())),
                column("material.friction", ColumnData::Float(friction)),
                column("status", ColumnData::Text(vec!["settled".into(); n])),
                column("settle_time", ColumnData::Float(vec![0.5; n])),
                column("packing_fraction_interior", ColumnData::Float(packing)),
                column("particle_steps", ColumnData::Float(cost.clone())),
                column("wall_time", ColumnData::Float(wall)),
            ],
        }
    }

    #[test]
    fn the_reference_verdict_sorts_points_by_their_tost_decision() {
        let summary = summary();
        let points = Points::new(&summary);
        let verdict = ReferenceVerdict::new(&points, "friction=0.2").unwrap();
        let label = |i: &usize| points.label(verdict.comparison.points[*i].point);
        assert_eq!(points.label(verdict.comparison.reference), "material.friction=0.2");
        assert_eq!(verdict.equivalent.iter().map(label).collect::<Vec<_>>(), ["material.friction=0.4"]);
        assert_eq!(verdict.different.iter().map(label).collect::<Vec<_>>(), ["material.friction=0.6"]);
        assert!(verdict.undecided.is_empty());
        let cost = &verdict.comparison.points[verdict.equivalent[0]].cost;
        assert!((cost.ratio - 0.5).abs() < 1e-3 && cost.low < 0.5 && cost.high > 0.5, "{cost:?}");
        let html = super::verdict(&summary, Some("friction=0.2"));
        assert!(html.contains("1 of 2 other grid points make an equivalent pile"), "{html}");
        assert!(ReferenceVerdict::new(&points, "friction=0.3").unwrap_err().to_string().contains("no point has"));
    }

    /// The text of the page's first answer.
    fn answer(summary: &SummaryTable, spec: Option<&str>) -> String {
        let html = super::verdict(summary, spec);
        let start = html.find("<p class=\"verdict answer\" id=\"answer\">").expect("the answer paragraph");
        html[start..].split("</p>").next().unwrap().to_string()
    }

    #[test]
    fn the_answer_is_the_fastest_point_that_makes_the_same_pile() {
        let text = answer(&summary(), Some("friction=0.2"));
        assert!(
            text.contains("<b>material.friction=0.4</b> is the fastest grid point that makes the same pile"),
            "{text}"
        );
        let rounded = "0.500000 [0.499919, 0.500081] of the reference's particle_steps"; // half-width 8.1e-5
        assert!(
            text.contains(rounded) && !text.contains("disagree"),
            "the cost ratio, rounded to its interval: {text}"
        );
        let html = super::verdict(&summary(), Some("friction=0.2"));
        assert!(html.find("id=\"answer\"").unwrap() < html.find("Fastest-settling").unwrap_or(usize::MAX), "first");
    }

    #[test]
    fn without_an_equivalent_faster_point_the_answer_names_the_nearest_miss_and_what_moved() {
        // 0.4 and 0.6 are faster than 0.2; both piles differ, 0.4's less.
        let grid = [(0.2, 0.80, 2e6, 1.0), (0.4, 0.84, 1e6, 1.0), (0.6, 0.90, 1.5e6, 1.0)];
        let text = answer(&summary_of(&grid), Some("friction=0.2"));
        assert!(
            text.starts_with("<p class=\"verdict answer\" id=\"answer\">None of the 2 faster grid points"),
            "{text}"
        );
        assert!(text.contains("The nearest miss is <b>material.friction=0.4</b>"), "{text}");
        assert!(text.contains("its packing_fraction_interior moved by 0.04"), "{text}");
        let slower = [(0.2, 0.80, 1e6, 1.0), (0.4, 0.80, 2e6, 1.0)];
        assert!(
            answer(&summary_of(&slower), Some("friction=0.2")).contains("No grid point is faster than the reference")
        );
    }

    #[test]
    fn without_a_reference_the_answer_is_the_fastest_point_and_says_the_pile_was_not_compared() {
        let text = answer(&summary(), None);
        assert!(text.contains("<b>material.friction=0.4</b> is the fastest grid point"), "{text}");
        assert!(text.contains("The pile was not compared: the study names no reference point"), "{text}");
        let mut unsettled = summary();
        unsettled.columns.retain(|c| c.name != "settle_time");
        assert!(answer(&unsettled, None).contains("No grid point has a settled run, so none is the fastest"));
    }

    #[test]
    fn where_wall_time_and_particle_steps_disagree_the_page_says_which_to_trust() {
        // 0.4 takes half the particle-steps but, on a busy machine, three times the wall time per step.
        let grid = [(0.2, 0.80, 2e6, 1.0), (0.4, 0.8004, 1e6, 3.0), (0.6, 0.88, 2e6, 1.0)];
        let html = super::verdict(&summary_of(&grid), Some("friction=0.2"));
        let text = answer(&summary_of(&grid), Some("friction=0.2"));
        assert!(text.contains("the particle_steps and wall-time ratios disagree"), "{text}");
        assert!(text.contains("trust the particle_steps ratio"), "{text}");
        assert!(html.contains("id=\"ratios-disagree\""), "beside the table too");
        assert!(!super::verdict(&summary(), Some("friction=0.2")).contains("disagree"), "agreeing ratios: no note");
    }
}
