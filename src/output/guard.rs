//! Output-path guards: every command that writes output checks its paths here, so that nothing is
//! deleted or overwritten that demsweep did not make, and never one of its own inputs.
//!
//! - A file written ([`create_file`]) is refused when it is a symbolic link, a folder, one of the
//!   command's inputs, or a results file (HDF5); it is opened without following a link.
//! - A folder replaced as a whole (an export, [`ReplacedFolder`]) is refused when it is `/`, `.`,
//!   `..`, a home folder, the working folder or above it, or holds an input; `--force` replaces only
//!   a folder that holds demsweep's marker of the same kind, and an existing `<out>.partial` is
//!   removed only when it holds that marker too.

use std::fmt;
use std::fs::{File, OpenOptions};
use std::io::Read;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};

/// The first bytes of every HDF5 file (a results file).
const HDF5_SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// Why an output path is refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// The path is a symbolic link (never followed).
    Symlink,
    /// The path is one of the command's inputs.
    IsInput,
    /// The folder holds this input.
    ContainsInput(PathBuf),
    /// The path is a results file (HDF5).
    ResultsFile,
    /// A file was expected, the path is a folder (or the other way round).
    WrongKind(&'static str),
    /// `/`, `.`, `..`, a home folder, or the working folder or one above it.
    Protected(&'static str),
    /// The path exists and `--force` was not given.
    Exists,
    /// The folder exists but demsweep did not make it (it lacks the marker).
    NotOurs(&'static str),
    /// `--force` replaces a results file, and this is none (no HDF5 signature).
    NotResults,
    /// The path could not be examined or prepared.
    Io(String),
}

/// An output path refused, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GuardError {
    /// The refused path.
    pub path: PathBuf,
    /// Why.
    pub refusal: Refusal,
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Symlink => write!(f, "refused: is a symbolic link (demsweep does not write through links)"),
            Self::IsInput => write!(f, "refused: is an input of this command; choose another output path"),
            Self::ContainsInput(input) => {
                write!(f, "refused: holds the input {}; choose another output path", input.display())
            }
            Self::ResultsFile => write!(f, "refused: is a results file (HDF5), which this command never overwrites"),
            Self::WrongKind(expected) => write!(f, "refused: exists and is not {expected}"),
            Self::Protected(what) => write!(f, "refused: is {what}; choose a new folder for the output"),
            Self::Exists => write!(f, "already exists: pass --force to replace it, or choose another --out"),
            Self::NotOurs(kind) => write!(
                f,
                "refused: exists but was not written by demsweep {kind} (no {} marker in it): remove it \
                 yourself or choose another path",
                marker_name(kind)
            ),
            Self::NotResults => write!(
                f,
                "refused: --force replaces only a results file, and this is not one (no HDF5 signature): remove it \
                 yourself or choose another --out"
            ),
            Self::Io(reason) => write!(f, "{reason}"),
        }
    }
}

impl GuardError {
    /// The reason without the path (for errors that name the path themselves).
    pub fn refusal_text(&self) -> String {
        self.refusal.to_string()
    }
}

impl fmt::Display for GuardError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.refusal)
    }
}

impl std::error::Error for GuardError {}

fn refuse(path: &Path, refusal: Refusal) -> GuardError {
    GuardError { path: path.to_path_buf(), refusal }
}

/// The marker file demsweep writes into a folder of output `kind` (e.g. `.demsweep-export`).
pub fn marker_name(kind: &str) -> String {
    format!(".demsweep-{kind}")
}

/// Checks that `path` may be written as a file: not a link, folder, input or results file.
pub fn check_file(path: &Path, inputs: &[&Path]) -> Result<(), GuardError> {
    let Ok(meta) = std::fs::symlink_metadata(path) else { return Ok(()) };
    if meta.file_type().is_symlink() {
        return Err(refuse(path, Refusal::Symlink));
    }
    if !meta.is_file() {
        return Err(refuse(path, Refusal::WrongKind("a file")));
    }
    if inputs.iter().any(|input| same_file(path, input)) {
        return Err(refuse(path, Refusal::IsInput));
    }
    if is_hdf5(path) {
        return Err(refuse(path, Refusal::ResultsFile));
    }
    Ok(())
}

