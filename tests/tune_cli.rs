//! `demsweep tune` as a user runs it: a tiny real tune end to end, killed with SIGKILL and resumed to
//! the same answer as an uninterrupted tune, `check` and `plan` on tune files, and bad tune files that
//! give every problem with file, line and key and write nothing.

mod runner_common;
mod tune_common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use demsweep::output::summary;
use runner_common::{demsweep, text};
use tune_common::TUNE;

fn write_tune(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("tiny_tune.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The recommendation paragraph (the line starting with "Recommendation" or "No acceptable").
/// The answer sheet: from its first line to the next blank line.
fn paragraph(stdout: &str) -> String {
    let start = stdout.lines().position(|l| l.starts_with("Recommendation") || l.starts_with("No acceptable"));
    let lines = stdout.lines().skip(start.unwrap_or(usize::MAX)).take_while(|l| !l.is_empty());
    lines.collect::<Vec<_>>().join("\n")
}

fn tune(file: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap()];
    args.extend(extra);
    demsweep(&args)
}

/// [`tune`], which must exit 0.
fn tuned(file: &Path, out: &Path, extra: &[&str]) -> Output {
    let output = tune(file, out, extra);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    output
}

#[test]
fn a_tiny_tune_runs_end_to_end() {
    let dir = runner_common::scratch("tune_end_to_end");
    let file = write_tune(&dir, TUNE);
    let check = demsweep(&["check", file.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stderr));
    assert!(text(&check.stdout).starts_with("ok: tune file, 2 levers, 1 kept metrics, budget 40 runs"));
    let plan = demsweep(&["plan", file.to_str().unwrap(), "--cores", "2"]);
    assert_eq!(plan.status.code(), Some(0), "{}", text(&plan.stderr));
    assert!(text(&plan.stdout).contains("budget bound"), "{}", text(&plan.stdout));

    let out = dir.join("out");
    let run = tuned(&file, &out, &["--jobs", "2"]);
    let stdout = text(&run.stdout);
    let said = paragraph(&stdout);
    // The answer is a point of the lever space or a standard setting (verified before the search).
    let answer = said.strip_prefix("Recommendation for tiny_tune: ").expect("a recommendation");
    assert!(answer.starts_with("material.restitution = ") || answer.starts_with("the standard setting"), "{stdout}");
    assert!(said.contains("of the reference (95 % interval"), "{said}");
    let verified = said.split("Verified on ").nth(1).and_then(|rest| rest.split(' ').next()?.parse::<usize>().ok());
    assert!(verified.is_some_and(|seeds| seeds >= 3), "verified on fresh seeds, at least verify_seeds of them: {said}");
    for name in [
        "tiny_tune.h5",
        "tiny_tune_summary.csv",
        "tiny_tune_candidates.csv",
        "tiny_tune_best.toml",
        "tiny_tune_recommendation.txt",
        "plots/tiny_tune_cost_vs_difference.png",
        "plots/tiny_tune_cost_along_levers.png",
        "tiny_tune_tune.json",
        "tiny_tune_report.html",
    ] {
        assert!(out.join(name).is_file(), "{name} missing; {stdout}");
    }
    // The report page carries the tune, answer first: recommendation, pile metrics as a list, chart
    // and candidates, before how the runs ended, and no study charts averaged over the levers; so does
    // a rewrite.
    let page = std::fs::read_to_string(out.join("tiny_tune_report.html")).unwrap();
    let tune_at = page.find("<h2 id=\"tune\">").expect("a tune section");
    assert!(tune_at < page.find("id=\"outcomes\"").unwrap(), "the answer comes first");
    assert!(!page.contains("id=\"grid-points\"") && !page.contains("id=\"charts\""), "no lever-averaged charts");
    let tune_part = &page[tune_at..];
    assert!(tune_part.contains("<ul class=\"metrics\"><li>settle_time: "), "every pile metric, one per line");
    assert!(
        tune_part.contains("Recommendation for tiny_tune") && tune_part.contains("<svg"),
        "recommendation and chart"
    );
    assert!(tune_part.contains("<th>cost_ratio</th>"), "the candidates table");
    let rewritten = out.join("again.html");
    let report =
        demsweep(&["report", out.join("tiny_tune.h5").to_str().unwrap(), "--out", rewritten.to_str().unwrap()]);
    assert_eq!(report.status.code(), Some(0), "{}", text(&report.stderr));
    assert!(std::fs::read_to_string(&rewritten).unwrap().contains("Recommendation for tiny_tune"));
    // Every run is in the results file, within the budget.
    let runs = summary::read(&out.join("tiny_tune.h5")).unwrap().len();
    assert!((10..=40).contains(&runs), "{runs} runs");
    let csv = std::fs::read_to_string(out.join("tiny_tune_candidates.csv")).unwrap();
    let header: Vec<&str> = csv.lines().take(2).collect();
    assert!(
        header[0]
            .starts_with("candidate,origin,material.restitution,integrator.time_step,n,particle_steps_mean,cost_ratio")
    );
    let sidecar = std::fs::read_to_string(out.join("tiny_tune_candidates.csv-metadata.json")).unwrap();
    let meta: serde_json::Value = serde_json::from_str(&sidecar).unwrap();
    assert_eq!(meta["tableSchema"]["columns"][3]["schema:unitText"], "s", "the time step's unit: {sidecar}");
    let datatype = |k: usize| meta["tableSchema"]["columns"][k]["datatype"].as_str().unwrap_or_default().to_string();
    let last = meta["tableSchema"]["columns"].as_array().map_or(0, Vec::len) - 1;
    assert_eq!(
        [datatype(0), datatype(1), datatype(4), datatype(6), datatype(last)],
        ["integer", "string", "integer", "double", "boolean"],
        "candidate, origin, n, cost ratio and recommended typed from their cells: {sidecar}"
    );
    assert!(header[1].starts_with("0,reference,"), "the values follow the names: {}", header[1]);
    assert_eq!(csv.lines().filter(|l| l.ends_with(",true")).count(), 1, "one recommended row");
    // The best study is a runnable study.
    let best = out.join("tiny_tune_best.toml");
    let checked = demsweep(&["check", best.to_str().unwrap()]);
    assert_eq!(checked.status.code(), Some(0), "{}", text(&checked.stderr));
    // An existing file is neither overwritten nor resumed without being asked.
    let again = tune(&file, &out, &[]);
    assert_eq!(again.status.code(), Some(1));
    assert!(text(&again.stderr).contains("--resume"), "{}", text(&again.stderr));
    // Runs another demsweep version made are reused only when accepted, with the same answer.
    runner_common::made_by(&out.join("tiny_tune.h5"), "0.0.9");
    let refused = tune(&file, &out, &["--resume"]);
    let said_refused = text(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{said_refused}");
    assert!(said_refused.contains("was made by demsweep 0.0.9") && said_refused.contains("--accept-version"));
    let accepted = tuned(&file, &out, &["--resume", "--accept-version", "--jobs", "2"]);
    assert_eq!(paragraph(&text(&accepted.stdout)), said, "the same answer from the same runs");
}

#[test]
fn killed_with_sigkill_then_resumed_equals_an_uninterrupted_tune() {
    let dir = runner_common::scratch("tune_kill");
    let file = write_tune(&dir, TUNE);
    let reference_out = dir.join("reference");
    let reference = tuned(&file, &reference_out, &["--jobs", "2"]);

    let out = dir.join("killed");
    let mut child = Command::new(env!("CARGO_BIN_EXE_demsweep"))
        .args(["tune", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--jobs", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let results = out.join("tiny_tune.h5");
    let started = Instant::now();
    while !summary::read(&results).is_ok_and(|t| t.len() >= 4) {
        assert!(child.try_wait().unwrap().is_none(), "the tune ended before it could be killed");
        assert!(started.elapsed() < Duration::from_secs(60), "no commit within a minute");
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    assert_eq!(child.wait().unwrap().code(), None, "killed by a signal");
    let kept = summary::read(&results).unwrap().len();

    let resumed = tuned(&file, &out, &["--resume", "--jobs", "2"]);
    let said = text(&resumed.stdout);
    assert!(said.contains("from the file"), "{said}");
    // The sheet's `--resume` command names each tune's own `--out` folder.
    let sheet = |stdout: &str, out: &Path| paragraph(stdout).replace(out.to_str().unwrap(), "OUT");
    assert_eq!(sheet(&said, &out), sheet(&text(&reference.stdout), &reference_out));
    let read = |dir: &Path, name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
    for name in ["tiny_tune_candidates.csv", "tiny_tune_best.toml"] {
        assert_eq!(read(&out, name), read(&reference_out, name), "{name} differs after resuming {kept} runs");
    }
    let table = |dir: &Path| summary::read(&dir.join("tiny_tune.h5")).unwrap().without_timing();
    assert_eq!(table(&out), table(&reference_out));
}

/// The runs a tune's stdout says it took from the file.
fn from_the_file(stdout: &str) -> usize {
    let counts = stdout.lines().rev().find(|l| l.contains(" from the file)")).expect("the closing line");
    counts.split(", ").nth(1).and_then(|t| t.split(' ').next()?.parse().ok()).expect("a count")
}

#[test]
fn a_resumed_tune_notes_only_the_stored_runs_it_did_not_replay() {
    let dir = runner_common::scratch("tune_unplanned");
    let file = write_tune(&dir, TUNE);
    let out = dir.join("out");
    tuned(&file, &out, &["--jobs", "2"]);
    let stored = summary::read(&out.join("tiny_tune.h5")).unwrap().len();
    // Replaying the same tune: the runs its later batches take from the file are not "unplanned".
    let again = tuned(&file, &out, &["--resume", "--jobs", "2"]);
    assert_eq!(from_the_file(&text(&again.stdout)), stored, "every run replayed");
    assert!(!text(&again.stderr).contains("note:"), "{}", text(&again.stderr));
    // Another search seed goes another way: the stored runs it leaves are named once, at the end.
    write_tune(&dir, &TUNE.replace("seed = 3\n", "seed = 4\n"));
    let other = tuned(&file, &out, &["--resume", "--jobs", "2"]);
    let reused = from_the_file(&text(&other.stdout));
    let stderr = text(&other.stderr);
    let notes: Vec<&str> = stderr.lines().filter(|l| l.starts_with("note:")).collect();
    let expected = format!("{} stored run(s) were not replayed by this tune", stored - reused);
    assert!(reused < stored && notes.len() == 1 && notes[0].contains(&expected), "{stderr}");
    assert!(!stderr.contains("--drop-unplanned"), "demsweep tune has no such option: {stderr}");
}

#[test]
fn bad_tune_files_give_every_problem_and_write_nothing() {
    let dir = runner_common::scratch("tune_bad");
    let bad = TUNE
        .replace("[levers]\n", "colour = \"red\"\n[levers]\n\"material.restitutio\" = [0.1, 0.2]\n")
        .replace("linear = [0.2, 0.8]", "linear = [0.2, 1.8]")
        .replace("{ log = [5e-6, 2.5e-5] }", "{ log = [-1.0, 2.5e-5] }")
        .replace("pile_height = 0.25", "pile_height = 0.25\npile_heigth = 0.1\npacking_fraction = -0.1")
        .replace("seeds = 2\n", "seeds = 1\n")
        .replace("[search]\n", "[search]\nobjective = \"speed\"\n");
    let file = write_tune(&dir, &bad);
    let out = dir.join("out");
    for command in [&["check"][..], &["plan"], &["tune"]] {
        let mut args: Vec<&str> = command.to_vec();
        args.push(file.to_str().unwrap());
        if command[0] == "tune" {
            args.extend(["--out", out.to_str().unwrap()]);
        }
        let output = demsweep(&args);
        assert_eq!(output.status.code(), Some(2), "{:?}: {}", command, text(&output.stderr));
        let stderr = text(&output.stderr);
        let name = file.display().to_string();
        for expected in [
            format!("{name}:14:1: scene.colour: unknown field `colour`"),
            format!("{name}:16:1: levers.\"material.restitutio\": unknown field `restitutio`"),
            format!("{name}:17:1: levers.\"material.restitution\": value 1.8: "),
            format!("{name}:18:1: levers.\"integrator.time_step\": log: the ends must be > 0"),
            format!("{name}:22:1: keep.pile_heigth: unknown pile metric"),
            format!("{name}:23:1: keep.packing_fraction: the tolerance must be > 0, got -0.1"),
            format!("{name}:26:1: search.objective: unknown variant `speed`"),
            format!("{name}:27:1: search.seeds: must be at least 2"),
        ] {
            assert!(stderr.contains(&expected), "missing `{expected}` in:\n{stderr}");
        }
        assert!(stderr.contains("nothing was run"), "{stderr}");
    }
    assert!(!out.exists(), "a bad tune file writes nothing");
}

#[test]
fn check_names_the_file_line_and_key_of_the_references_predicted_warnings() {
    let dir = runner_common::scratch("tune_reference_warnings");
    let stage = "[[scene.stages]]\nname = \"fill\"\nuntil.time = 0.1\nintegrator.time_step = 2e-4\n\n[levers]\n";
    let tune = TUNE.replace("time_step = 7e-6", "time_step = 1e-4").replace("[levers]\n", stage);
    let file = write_tune(&dir, &tune);
    let check = demsweep(&["check", file.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stderr));
    let stderr = text(&check.stderr);
    let line = |written: &str| tune.lines().position(|l| l == written).unwrap() + 1;
    let name = file.display().to_string();
    for expected in [
        format!(
            "{name}:{}:12: scene.integrator.time_step: value 0.0001: predicted: ",
            line("integrator.time_step = 1e-4")
        ),
        format!(
            "{name}:{}:12: scene.stages.fill.integrator.time_step: value 0.0002: predicted in stage \"fill\": ",
            line("integrator.time_step = 2e-4")
        ),
    ] {
        assert!(stderr.contains(&format!("warning: {expected}")), "missing `{expected}` in:\n{stderr}");
    }
}

#[test]
fn a_tolerance_the_reference_cannot_decide_stops_after_the_reference_with_its_own_exit_status() {
    let dir = runner_common::scratch("tune_undecidable");
    let file = write_tune(&dir, &TUNE.replace("pile_height = 0.25", "pile_height = 1e-6"));
    let out = dir.join("out");
    let run = tune(&file, &out, &["--jobs", "2"]);
    assert_eq!(run.status.code(), Some(3), "{}", text(&run.stderr));
    let stdout = text(&run.stdout);
    let said = stdout.lines().find(|l| l.starts_with("Cannot decide")).unwrap_or_else(|| panic!("{stdout}"));
    assert!(said.contains("pile_height") && said.contains("smallest decidable tolerance"), "{said}");
    assert!(stdout.contains("4 runs (4 made now"), "only the 4 reference runs ran: {stdout}");
}

#[test]
fn a_tune_without_a_time_step_lever_changes_no_time_step_key() {
    // The time step is fixed at 7e-6 s; the levers are damping only.
    let dir = runner_common::scratch("tune_contract");
    let levers = "\"material.restitution\" = { linear = [0.2, 0.8] }\n\"damping.local\" = { linear = [0.0, 0.3] }";
    let file = write_tune(
        &dir,
        &TUNE.replace(
            "\"material.restitution\" = { linear = [0.2, 0.8] }\n\"integrator.time_step\" = { log = [5e-6, 2.5e-5] }",
            levers,
        ),
    );
    let plan = demsweep(&["plan", file.to_str().unwrap()]);
    let planned = text(&plan.stdout);
    assert_eq!(plan.status.code(), Some(0), "{}", text(&plan.stderr));
    assert!(planned.contains("  local damping 0.2") && !planned.contains("time step at"), "{planned}");
    let out = dir.join("out");
    tuned(&file, &out, &["--jobs", "2"]);
    let summary = std::fs::read_to_string(out.join("tiny_tune_summary.csv")).unwrap();
    let mut lines = summary.lines();
    let column = lines.next().unwrap().split(',').position(|c| c == "time_step").expect("a time_step column");
    let steps: Vec<f64> = lines.skip(1).map(|l| l.split(',').nth(column).unwrap().parse().unwrap()).collect();
    assert!(steps.len() > 10 && steps.iter().all(|&dt| dt == 7e-6), "every run at the fixed step: {steps:?}");
    if let Ok(change) = std::fs::read_to_string(out.join("tiny_tune_scene_change.toml")) {
        let keys: Vec<&str> = change.lines().filter(|l| !l.starts_with('#') && l.contains(" = ")).collect();
        assert!(
            keys.iter().all(|l| l.starts_with("material.restitution") || l.starts_with("damping.local")),
            "{change}"
        );
    }
}

#[test]
fn a_wall_time_tune_states_the_same_cost_when_rerun() {
    // Restitution and time step keep the reference's configuration: its wall time per particle-step
    // prices every run, so the stated cost is the particle-steps' and does not follow the load.
    let dir = runner_common::scratch("tune_wall_time");
    let file = write_tune(&dir, &TUNE.replace("[search]\n", "[search]\nobjective = \"wall_time\"\n"));
    let sheets: Vec<String> = ["first", "second"]
        .iter()
        .map(|name| {
            let run = tuned(&file, &dir.join(name), &["--jobs", "2"]);
            paragraph(&text(&run.stdout))
        })
        .collect();
    let cost = |sheet: &str| {
        let line = sheet.lines().find(|l| l.starts_with("Cost (wall_time")).unwrap_or_else(|| panic!("{sheet}"));
        line.split(" a speedup").next().unwrap().to_string()
    };
    assert_eq!(cost(&sheets[0]), cost(&sheets[1]), "{}\n---\n{}", sheets[0], sheets[1]);
    assert!(sheets[0].contains("ns per particle-step"), "{}", sheets[0]);
}

#[test]
fn tune_refuses_to_replace_a_users_best_toml_and_its_other_files() {
    let dir = runner_common::scratch("tune_users_files");
    let file = write_tune(&dir, TUNE);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let mine = [
        ("tiny_tune_best.toml", "# my best settings\nname = \"mine\"\n"),
        ("tiny_tune_scene_change.toml", "[scene]\n"),
        ("tiny_tune_recommendation.txt", "my notes\n"),
        ("tiny_tune_tune.json", "{\"mine\": true}\n"),
        ("tiny_tune_candidates.csv", "sample,comment\r\nA1,looks fine\r\n"),
    ];
    for (name, text) in mine {
        std::fs::write(out.join(name), text).unwrap();
    }
    let refused = tune(&file, &out, &[]);
    let said = text(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{said}");
    assert!(said.contains("refused: exists and was not written by demsweep"), "{said}");
    assert!(!out.join("tiny_tune.h5").exists(), "refused before any run");
    for (name, text) in mine {
        assert_eq!(std::fs::read_to_string(out.join(name)).unwrap(), text, "{name} kept");
    }
    // Each refused alone, named.
    for (name, _) in mine {
        let others: Vec<&str> = mine.iter().map(|(n, _)| *n).filter(|n| n != &name).collect();
        let moved = dir.join("moved");
        std::fs::create_dir_all(&moved).unwrap();
        others.iter().for_each(|n| std::fs::rename(out.join(n), moved.join(n)).unwrap());
        let refused = tune(&file, &out, &[]);
        assert!(text(&refused.stderr).contains(&format!("{name}: refused")), "{name}: {}", text(&refused.stderr));
        others.iter().for_each(|n| std::fs::rename(moved.join(n), out.join(n)).unwrap());
    }
    tuned(&file, &out, &["--force"]);
    assert_ne!(std::fs::read_to_string(out.join("tiny_tune_best.toml")).unwrap(), mine[0].1, "--force replaces it");
    tuned(&file, &out, &["--resume"]);
}

#[test]
fn check_and_plan_name_the_spend_a_tune_needs() {
    // 2 seeds a candidate and a verification round of 3: 5.5 reference depositions priced with the
    // margin. The reference's 4 runs leave 16 of 20: five candidates. With 18 reference runs the 2
    // left pay for none, even cut (at 0.36 of the reference's cost, below what a setting plausibly
    // settles in): the line names the max_spend (18 + 5.5) or reference_seeds (20 - 5.5) that would.
    let dir = runner_common::scratch("tune_spend_plan");
    let file = write_tune(&dir, TUNE);
    for command in ["check", "plan"] {
        let out = demsweep(&[command, file.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let said = text(&out.stdout);
        assert!(said.contains("the reference's 4 runs take 4 of max_spend = 20"), "{said}");
        assert!(said.contains("the 16 left pay for 5 candidate(s)"), "{said}");
        assert!(!said.contains("needs max_spend"), "{said}");
    }
    let file = write_tune(&dir, &TUNE.replace("reference_seeds = 4", "reference_seeds = 18"));
    for command in ["check", "plan"] {
        let out = demsweep(&[command, file.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let said = text(&out.stdout);
        assert!(said.contains("the 2 left pay for 0 candidate(s)") && !said.contains("cut at"), "{said}");
        assert!(said.contains("needs max_spend = 23.5 or reference_seeds = 14"), "{said}");
    }
}

/// Whether 30 disks of 1 cm fit the tiny tune's box, narrowed to 5.2 cm, on placement seed `seed`.
fn tight_box_placeable(seed: u64) -> bool {
    let mut scene = demsweep::physics::config::SceneConfig::default();
    (scene.particles.count, scene.particles.radius) = (30, 0.005);
    (scene.domain.width, scene.domain.height) = (0.1, 0.052);
    scene.placement.seed = seed;
    demsweep::physics::placement::generate(&scene).is_ok()
}

#[test]
fn a_seed_the_references_disks_cannot_be_placed_on_is_stepped_over() {
    // Near its jamming limit, random placement fits 30 disks in the narrowed box on most seeds, not
    // on all: such a seed is no deposition of the reference, and no run is made on it (before, the
    // verification runs on it failed and took their candidates with them).
    let dir = runner_common::scratch("tune_unplaceable");
    let narrowed = TUNE
        .replace("domain.height = 0.15", "domain.height = 0.052\nplacement.seed = 20")
        .replace("verify_seeds = 3", "verify_seeds = 6");
    let file = write_tune(&dir, &narrowed);
    let out = dir.join("out");
    let said = text(&tuned(&file, &out, &["--jobs", "2"]).stdout);
    let table = summary::read(&out.join("tiny_tune.h5")).unwrap();
    let column = |name: &str| &table.column(name).unwrap().data;
    let seeds: Vec<u64> = (0..table.len()).map(|row| column("placement.seed").number(row).unwrap() as u64).collect();
    assert!(seeds.iter().all(|&seed| tight_box_placeable(seed)), "runs only where the disks fit: {seeds:?}");
    assert!((0..table.len()).all(|row| column("status").text(row) != "error"), "{said}");
    let line = said.split("No run was made on seed").nth(1).expect("the sheet names the seeds stepped over");
    let named: Vec<u64> = line
        .trim_start_matches('s')
        .split(':')
        .next()
        .unwrap()
        .split(", ")
        .map(|s| s.trim().parse().unwrap())
        .collect();
    let last = *seeds.iter().max().unwrap();
    let unplaceable: Vec<u64> =
        (20..last).filter(|&seed| !tight_box_placeable(seed) && !seeds.contains(&seed)).collect();
    assert!(!named.is_empty() && named.iter().all(|&seed| !tight_box_placeable(seed)), "{named:?}\n{said}");
    assert!(named.iter().all(|seed| unplaceable.contains(seed)), "{named:?} among {unplaceable:?}");
    assert!(
        said.starts_with("Recommendation for tiny_tune") || said.contains("\nRecommendation for tiny_tune"),
        "{said}"
    );
    // The answer's study runs on its verification seeds: none stepped over.
    let best: toml::Table = std::fs::read_to_string(out.join("tiny_tune_best.toml")).unwrap().parse().unwrap();
    let sweep = best["sweep"].as_table().unwrap();
    let study_seeds: Vec<u64> = match sweep.get("placement.seed") {
        Some(list) => list.as_array().unwrap().iter().map(|s| s.as_integer().unwrap() as u64).collect(),
        None => {
            let first = best["scene"]["placement"]["seed"].as_integer().unwrap() as u64;
            (first..first + sweep["replicates"].as_integer().unwrap() as u64).collect()
        }
    };
    assert!(study_seeds.iter().all(|&seed| tight_box_placeable(seed)), "{study_seeds:?}");
}
