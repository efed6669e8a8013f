//! Results-writer benchmark: writes synthetic run records of realistic size into a results file the way
//! the runner does (batched in-place commits) and reports commit times, total writer time and file
//! size against the raw data size.
//!
//! Usage: `cargo run --release --example writer_bench -- [RUNS] [BATCH] [OUT_DIR] [SHARDS]`
//! (defaults: 10000 runs, 50 runs per commit, a temporary directory, one file). Each run has 1 500-sample
//! histories and a 300-disk final state. With SHARDS = N > 1 the runs go round-robin into the shard
//! files `bench.shard-K-of-N.h5` instead (input for measuring `demsweep merge`); the report is then
//! about all of them together.

use std::time::Instant;

use demsweep::output::header::utc_now;
use demsweep::output::row::SummaryRow;
use demsweep::output::{FileHeader, ResultSink, ResultsWriter, RunResult, ShardInfo, ShardSpec};
use demsweep::physics::SceneConfig;
use demsweep::physics::record::{History, RunRecord, RunStatus, Snapshot};
use demsweep::physics::stability::StabilityReport;
use demsweep::stats::points;
use demsweep::study::{OutputOptions, ParamValue};

const SAMPLES: usize = 1500;
const DISKS: usize = 300;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let runs: usize = args.get(1).map_or(10_000, |a| a.parse().expect("RUNS must be a number"));
    let batch: usize = args.get(2).map_or(50, |a| a.parse().expect("BATCH must be a number"));
    let dir = args.get(3).map_or_else(|| std::env::temp_dir().join("demsweep_writer_bench"), Into::into);
    let shards: usize = args.get(4).map_or(1, |a| a.parse().expect("SHARDS must be a number"));
    std::fs::create_dir_all(&dir).expect("create output directory");
    let output = OutputOptions { histories: true, final_states: true, frames: false };
    let files: Vec<(std::path::PathBuf, FileHeader)> = (1..=shards)
        .map(|k| {
            let spec = ShardSpec { index: k, count: shards };
            let shard = (shards > 1).then(|| ShardInfo { spec, runs: (k - 1..runs).step_by(shards).collect() });
            let name = if shards > 1 { format!("bench.shard-{k}-of-{shards}.h5") } else { "bench.h5".into() };
            let header = FileHeader {
                study_name: "bench".into(),
                study_text: "# synthetic".into(),
                fingerprint: "bench".into(),
                demsweep_version: env!("CARGO_PKG_VERSION").into(),
                created: utc_now(),
                planned_runs: runs,
                shard,
            };
            (dir.join(name), header)
        })
        .collect();
    let scene = SceneConfig::default();
    let started = Instant::now();
    let mut writers: Vec<ResultsWriter> = files
        .iter()
        .map(|(path, header)| {
            let _ = std::fs::remove_file(path);
            ResultsWriter::create(path, header, output.clone()).expect("create results file")
        })
        .collect();
    let mut rows: Vec<Vec<SummaryRow>> = vec![Vec::new(); shards];
    let mut commit_ms: Vec<f64> = Vec::new();
    let mut stage_s = 0.0;
    for index in 0..runs {
        let result = synthetic_run(index, &scene);
        let writer = &mut writers[index % shards];
        let t = Instant::now();
        writer.stage(&result).expect("stage run");
        rows[index % shards].push(result.row);
        stage_s += t.elapsed().as_secs_f64();
        if writer.pending() >= batch || index + shards >= runs {
            let t = Instant::now();
            writer.commit().expect("commit");
            commit_ms.push(t.elapsed().as_secs_f64() * 1e3);
            if commit_ms.len().is_multiple_of(20) {
                println!("{:>6} runs committed, last commit {:.1} ms", index + 1, commit_ms.last().unwrap());
            }
        }
    }
    let t = Instant::now();
    for ((writer, rows), (path, _)) in writers.iter_mut().zip(&rows).zip(&files) {
        let tables = points::tables(rows);
        writer.finish(&tables).expect("finish");
        demsweep::output::write_csv_files(path, &tables).expect("CSV tables");
    }
    let finish_s = t.elapsed().as_secs_f64();
    let total_s = started.elapsed().as_secs_f64();
    let paths: Vec<&std::path::Path> = files.iter().map(|(p, _)| p.as_path()).collect();
    report(runs, batch, &commit_ms, stage_s, finish_s, total_s, &paths);
}

