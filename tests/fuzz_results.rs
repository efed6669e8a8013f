//! Damaged results files (fixed seeds): truncations and byte flips of a small results file go
//! through every reader — summary, points, report, plot, export, stored runs, histories, merge and
//! the runner's `--resume` — which must end with an error or a result (with its damage listed), never a
//! panic, an abort (which would end this test), a hang (a watchdog ends the test after a while) or a
//! file written outside the variant's own folder.

mod runner_common;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use demsweep::export::{self, ExportRequest};
use demsweep::output::guard::Existing;
use demsweep::output::{reader, stored};
use demsweep::plot::results::{PlotRequest, plot_results};
use demsweep::plot::run::ColourBy;
use demsweep::report::{ReportContext, write_report};
use demsweep::runner;

/// Variants of each kind.
const TRUNCATIONS: usize = 40;
const FLIPS: usize = 120;
/// The whole test's limit: a reader that hangs ends it.
const WATCHDOG: Duration = Duration::from_secs(240);

/// A small deterministic generator (xorshift64*), fixed seed.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) as usize % n.max(1)
    }
}

/// The variants of `bytes`: truncations at random lengths, then 1 to 8 random bytes flipped.
fn variants(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut out = Vec::new();
    for _ in 0..TRUNCATIONS {
        let length = rng.below(bytes.len());
        out.push((format!("truncated to {length} bytes"), bytes[..length].to_vec()));
    }
    for _ in 0..FLIPS {
        let mut damaged = bytes.to_vec();
        let flips: Vec<usize> = (0..1 + rng.below(8)).map(|_| rng.below(bytes.len())).collect();
        for &at in &flips {
            damaged[at] ^= 1 << rng.below(8);
        }
        out.push((format!("bits flipped at {flips:?}"), damaged));
    }
    out
}

/// Every reader on the results file `results` (its outputs under its folder); what happened.
fn read_everything(results: &Path, plan: &demsweep::study::Plan) -> Vec<String> {
    let folder = results.parent().unwrap();
    let mut outcomes = Vec::new();
    let mut note = |what: &str, ok: bool| outcomes.push(format!("{what}: {}", if ok { "ok" } else { "error" }));
    note("summary", demsweep::output::summary::read(results).is_ok());
    note("points", demsweep::stats::points::read(results).is_ok());
    if let Ok(file) = reader::open(results)
        && let Ok((rows, _damaged)) = reader::scan(&file, results)
    {
        for row in &rows {
            note("stored run", stored::read_run(&file, results, row).is_ok());
            note("history", demsweep::output::history::to_csv(results, &row.id, &mut Vec::new()).is_ok());
        }
    }
    note(
        "report",
        write_report(results, (Some(&folder.join("report.html")), Existing::Any), &ReportContext::default()).is_ok(),
    );
    let plot = PlotRequest {
        results: results.to_path_buf(),
        out_dir: Some(folder.join("plots")),
        run_ids: Vec::new(),
        all_runs: true,
        formats: vec![demsweep::plot::Format::Svg],
        colour_by: ColourBy::ContactForce,
        size: (400, 300),
        force: false,
    };
    note("plot", plot_results(&plot, &mut |_| {}).is_ok());
    for name in ["vtk", "csv"] {
        let request = ExportRequest {
            results: results.to_path_buf(),
            format: export::format(name).expect("a format of the table"),
            runs: Vec::new(),
            frames: true,
            out: folder.join(name),
            force: false,
        };
        note("export", export::export(&request).is_ok());
    }
    note("merge", runner::merge(&folder.join("merged"), &[results.to_path_buf()], &Default::default()).is_ok());
    let options = runner::RunOptions { resume: true, ..runner_common::options(folder, 1) };
    note("resume", runner::run_plan(plan, &options).is_ok());
    outcomes
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

#[test]
fn truncated_and_bit_flipped_results_files_give_errors_or_results_never_panics() {
    let done = std::sync::Arc::new(AtomicBool::new(false));
    let watched = done.clone();
    std::thread::spawn(move || {
        std::thread::sleep(WATCHDOG);
        if !watched.load(Ordering::SeqCst) {
            eprintln!("a reader hangs: the fuzz test did not end within {WATCHDOG:?}");
            std::process::exit(1);
        }
    });
    let dir = runner_common::scratch("fuzz");
    let plan = runner_common::sweep("fuzz", 3);
    let report = runner::run_plan(&plan, &runner_common::options(&dir.join("original"), 1)).unwrap();
    let bytes = std::fs::read(&report.results).unwrap();
    let mut panics: Vec<String> = Vec::new();
    let (mut readable, mut failed) = (0, 0);
    let all = variants(&bytes);
    for (k, (what, damaged)) in all.iter().enumerate() {
        let folder = dir.join(format!("v{k:03}"));
        std::fs::create_dir_all(&folder).unwrap();
        let results: PathBuf = folder.join("fuzz.h5");
        std::fs::write(&results, damaged).unwrap();
        match catch_unwind(AssertUnwindSafe(|| read_everything(&results, &plan))) {
            Ok(outcomes) if outcomes.iter().all(|o| o.ends_with("ok")) => readable += 1,
            Ok(_) => failed += 1,
            Err(_) => panics.push(format!("v{k:03}: {what}")),
        }
        let outside: Vec<String> = names(&dir).into_iter().filter(|n| !n.starts_with('v') && n != "original").collect();
        assert!(outside.is_empty(), "v{k:03} ({what}) wrote beside its folder: {outside:?}");
        let _ = std::fs::remove_dir_all(&folder);
    }
    done.store(true, Ordering::SeqCst);
    eprintln!("{} variants: {readable} read whole, {failed} with errors, {} panicked", all.len(), panics.len());
    assert!(panics.is_empty(), "{} of {} variants panicked:\n{}", panics.len(), all.len(), panics.join("\n"));
    assert!(failed > 0 && readable + failed == all.len(), "{readable} read whole, {failed} with errors");
}
