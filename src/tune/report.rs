//! What a tune tells: the recommendation paragraph, `<name>_best.toml` (a runnable study of the
//! recommended scene), `<name>_candidates.csv` (every evaluated setting) and the charts.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::search::{Assessment, Candidate, SearchResult, State};
use super::{TuneSpec, seed_text};
use crate::output::csv::write_record;
use crate::plot::tune::{CostPoint, LeverSeries, cost_along_levers_chart, cost_vs_difference_chart};
use crate::plot::{ChartOptions, Format};
use crate::report::TuneSection;
use crate::stats;
use crate::study::ParamValue;

/// Files a tune wrote.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// Every file, in the order written.
    pub files: Vec<PathBuf>,
    /// Charts that could not be drawn, with the reason.
    pub chart_errors: Vec<String>,
}

/// A number short: 4 significant digits.
fn num(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x != 0.0 && !(1e-3..1e5).contains(&x.abs()) {
        format!("{x:.3e}")
    } else {
        let digits = (3 - x.abs().log10().floor() as i32).clamp(0, 8) as usize;
        let text = format!("{x:.digits$}");
        if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.').to_string() } else { text }
    }
}

/// The lever settings of a candidate: `key = value, ...`.
pub fn settings(spec: &TuneSpec, candidate: &Candidate) -> String {
    spec.values(&candidate.point).iter().map(|(k, v)| format!("{k} = {v}")).collect::<Vec<_>>().join(", ")
}

/// The recommendation (or why there is none) as one paragraph.
pub fn paragraph(spec: &TuneSpec, result: &SearchResult) -> String {
    let mut text = String::new();
    let objective = spec.search.objective.name();
    let reference = result.reference_costs();
    let evaluated = result.candidates.iter().filter(|c| !c.runs.is_empty()).count();
    let skipped = result.candidates.iter().filter(|c| c.predicted_invalid.is_some()).count();
    let budget_line = format!(
        "The search evaluated {evaluated} settings ({skipped} more were predicted to diverge and not run) in {} of \
         {} runs; the reference ran on seeds {}.",
        result.runs,
        result.budget,
        seed_text(spec, &(0..result.reference.len() as u64).collect::<Vec<_>>())
    );
    match result.recommended {
        Some(k) => {
            let cand = &result.candidates[k];
            let verified = result.assess_verification(cand).expect("a recommendation is verified");
            let costs: Vec<f64> = cand.verification.iter().map(|o| o.cost).collect();
            let ratio = stats::ratio_interval(&reference, &costs);
            let _ = write!(
                text,
                "Recommendation for {}: {} (candidate {}). Cost ({objective}) {} of the reference (95 % interval \
                 {}-{}), a speedup of {}x. Kept metrics, candidate minus reference with 90 % interval: {}. \
                 Verified on {} fresh placement seeds {} never used during the search. {budget_line}",
                spec.name,
                settings(spec, cand),
                cand.id,
                num(ratio.ratio),
                num(ratio.low),
                num(ratio.high),
                num(1.0 / ratio.ratio),
                metric_lines(spec, result, &verified),
                cand.verification.len(),
                seed_text(spec, &cand.verify_seeds),
            );
        }
        None => {
            let _ = write!(text, "No acceptable setting was found for {}. ", spec.name);
            let failed_verification: Vec<&Candidate> =
                result.candidates.iter().filter(|c| !c.verification.is_empty()).collect();
            for cand in &failed_verification {
                let a = result.assess_verification(cand).expect("verified");
                let _ = write!(
                    text,
                    "Candidate {} ({}) was equivalent during the search but failed verification on seeds {}: {}. ",
                    cand.id,
                    settings(spec, cand),
                    seed_text(spec, &cand.verify_seeds),
                    failure_reason(spec, result, &a)
                );
            }
            match result.closest() {
                Some(k) => {
                    let cand = &result.candidates[k];
                    let a = result.assess(cand);
                    let _ = write!(
                        text,
                        "The closest candidate was {} ({}): cost {} of the reference; {}; metrics: {}. ",
                        cand.id,
                        settings(spec, cand),
                        num(a.cost / stats::describe(&reference).mean),
                        failure_reason(spec, result, &a),
                        metric_lines(spec, result, &a)
                    );
                }
                None => text.push_str("No candidate's runs all settled. "),
            }
            text.push_str(&budget_line);
        }
    }
    text
}