fn report(
    runs: usize,
    batch: usize,
    commit_ms: &[f64],
    stage_s: f64,
    finish_s: f64,
    total_s: f64,
    paths: &[&std::path::Path],
) {
    let raw = runs * (SAMPLES * (10 * 8 + 4) + DISKS * 7 * 8);
    let size: u64 = paths.iter().map(|p| std::fs::metadata(p).map_or(0, |m| m.len())).sum();
    let quarter = commit_ms.len() / 4;
    let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len().max(1) as f64;
    println!("runs {runs}, {batch} runs per commit, {} commits", commit_ms.len());
    println!(
        "commit ms: first quarter mean {:.1}, last quarter mean {:.1}, max {:.1}",
        mean(&commit_ms[..quarter.max(1)]),
        mean(&commit_ms[commit_ms.len() - quarter.max(1)..]),
        commit_ms.iter().cloned().fold(0.0, f64::max)
    );
    let commits_s = commit_ms.iter().sum::<f64>() / 1e3;
    println!("staging {stage_s:.2} s, commits {commits_s:.2} s, summary {finish_s:.2} s, total writer {total_s:.2} s");
    println!("writer time per run {:.2} ms", total_s * 1e3 / runs as f64);
    println!(
        "file {:.1} MB for {:.1} MB raw data ({:.2}x)",
        size as f64 / 1e6,
        raw as f64 / 1e6,
        size as f64 / raw as f64
    );
}

/// A deterministic run record shaped like a deposition: decaying kinetic energy, a settling pile.
fn synthetic_run(index: usize, scene: &SceneConfig) -> RunResult {
    let mut noise = Lcg(index as u64 * 7919 + 1);
    let time: Vec<f64> = (0..SAMPLES).map(|k| k as f64 * 1e-3).collect();
    let decay = |scale: f64, noise: &mut Lcg| -> Vec<f64> {
        time.iter().map(|t| scale * (-t * 4.0).exp() * (1.0 + 0.05 * noise.next())).collect()
    };
    let kinetic_translational = decay(2.0, &mut noise);
    let kinetic_rotational = decay(0.3, &mut noise);
    let potential: Vec<f64> = time.iter().map(|t| 50.0 - 20.0 * (1.0 - (-t * 3.0).exp())).collect();
    let elastic = decay(0.01, &mut noise);
    let dissipated: Vec<f64> = potential.iter().map(|p| 50.0 - p).collect();
    let total: Vec<f64> = kinetic_translational.iter().zip(&potential).map(|(k, p)| k + p).collect();
    let mechanical: Vec<f64> = total.iter().zip(&elastic).map(|(t, e)| t + e).collect();
    let history = History {
        unbalanced_force_ratio: decay(1.0, &mut noise),
        max_overlap_ratio: decay(0.02, &mut noise),
        contacts: (0..SAMPLES).map(|k| (k * 600 / SAMPLES) as u32).collect(),
        time,
        kinetic_translational,
        kinetic_rotational,
        potential,
        elastic,
        numerical_damping_dissipated: vec![0.0; dissipated.len()],
        dissipated,
        total,
        mechanical,
    };
    let field = |noise: &mut Lcg, scale: f64| -> Vec<f64> { (0..DISKS).map(|_| scale * noise.next()).collect() };
    let final_state = Snapshot {
        time: 1.5,
        x: field(&mut noise, 0.4),
        y: field(&mut noise, 0.2),
        vx: field(&mut noise, 1e-4),
        vy: field(&mut noise, 1e-4),
        omega: field(&mut noise, 1e-3),
        angle: field(&mut noise, 6.0),
        r: vec![0.01; DISKS],
        contact_force: field(&mut noise, 5.0),
        ..Default::default()
    };
    let record = RunRecord {
        status: RunStatus::Settled,
        message: None,
        warnings: Vec::new(),
        settle_time: Some(0.9),
        steps: 150_000,
        time_step: 1e-5,
        simulated_time: 1.5,
        energy_balance_error: 1e-3,
        largest_overlap_ratio: 0.01,
        pile: Default::default(),
        stability: StabilityReport::default(),
        history,
        final_state,
        frames: Vec::new(),
        stage_ends: Vec::new(),
        pour: None,
    };
    let parameters = vec![
        ("material.beta".to_string(), ParamValue::Float(0.1 * (index % 10) as f64)),
        ("placement.seed".to_string(), ParamValue::Int(index as i64)),
    ];
    let id = format!("r{index:05}");
    let mut row = SummaryRow::finished(index, &id, &parameters, &record);
    row.wall_time = 3.0;
    RunResult { row, scene: scene.clone(), record: Some(record) }
}

/// A tiny deterministic generator of values in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
