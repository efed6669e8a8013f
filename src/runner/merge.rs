//! Merging results files: the shards of one study into the results file a one-machine run gives, or
//! the files of different studies into one file holding each run once (runs are matched by
//! identity, `crate::study::RunIdentity`).

use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

use crate::output::guard;
use crate::output::header::{FileHeader, utc_now};
use crate::output::lock::ResultsLock;
use crate::output::{OutputError, OutputReason, ResultsWriter, SummaryRow, reader, write_csv_files};
use crate::stats::points;
use crate::study::identity::fnv;
use crate::study::plan::run_id;
use crate::study::{OutputOptions, RunIdentity};

/// Data staged (decoded bytes) before a commit while merging: memory holds this, or one run if larger.
const BYTES_PER_COMMIT: usize = 16 << 20;

/// How to merge.
#[derive(Clone, Debug, Default)]
pub struct MergeOptions {
    /// Replace an existing merged file.
    pub force: bool,
    /// Merge runs made by different demsweep versions (else refused, naming them).
    pub accept_version: bool,
    /// The merged file's study name (`<name>.h5`); default the first file's study name.
    pub name: Option<String>,
}

/// What a merge produced.
#[derive(Clone, Debug, PartialEq)]
pub struct MergeReport {
    /// The merged HDF5 file.
    pub results: PathBuf,
    /// Its CSV summary.
    pub summary_csv: PathBuf,
    /// Its per-point CSV.
    pub points_csv: PathBuf,
    /// Number of runs merged.
    pub runs: usize,
    /// Number of shard files merged.
    pub shards: usize,
    /// Runs in the whole study.
    pub planned_runs: usize,
    /// Shards the study was split into.
    pub shard_count: usize,
    /// Shards missing, incomplete or holding runs that failed with an error: they must run again
    /// (empty when the merge is complete).
    pub problems: Vec<ShardProblem>,
}

/// A shard that must run again before the merge is complete.
#[derive(Clone, Debug, PartialEq)]
pub struct ShardProblem {
    /// Which shard (1-based).
    pub shard: usize,
    /// What is wrong, in words.
    pub reason: String,
}

impl MergeReport {
    /// The shards to run again (ascending, each once).
    pub fn shards_to_rerun(&self) -> Vec<usize> {
        let mut shards: Vec<usize> = self.problems.iter().map(|p| p.shard).collect();
        shards.dedup();
        shards
    }
}

/// One shard file, checked.
struct ShardFile {
    path: PathBuf,
    header: FileHeader,
    rows: Vec<SummaryRow>,
    /// Where each run's group is in the file, by run id.
    groups: HashMap<String, String>,
}