/// `metric difference (low to high, tolerance ±m) decision; ...`.
fn metric_lines(spec: &TuneSpec, result: &SearchResult, a: &Assessment) -> String {
    if a.tests.is_empty() {
        return "not compared (a run failed)".into();
    }
    spec.keep
        .iter()
        .zip(&a.tests)
        .zip(&result.margins)
        .map(|((keep, t), m)| {
            format!(
                "{} {} ({} to {}, tolerance ±{}) {}",
                keep.metric,
                num(t.difference),
                num(t.low),
                num(t.high),
                num(*m),
                decision_name(t.decision)
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

fn decision_name(d: stats::Decision) -> &'static str {
    match d {
        stats::Decision::Equivalent => "equivalent",
        stats::Decision::Different => "different",
        stats::Decision::Undecided => "undecided",
    }
}

/// Why an assessment is not acceptable, naming the failing metric.
pub fn failure_reason(spec: &TuneSpec, result: &SearchResult, a: &Assessment) -> String {
    match &a.state {
        State::NotRun(reason) => format!("not run: {reason}"),
        State::Feasible => "acceptable during the search, but the budget ran out before it was verified".into(),
        State::Infeasible(reason) if a.tests.is_empty() => reason.clone(),
        _ => {
            let worst = a
                .tests
                .iter()
                .zip(&result.margins)
                .enumerate()
                .filter(|(_, (t, _))| t.decision != stats::Decision::Equivalent)
                .max_by(|x, y| (x.1.0.difference.abs() / x.1.1).total_cmp(&(y.1.0.difference.abs() / y.1.1)));
            match worst {
                Some((k, (t, m))) => format!(
                    "{} is {} (difference {}, 90 % interval {} to {}, tolerance ±{}{})",
                    spec.keep[k].metric,
                    decision_name(t.decision),
                    num(t.difference),
                    num(t.low),
                    num(t.high),
                    num(*m),
                    t.seeds_needed.map(|n| format!("; about {n} seeds would decide it")).unwrap_or_default()
                ),
                None => a.state.name().into(),
            }
        }
    }
}

/// Writes `<name>_candidates.csv`, `<name>_best.toml` (when there is a recommendation), the charts and
/// `<name>_recommendation.txt` into `dir`.
pub fn write_all(spec: &TuneSpec, result: &SearchResult, dir: &Path, text: &str) -> Result<Written, String> {
    let mut written = Written::default();
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let csv = dir.join(format!("{}_candidates.csv", spec.name));
    write_candidates(spec, result, &csv).map_err(|e| format!("{}: {e}", csv.display()))?;
    written.files.push(csv);
    if let Some(k) = result.recommended {
        let best = dir.join(format!("{}_best.toml", spec.name));
        std::fs::write(&best, best_study(spec, result, k)).map_err(|e| format!("{}: {e}", best.display()))?;
        written.files.push(best);
    }
    let note = dir.join(format!("{}_recommendation.txt", spec.name));
    std::fs::write(&note, format!("{text}\n")).map_err(|e| format!("{}: {e}", note.display()))?;
    written.files.push(note);
    let plots = dir.join("plots");
    let options = ChartOptions { format: Format::Png, subject: Some(spec.name.clone()), ..Default::default() };
    let (points, recommended) = cost_points(result);
    let chart = plots.join(format!("{}_cost_vs_difference.png", spec.name));
    match cost_vs_difference_chart(&points, recommended, &options, &chart) {
        Ok(()) => written.files.push(chart),
        Err(e) => written.chart_errors.push(e.to_string()),
    }
    let series = lever_series(spec, result);
    let chart = plots.join(format!("{}_cost_along_levers.png", spec.name));
    match cost_along_levers_chart(&series, &options, &chart) {
        Ok(()) => written.files.push(chart),
        Err(e) => written.chart_errors.push(e.to_string()),
    }
    Ok(written)
}

/// One point per evaluated candidate: (largest |difference|/tolerance, cost ratio, feasible).
fn cost_points(result: &SearchResult) -> (Vec<CostPoint>, Option<CostPoint>) {
    let reference = stats::describe(&result.reference_costs()).mean;
    let point = |c: &Candidate| {
        let a = result.assess(c);
        CostPoint {
            worst: if a.worst.is_finite() { a.worst } else { f64::NAN },
            cost_ratio: a.cost / reference,
            feasible: a.state == State::Feasible,
            failed: a.tests.is_empty(),
        }
    };
    let points = result.candidates.iter().filter(|c| !c.runs.is_empty()).map(point).collect();
    (points, result.recommended.map(|k| point(&result.candidates[k])))
}

fn lever_series(spec: &TuneSpec, result: &SearchResult) -> Vec<LeverSeries> {
    let reference = stats::describe(&result.reference_costs()).mean;
    spec.levers
        .iter()
        .enumerate()
        .map(|(d, lever)| {
            let points = result
                .candidates
                .iter()
                .filter(|c| !c.runs.is_empty())
                .map(|c| {
                    let a = result.assess(c);
                    let x = match lever.value(c.point[d]) {
                        ParamValue::Float(x) => x,
                        ParamValue::Int(i) => i as f64,
                        _ => c.point[d],
                    };
                    (x, a.cost / reference, a.state == State::Feasible)
                })
                .collect();
            let best = result.recommended.map(|k| {
                let c = &result.candidates[k];
                match lever.value(c.point[d]) {
                    ParamValue::Float(x) => x,
                    ParamValue::Int(i) => i as f64,
                    _ => c.point[d],
                }
            });
            LeverSeries { name: lever.key.clone(), log: lever.is_log(), points, best }
        })
        .collect()
}

/// The candidates table.
fn write_candidates(spec: &TuneSpec, result: &SearchResult, path: &Path) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for record in candidate_records(spec, result) {
        write_record(&mut out, &record)?;
    }
    std::io::Write::flush(&mut out)
}

/// The candidates table (`<name>_candidates.csv`): the header, the reference, then every evaluated
/// setting with its levers, n, cost, metric means, decisions and verification.
pub fn candidate_records(spec: &TuneSpec, result: &SearchResult) -> Vec<Vec<String>> {
    let reference = stats::describe(&result.reference_costs());
    let mut header: Vec<String> = vec!["candidate".into(), "origin".into()];
    header.extend(spec.levers.iter().map(|l| l.key.clone()));
    header.extend(["n".into(), "cost_mean".into(), "cost_ratio".into()]);
    for keep in &spec.keep {
        header.extend([
            format!("{}_mean", keep.metric),
            format!("{}_difference", keep.metric),
            format!("{}_decision", keep.metric),
        ]);
    }
    header.extend([
        "worst_difference_over_tolerance".into(),
        "decision".into(),
        "reason".into(),
        "verify_n".into(),
        "verify_cost_ratio".into(),
        "verify_decision".into(),
        "recommended".into(),
    ]);
    let mut records = vec![header];
    let mean_of = |runs: &[super::Outcome], k: usize| {
        stats::describe(&runs.iter().map(|o| o.metrics[k]).collect::<Vec<_>>()).mean
    };
    let reference_row: Vec<String> =
        {
            let mut row = vec!["0".to_string(), "reference".into()];
            let values = spec.reference_values();
            row.extend(spec.levers.iter().map(|l| {
                values.iter().find(|(k, _, _)| *k == l.key).map(|(_, v, _)| v.to_string()).unwrap_or_default()
            }));
            row.extend([result.reference.len().to_string(), format!("{:?}", reference.mean), "1.0".into()]);
            for k in 0..spec.keep.len() {
                row.extend([format!("{:?}", mean_of(&result.reference, k)), "0.0".into(), String::new()]);
            }
            row.extend(["0.0".into(), "reference".into()]);
            row.extend(std::iter::repeat_n(String::new(), 5));
            row
        };
    records.push(reference_row);
    for (index, cand) in result.candidates.iter().enumerate() {
        let a = result.assess(cand);
        let mut row = vec![cand.id.to_string(), cand.origin.name().to_string()];
        row.extend(spec.values(&cand.point).iter().map(|(_, v)| crate::output::table::param_text(v)));
        let number = |x: f64| if x.is_finite() { format!("{x:?}") } else { String::new() };
        row.extend([a.n.to_string(), number(a.cost), number(a.cost / reference.mean)]);
        for k in 0..spec.keep.len() {
            let mean = if cand.runs.is_empty() { f64::NAN } else { mean_of(&cand.runs, k) };
            match a.tests.get(k) {
                Some(t) => row.extend([number(mean), number(t.difference), decision_name(t.decision).into()]),
                None => row.extend([number(mean), String::new(), String::new()]),
            }
        }
        let reason = match &a.state {
            State::Feasible => String::new(),
            _ => failure_reason(spec, result, &a),
        };
        row.extend([number(a.worst), a.state.name().into(), reason]);
        match result.assess_verification(cand) {
            Some(v) => row.extend([v.n.to_string(), number(v.cost / reference.mean), v.state.name().into()]),
            None => row.extend([String::new(), String::new(), String::new()]),
        }
        row.push((result.recommended == Some(index)).to_string());
        records.push(row);
    }
    records
}

/// The tune's section of the report page: the recommendation, the cost-versus-deviation chart (SVG)
/// and the candidates table.
pub fn report_section(spec: &TuneSpec, result: &SearchResult, text: &str) -> Result<TuneSection, String> {
    let options = ChartOptions { subject: Some(spec.name.clone()), ..Default::default() };
    let (points, recommended) = cost_points(result);
    let mut chart_svg = String::new();
    cost_vs_difference_chart(&points, recommended, &options, &mut chart_svg).map_err(|e| e.to_string())?;
    Ok(TuneSection { recommendation: text.to_string(), chart_svg, candidates: candidate_records(spec, result) })
}

/// A runnable study of the recommended scene: the reference scene with the lever values set, run on
/// the verification seeds.
pub fn best_study(spec: &TuneSpec, result: &SearchResult, k: usize) -> String {
    let cand = &result.candidates[k];
    let mut scene = spec.base.clone();
    for (key, value) in spec.values(&cand.point) {
        let path: Vec<String> = key.split('.').map(String::from).collect();
        let _ = crate::study::file::set_path(&mut scene, &path, value.to_toml());
    }
    let first_seed = spec.reference.placement.seed.wrapping_add(cand.verify_seeds.first().copied().unwrap_or(0));
    let _ = crate::study::file::set_path(
        &mut scene,
        &["placement".to_string(), "seed".to_string()],
        toml::Value::Integer(first_seed as i64),
    );
    let mut doc = toml::Table::new();
    doc.insert("name".into(), toml::Value::String(format!("{}_best", spec.name)));
    doc.insert(
        "description".into(),
        toml::Value::String(format!(
            "the recommendation of `demsweep tune {}`: {}",
            spec.path.display(),
            settings(spec, cand)
        )),
    );
    doc.insert("scene".into(), toml::Value::Table(scene));
    let mut sweep = toml::Table::new();
    sweep.insert("replicates".into(), toml::Value::Integer(cand.verification.len().max(1) as i64));
    doc.insert("sweep".into(), toml::Value::Table(sweep));
    let header = format!(
        "# Written by `demsweep tune {}`: the reference scene with the recommended levers\n# ({}), \
         on its verification seeds. Run it with: demsweep run {}_best.toml\n",
        spec.path.display(),
        spec.levers.iter().map(|l| l.key.as_str()).collect::<Vec<_>>().join(", "),
        spec.name
    );
    format!("{header}{}", toml::to_string(&doc).unwrap_or_default())
}