/// Checks that the existing `path` may be replaced by a results file (`--force`): a results file
/// (HDF5), no link, folder nor input.
pub fn check_results_replaceable(path: &Path, inputs: &[&Path]) -> Result<(), GuardError> {
    match check_file(path, inputs) {
        Err(GuardError { refusal: Refusal::ResultsFile, .. }) => Ok(()),
        Err(other) => Err(other),
        Ok(()) if !exists(path) => Ok(()),
        Ok(()) => Err(refuse(path, Refusal::NotResults)),
    }
}

/// Creates (or truncates) the file `path` after [`check_file`], without following a link.
pub fn create_file(path: &Path, inputs: &[&Path]) -> Result<File, GuardError> {
    check_file(path, inputs)?;
    open_no_follow(path, true).map_err(|e| refuse(path, Refusal::Io(format!("cannot create: {e}"))))
}

/// Writes `bytes` to the file `path` through [`create_file`].
pub fn write(path: &Path, bytes: &[u8], inputs: &[&Path]) -> Result<(), GuardError> {
    let mut file = create_file(path, inputs)?;
    std::io::Write::write_all(&mut file, bytes).map_err(|e| refuse(path, Refusal::Io(format!("cannot write: {e}"))))
}

/// Opens `path` for reading and writing, created if missing and never truncated, without following
/// a symbolic link at it (a link is an error).
pub fn open_no_follow(path: &Path, truncate: bool) -> std::io::Result<File> {
    OpenOptions::new().read(true).write(true).create(true).truncate(truncate).custom_flags(libc::O_NOFOLLOW).open(path)
}

/// Refuses a symbolic link at `path` (a missing path is fine).
pub fn refuse_symlink(path: &Path) -> Result<(), GuardError> {
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_symlink() => Err(refuse(path, Refusal::Symlink)),
        _ => Ok(()),
    }
}

/// Whether the file at `path` starts with the HDF5 signature.
pub fn is_hdf5(path: &Path) -> bool {
    let mut start = [0u8; 8];
    File::open(path).and_then(|mut f| f.read_exact(&mut start)).is_ok() && &start == HDF5_SIGNATURE
}

/// Whether `a` and `b` name the same existing file (hard links included).
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// A folder being written under `<out>.partial` to replace `<out>` when complete.
#[derive(Debug)]
pub struct ReplacedFolder {
    out: PathBuf,
    partial: PathBuf,
    kind: &'static str,
}

impl ReplacedFolder {
    /// Checks `out` (see the module) and prepares `<out>.partial` with the marker of `kind` in it.
    pub fn prepare(out: &Path, kind: &'static str, inputs: &[&Path], force: bool) -> Result<Self, GuardError> {
        let Some(name) = out.file_name() else { return Err(refuse(out, Refusal::Protected("`/`, `.` or `..`"))) };
        let mut partial_name = name.to_os_string();
        partial_name.push(".partial");
        let partial = out.with_file_name(partial_name);
        check_folder_place(out, inputs)?;
        if exists(out) {
            if !force {
                return Err(refuse(out, Refusal::Exists));
            }
            check_ours(out, kind)?;
        }
        if exists(&partial) {
            check_ours(&partial, kind)?;
            std::fs::remove_dir_all(&partial).map_err(|e| {
                refuse(&partial, Refusal::Io(format!("cannot remove this earlier partial output: {e}")))
            })?;
        }
        let io = |e: std::io::Error| refuse(&partial, Refusal::Io(format!("cannot create: {e}")));
        std::fs::create_dir_all(&partial).map_err(io)?;
        let marker = partial.join(marker_name(kind));
        std::fs::write(&marker, b"written by demsweep; --force may replace this folder\n").map_err(io)?;
        Ok(Self { out: out.to_path_buf(), partial, kind })
    }

    /// The folder to write into.
    pub fn partial(&self) -> &Path {
        &self.partial
    }

    /// Replaces `<out>` (checked again: still demsweep's) by the completed partial folder.
    pub fn finish(self) -> Result<(), GuardError> {
        if exists(&self.out) {
            check_ours(&self.out, self.kind)?;
            std::fs::remove_dir_all(&self.out)
                .map_err(|e| refuse(&self.out, Refusal::Io(format!("cannot replace: {e}"))))?;
        }
        std::fs::rename(&self.partial, &self.out)
            .map_err(|e| refuse(&self.out, Refusal::Io(format!("cannot rename {} to it: {e}", self.partial.display()))))
    }

    /// Removes the partial folder after a failure.
    pub fn abandon(self) {
        let _ = std::fs::remove_dir_all(&self.partial);
    }
}