/// Merges the results files in `inputs` (files, or directories searched for `*.shard-K-of-N.h5`)
/// into `out_dir/<name>.h5` (the first study's name unless `options` gives one) and its CSV summary
/// and points.
///
/// Shards of one study merge into the file a one-machine run gives: refused, naming the files, when
/// they hold a run twice or are shards of the same study text whose input files or demsweep version
/// differ; missing shards, missing runs and runs that failed with an error do not stop it: it merges
/// what there is and lists them in [`MergeReport::problems`]. Files of different studies merge run
/// by run, each identity once, renumbered `r0000`, … in file order; refused for files written
/// before run identities, for files of different physics versions, and (unless
/// `options.accept_version`) for runs made by different demsweep versions.
/// An existing merged file is only replaced with `options.force`; the merged file is written under a
/// temporary name (`<name>.merging.h5`) and renamed when complete, holding the results file's lock.
pub fn merge(out_dir: &Path, inputs: &[PathBuf], options: &MergeOptions) -> Result<MergeReport, OutputError> {
    let (mut shards, unreadable) = read_shards(&shard_paths(inputs)?);
    let studies = match shards.is_empty() {
        true => true,
        false => !one_study(&shards)?,
    };
    let problems = match (studies, unreadable.first()) {
        (true, Some(file)) => return Err(file.error.clone()),
        (true, None) => combine(&mut shards, options.accept_version)?,
        (false, _) => check_complete(&shards, &unreadable)?,
    };
    let first = &shards[0].header;
    let name = match &options.name {
        Some(name) => crate::study::name::check_name(name)
            .map(|()| name.clone())
            .map_err(|reason| OutputError::at(out_dir, OutputReason::BadName(reason)))?,
        None => first.study_name.clone(),
    };
    std::fs::create_dir_all(out_dir).map_err(|e| OutputError::io(out_dir, e))?;
    let results = out_dir.join(format!("{name}.h5"));
    let _lock = ResultsLock::acquire(&results)?;
    if results.exists() && !options.force {
        return Err(OutputError::at(&results, OutputReason::Exists { resumable: false }));
    }
    let shard_files: Vec<&Path> = shards.iter().map(|s| s.path.as_path()).collect();
    guard::check_results_replaceable(&results, &shard_files).map_err(|e| OutputError::refused(&results, e))?;
    crate::output::check_companions(&results, options.force, false)?;
    let header = if studies {
        combined_header(&shards)
    } else {
        FileHeader { created: utc_now(), shard: None, ..first.clone() }
    };
    let header = FileHeader { study_name: name, ..header };
    // Written under a temporary name and renamed when complete, then its CSV files (checked above):
    // a killed merge leaves no partial file under the final name (and an existing one stays until
    // replaced).
    let partial = results.with_extension("merging.h5");
    // Copies keep every dataset of the shards; the options only matter for newly simulated runs.
    let mut writer = ResultsWriter::create(&partial, &header, OutputOptions::default())?;
    let (mut runs, mut staged, mut copied) = (0, 0, HashSet::new());
    for shard in &shards {
        let source = reader::open(&shard.path)?;
        for row in &shard.rows {
            let name = row.group_name();
            if !copied.insert(name.to_string()) {
                continue;
            }
            let group = shard
                .groups
                .get(name)
                .ok_or_else(|| OutputError::at(&shard.path, OutputReason::NoGroup(row.id.clone())))?;
            staged += writer.stage_copy((&source, &shard.path), group, (name, &row.made_by))?;
            if staged >= BYTES_PER_COMMIT {
                writer.commit()?;
                staged = 0;
            }
        }
        runs += shard.rows.len();
    }
    let rows: Vec<SummaryRow> = shards.iter().flat_map(|s| s.rows.iter().cloned()).collect();
    let tables = points::tables(&rows);
    writer.close(&tables)?;
    std::fs::rename(&partial, &results).map_err(|e| OutputError::io(&results, e))?;
    let (summary_csv, points_csv) = write_csv_files(&results, &tables)?;
    let shard_count = if studies { 0 } else { first.shard.as_ref().map_or(0, |s| s.spec.count) };
    Ok(MergeReport {
        results,
        summary_csv,
        points_csv,
        runs,
        shards: shards.len(),
        planned_runs: if studies { runs } else { first.planned_runs },
        shard_count,
        problems,
    })
}

/// The shard files named by `inputs`, directories expanded, sorted.
fn shard_paths(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, OutputError> {
    let mut paths = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let entries = std::fs::read_dir(input).map_err(|e| OutputError::io(input, e))?;
            let mut found: Vec<PathBuf> = entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.file_name().and_then(|n| n.to_str()).is_some_and(is_shard_file_name))
                .collect();
            if found.is_empty() {
                return Err(OutputError::at(input, OutputReason::NoShards { in_folder: true }));
            }
            paths.append(&mut found);
        } else {
            paths.push(input.clone());
        }
    }
    if paths.is_empty() {
        return Err(OutputError::at(Path::new("."), OutputReason::NoShards { in_folder: false }));
    }
    paths.sort();
    paths.dedup();
    Ok(paths)
}

fn is_shard_file_name(name: &str) -> bool {
    name.ends_with(".h5") && name.contains(".shard-") && name.contains("-of-")
}

/// A file given that cannot be read (cut short, damaged): a shard of the study is merged as missing.
struct Unreadable {
    path: PathBuf,
    error: OutputError,
}

/// The files that read, and those that do not (see [`Unreadable`]).
fn read_shards(paths: &[PathBuf]) -> (Vec<ShardFile>, Vec<Unreadable>) {
    let read = |path: &PathBuf| {
        let file = reader::open(path)?;
        let header = reader::header(&file, path)?;
        let runs = reader::committed_runs(&file, path)?;
        if !runs.damaged.is_empty() {
            return Err(OutputError::at(path, OutputReason::Damaged(runs.damaged)));
        }
        Ok(ShardFile { path: path.clone(), header, rows: runs.rows, groups: runs.groups })
    };
    let (mut shards, mut unreadable) = (Vec::new(), Vec::new());
    for path in paths {
        match read(path) {
            Ok(shard) => shards.push(shard),
            Err(error) => unreadable.push(Unreadable { path: path.clone(), error }),
        }
    }
    (shards, unreadable)
}

/// The shard `(K, N)` a file's name says it is (`<name>.shard-K-of-N.h5`).
fn shard_in_name(path: &Path) -> Option<(usize, usize)> {
    let name = path.file_name()?.to_str()?.strip_suffix(".h5")?;
    let (k, n) = name.rsplit_once(".shard-")?.1.split_once("-of-")?;
    Some((k.parse().ok()?, n.parse().ok()?))
}

fn describe(shard: &ShardFile) -> String {
    let spec = shard.header.shard.as_ref().map_or(String::new(), |s| format!("shard {}", s.spec));
    format!(
        "{} ({spec}, study `{}`, fingerprint {})",
        shard.path.display(),
        shard.header.study_name,
        shard.header.fingerprint
    )
}

/// Whether the files are shards of one study split one way (merged as shards), rather than whole
/// files of different studies (merged run by run). A shard merges only with the other shards of its
/// study: shards whose study text or fingerprint differ (the study edited between them, its input
/// files or the demsweep version changed) or that split it differently, and a shard given with a
/// file that is not one, are refused, naming both files and what differs.
fn one_study(shards: &[ShardFile]) -> Result<bool, OutputError> {
    let Some(first) = shards.iter().find(|s| s.header.shard.is_some()) else { return Ok(false) };
    let Some((other, why)) = shards.iter().find_map(|s| Some(s).zip(difference(first, s))) else { return Ok(true) };
    let (first, other_file) = (describe(first), describe(other));
    Err(OutputError::at(&other.path, OutputReason::DifferentStudies { why, first, other: other_file }))
}

/// A line of a study file as an error shows it: trimmed, control characters escaped, at most 120
/// characters.
fn shown(line: &str) -> String {
    let mut escaped = String::new();
    for c in line.trim().chars() {
        match c.is_control() {
            true => escaped.extend(c.escape_debug()),
            false => escaped.push(c),
        }
    }
    match escaped.char_indices().nth(120) {
        Some((at, _)) => format!("{}…", &escaped[..at]),
        None => escaped,
    }
}

/// What makes `other` not a shard of the same study and split as the shard `first`, in words.
fn difference(first: &ShardFile, other: &ShardFile) -> Option<String> {
    let (a, b) = (&first.header, &other.header);
    let count = |h: &FileHeader| h.shard.as_ref().map(|i| i.spec.count);
    if b.shard.is_none() {
        Some("the second is not a shard: a shard merges only with the other shards of its study".to_string())
    } else if a.study_text != b.study_text {
        Some(text_difference(&a.study_text, &b.study_text))
    } else if a.fingerprint != b.fingerprint && a.demsweep_version != b.demsweep_version {
        Some(format!("demsweep version {} and {}", a.demsweep_version, b.demsweep_version))
    } else if a.fingerprint != b.fingerprint {
        Some("the study's input files (placement.file, placement.contacts) changed between them".to_string())
    } else if count(a) != count(b) {
        Some("they split the study differently".to_string())
    } else {
        None
    }
}

/// The first line where two study texts differ: `the study was edited between them (line 7:
/// `run.duration = 0.2` and `run.duration = 0.15`)`.
fn text_difference(a: &str, b: &str) -> String {
    let (mut a_lines, mut b_lines) = (a.lines(), b.lines());
    let mut line = 1;
    loop {
        match (a_lines.next(), b_lines.next()) {
            (Some(x), Some(y)) if x == y => line += 1,
            (None, None) => return "the study was edited between them: its line ends differ".to_string(),
            (x, y) => {
                let show = |l: Option<&str>| l.map_or("(end of file)".to_string(), |l| format!("`{}`", shown(l)));
                return format!("the study was edited between them: line {line}: {} and {}", show(x), show(y));
            }
        }
    }
}

/// The demsweep version that made a run of `file`: recorded on the run, else the file's creator.
fn made_by<'a>(file: &'a ShardFile, row: &'a SummaryRow) -> &'a str {
    if row.made_by.is_empty() { &file.header.demsweep_version } else { &row.made_by }
}