/// Whether anything (a link included) is at `path`.
fn exists(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok()
}

/// Refuses an output folder that is `/`, a home folder, the working folder or above it, or holds an input.
fn check_folder_place(out: &Path, inputs: &[&Path]) -> Result<(), GuardError> {
    refuse_symlink(out)?;
    let Some(place) = resolved(out) else { return Ok(()) };
    if place.parent().is_none() {
        return Err(refuse(out, Refusal::Protected("the root folder")));
    }
    let home = std::env::var_os("HOME").and_then(|h| std::fs::canonicalize(h).ok());
    if home.is_some_and(|home| home == place) {
        return Err(refuse(out, Refusal::Protected("a home folder")));
    }
    if std::env::current_dir().ok().and_then(|d| std::fs::canonicalize(d).ok()).is_some_and(|d| d.starts_with(&place)) {
        return Err(refuse(out, Refusal::Protected("the working folder or a folder above it")));
    }
    for input in inputs {
        if std::fs::canonicalize(input).is_ok_and(|input| input.starts_with(&place)) {
            return Err(refuse(out, Refusal::ContainsInput(input.to_path_buf())));
        }
    }
    Ok(())
}

/// `path` with its parent folder resolved (the path itself may not exist yet); `None` when the
/// parent does not exist either.
fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(place) = std::fs::canonicalize(path) {
        return Some(place);
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    Some(std::fs::canonicalize(parent).ok()?.join(path.file_name()?))
}

/// Refuses a folder that is a link, not a folder, or lacks the marker of `kind`.
fn check_ours(folder: &Path, kind: &'static str) -> Result<(), GuardError> {
    let meta = std::fs::symlink_metadata(folder).map_err(|e| refuse(folder, Refusal::Io(e.to_string())))?;
    if meta.file_type().is_symlink() {
        return Err(refuse(folder, Refusal::Symlink));
    }
    if !meta.is_dir() {
        return Err(refuse(folder, Refusal::WrongKind("a folder")));
    }
    match std::fs::symlink_metadata(folder.join(marker_name(kind))) {
        Ok(marker) if marker.is_file() => Ok(()),
        _ => Err(refuse(folder, Refusal::NotOurs(kind))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("demsweep-guard-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn files_refuse_links_inputs_and_results_files() {
        let dir = temp("files");
        let input = dir.join("in.csv");
        std::fs::write(&input, "x").unwrap();
        let results = dir.join("r.h5");
        std::fs::write(&results, HDF5_SIGNATURE).unwrap();
        std::os::unix::fs::symlink(&input, dir.join("link.csv")).unwrap();
        assert_eq!(check_file(&input, &[&input]).unwrap_err().refusal, Refusal::IsInput);
        assert_eq!(check_file(&results, &[]).unwrap_err().refusal, Refusal::ResultsFile);
        assert_eq!(create_file(&dir.join("link.csv"), &[]).unwrap_err().refusal, Refusal::Symlink);
        assert_eq!(check_file(&dir, &[]).unwrap_err().refusal, Refusal::WrongKind("a file"));
        assert!(create_file(&dir.join("new.csv"), &[&input]).is_ok());
        assert_eq!(std::fs::read(&input).unwrap(), b"x");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_is_replaced_only_when_it_holds_the_marker() {
        let dir = temp("folders");
        let out = dir.join("out");
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join("mine.txt"), "keep").unwrap();
        assert_eq!(ReplacedFolder::prepare(&out, "export", &[], false).unwrap_err().refusal, Refusal::Exists);
        assert_eq!(ReplacedFolder::prepare(&out, "export", &[], true).unwrap_err().refusal, Refusal::NotOurs("export"));
        std::fs::remove_dir_all(&out).unwrap();
        let first = ReplacedFolder::prepare(&out, "export", &[], false).unwrap();
        first.finish().unwrap();
        assert!(out.join(".demsweep-export").is_file());
        let second = ReplacedFolder::prepare(&out, "export", &[], true).unwrap();
        second.finish().unwrap();
        assert_eq!(ReplacedFolder::prepare(Path::new("/"), "export", &[], true).unwrap_err().path, Path::new("/"));
        let input = out.join("in.h5");
        std::fs::write(&input, "x").unwrap();
        let refused = ReplacedFolder::prepare(&out, "export", &[&input], true).unwrap_err();
        assert_eq!(refused.refusal, Refusal::ContainsInput(input.clone()));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