/// Files of different studies: every run once (by identity), renumbered in file order. Refuses
/// files without run identities, files of different physics versions and, unless `accept_version`,
/// runs made by different demsweep versions (naming a run of each).
fn combine(files: &mut [ShardFile], accept_version: bool) -> Result<Vec<ShardProblem>, OutputError> {
    let mut physics: Option<(u32, &Path)> = None;
    let mut version: Option<(&ShardFile, &SummaryRow)> = None;
    for file in files.iter() {
        for row in &file.rows {
            match version {
                Some((first, run)) if !accept_version && made_by(first, run) != made_by(file, row) => {
                    let differs = OutputReason::DifferentVersions {
                        run: row.id.clone(),
                        version: made_by(file, row).to_string(),
                        first_run: run.id.clone(),
                        first_file: first.path.clone(),
                        first_version: made_by(first, run).to_string(),
                    };
                    return Err(OutputError::at(&file.path, differs));
                }
                None => version = Some((file, row)),
                _ => {}
            }
        }
        for row in &file.rows {
            let identity: RunIdentity = row
                .identity
                .parse()
                .map_err(|_| OutputError::at(&file.path, OutputReason::NoIdentity { run: row.id.clone() }))?;
            match physics {
                Some((version, other)) if version != identity.physics => {
                    let differs = OutputReason::DifferentPhysics {
                        version: identity.physics,
                        other: other.to_path_buf(),
                        other_version: version,
                    };
                    return Err(OutputError::at(&file.path, differs));
                }
                _ => physics = Some((identity.physics, &file.path)),
            }
        }
    }
    let mut seen = HashSet::new();
    for file in files.iter_mut() {
        file.rows.retain(|row| seen.insert(row.identity.clone()));
    }
    let total = seen.len();
    for (index, row) in files.iter_mut().flat_map(|f| f.rows.iter_mut()).enumerate() {
        (row.index, row.id) = (index, run_id(index, total));
    }
    Ok(Vec::new())
}

/// The header of a file merged from different studies: the first's name, every study's text.
fn combined_header(files: &[ShardFile]) -> FileHeader {
    let first = &files[0].header;
    let texts: Vec<String> = files
        .iter()
        .map(|f| {
            format!(
                "# --- study `{}` (fingerprint {}) ---\n{}",
                f.header.study_name, f.header.fingerprint, f.header.study_text
            )
        })
        .collect();
    let fingerprints: String = files.iter().map(|f| f.header.fingerprint.as_str()).collect();
    FileHeader {
        study_text: texts.join("\n"),
        fingerprint: format!("merged-{:016x}", fnv(fingerprints.bytes())),
        created: utc_now(),
        shard: None,
        ..first.clone()
    }
}

/// No run in two files (an error); the shards missing, unreadable, incomplete or with failed runs
/// (problems). A file that cannot be read is refused unless its name says it is a shard of this split.
fn check_complete(shards: &[ShardFile], unreadable: &[Unreadable]) -> Result<Vec<ShardProblem>, OutputError> {
    let mut owner: BTreeMap<usize, &Path> = BTreeMap::new();
    for shard in shards {
        for row in &shard.rows {
            if let Some(other) = owner.insert(row.index, &shard.path) {
                let overlap =
                    OutputReason::Overlap { other: other.to_path_buf(), run: row.id.clone(), index: row.index };
                return Err(OutputError::at(&shard.path, overlap));
            }
        }
    }
    let count = shards[0].header.shard.as_ref().map_or(0, |s| s.spec.count);
    let holds = |shard: &ShardFile, k: usize| shard.header.shard.as_ref().is_some_and(|i| i.spec.index == k);
    if let Some(file) = unreadable.iter().find(|u| {
        shard_in_name(&u.path).is_none_or(|(k, n)| n != count || k == 0 || k > n || shards.iter().any(|s| holds(s, k)))
    }) {
        return Err(file.error.clone());
    }
    let mut problems = Vec::new();
    for k in 1..=count {
        let problem = |reason: String| ShardProblem { shard: k, reason };
        let Some(shard) = shards.iter().find(|s| holds(s, k)) else {
            problems.push(problem(match unreadable.iter().find(|u| shard_in_name(&u.path) == Some((k, count))) {
                Some(file) => format!(
                    "shard {k}/{count} ({}): cannot be read ({}): run it again with --force in place of --resume \
                     (it starts afresh)",
                    file.path.display(),
                    file.error.reason
                ),
                None => format!("shard {k}/{count}: no file given"),
            }));
            continue;
        };
        let assigned = shard.header.shard.as_ref().map_or(&[][..], |s| &s.runs[..]);
        let missing: Vec<String> =
            assigned.iter().filter(|i| !owner.contains_key(i)).map(|i| format!("#{i}")).collect();
        if !missing.is_empty() {
            problems.push(problem(format!(
                "shard {k}/{count} ({}): {} of {} runs missing (plan indices {})",
                shard.path.display(),
                missing.len(),
                assigned.len(),
                missing.join(", ")
            )));
        }
        for row in shard.rows.iter().filter(|r| !r.is_finished()) {
            problems.push(problem(format!(
                "shard {k}/{count} ({}): run {} failed with an error: {}",
                shard.path.display(),
                row.id,
                row.message
            )));
        }
    }
    Ok(problems)
}
