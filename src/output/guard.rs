//! Output-path guards: every command that writes output checks its paths here, so that nothing is
//! deleted or overwritten that demsweep did not make, and never one of its own inputs.
//!
//! - A file written ([`create_file`], [`write_with`]) is refused when it is a symbolic link, a folder,
//!   one of the command's inputs, or a results file (HDF5); it is opened without following a link.
//!   Where the command asks ([`Existing::Ours`]), an existing file is replaced only when demsweep
//!   wrote it ([`made_by_demsweep`]: its report pages, charts and CSV tables say so in their first
//!   bytes), any plain file only with `--force`.
//! - [`write_with`] writes a file whole or not at all: into a temporary file in the same folder,
//!   renamed onto the final name once complete, so that a full disk or a killed command never leaves
//!   a truncated file under that name.
//! - A folder replaced as a whole (an export, [`ReplacedFolder`]) is refused when it is `/`, `.`,
//!   `..`, a home folder, the working folder or above it, or holds an input; `--force` replaces only
//!   a folder that holds demsweep's marker of the same kind, and an existing `<out>.partial` is
//!   removed only when it holds that marker too.
//!
//! Paths are taken as written less trailing slashes and `.` parts ([`plain`]): `link/` is the link
//! `link`, refused as such, not the folder it points to.

use std::fmt;
use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};

/// The first bytes of every HDF5 file (a results file).
const HDF5_SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// The mark in the `<head>` of every report page demsweep writes.
pub const HTML_MARK: &str = "<meta name=\"generator\" content=\"demsweep\">";

/// The mark that starts every SVG chart file demsweep writes (an XML comment).
pub const SVG_MARK: &str = "<!-- made by demsweep -->\n";

/// The PNG text chunk (keyword, text) of every PNG chart demsweep writes.
pub const PNG_MARK: (&str, &str) = ("Software", "demsweep");

/// What an existing file at an output path may be, to be replaced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Existing {
    /// Any plain file: the path is in a folder demsweep made for this output.
    Any,
    /// A file demsweep wrote ([`made_by_demsweep`]); any plain file with `force`.
    Ours {
        /// `--force` was given.
        force: bool,
    },
}

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
    /// The file exists, demsweep did not write it, and `--force` was not given.
    NotMadeByDemsweep,
    /// The file exists and demsweep did not write it, beside a results file being resumed (which
    /// `--force` would run again from the start).
    NotMadeByDemsweepResuming,
    /// The file is one written beside the results file this command reads (given): its tables,
    /// their sidecars or its report page, and `--force` was not given.
    Companion(PathBuf),
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
            Self::NotMadeByDemsweep => write!(
                f,
                "refused: exists and was not written by demsweep: pass --force to replace it, or choose another path"
            ),
            Self::NotMadeByDemsweepResuming => write!(
                f,
                "refused: exists and was not written by demsweep (no table of this results file): move it \
                 elsewhere, then resume again (the stored runs are kept)"
            ),
            Self::Companion(results) => write!(
                f,
                "refused: is written beside the results file {} with it (its tables, their sidecars and its report \
                 page belong to it): pass --force to replace it, or choose another path",
                results.display()
            ),
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

    /// The refusal beside results being resumed: a file not demsweep's is to be moved away, as
    /// `--force` would run the stored runs again.
    pub fn resuming(self) -> Self {
        match self.refusal {
            Refusal::NotMadeByDemsweep => Self { refusal: Refusal::NotMadeByDemsweepResuming, ..self },
            _ => self,
        }
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

/// `path` as written less trailing slashes and `.` parts (`out/` is `out`, `./a/./b` is `a/b`): the
/// name a link refusal must see. `..` parts stay (resolving them could pass through a link).
pub fn plain(path: &Path) -> PathBuf {
    path.components().collect()
}

/// Checks that `path` may be written as a file: not a link, folder, input or results file.
pub fn check_file(path: &Path, inputs: &[&Path]) -> Result<(), GuardError> {
    let path = &plain(path);
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

/// Checks that `path` may be written as a file ([`check_file`]) and, when something is there, that
/// `existing` lets it be replaced.
pub fn check_replaceable(path: &Path, inputs: &[&Path], existing: Existing) -> Result<(), GuardError> {
    check_file(path, inputs)?;
    match existing {
        Existing::Ours { force: false } if exists(path) && !made_by_demsweep(path) => {
            Err(refuse(path, Refusal::NotMadeByDemsweep))
        }
        _ => Ok(()),
    }
}

/// Whether the file at `path` is one demsweep wrote, by a mark a file of its kind cannot hold by
/// accident, at a fixed place:
/// - a report page: its head, before the `<title>`, holds [`HTML_MARK`] (pages of earlier versions:
///   their title ends " demsweep report");
/// - an SVG chart starts with [`SVG_MARK`]; a PNG chart has [`PNG_MARK`] before its image data;
/// - a text file starts with [`stamp`]'s line, whose CRC-32 the rest still has;
/// - a JSON file is an object whose `dc:creator` is `demsweep`; a CSV metadata sidecar
///   (`NAME-metadata.json`) also names `NAME` as its `url`;
/// - a CSV table's sidecar is demsweep's and records the table's size and CRC-32, which it still has
///   (an edited table is the user's).
pub fn made_by_demsweep(path: &Path) -> bool {
    let Ok(bytes) = std::fs::read(path) else { return false };
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    is_our_page(&bytes)
        || bytes.starts_with(SVG_MARK.as_bytes())
        || is_our_png(&bytes)
        || is_stamped(&bytes)
        || serde_json::from_slice(&bytes).is_ok_and(|json| is_our_json(&json, &name))
        || bound_to_sidecar(path, &bytes)
}

/// The size and CRC-32 of a file's bytes: what a CSV table's sidecar records of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Content {
    /// Its size (bytes).
    pub bytes: u64,
    /// Its CRC-32 (IEEE, as zlib's `crc32`).
    pub crc32: u32,
}

impl Content {
    /// The content of `bytes`.
    pub fn of(bytes: &[u8]) -> Self {
        Self { bytes: bytes.len() as u64, crc32: crc32fast::hash(bytes) }
    }

    /// As a sidecar records it: `{"bytes": N, "crc32": "8 hex digits"}`.
    pub fn to_json(self) -> serde_json::Value {
        serde_json::json!({"bytes": self.bytes, "crc32": format!("{:08x}", self.crc32)})
    }

    /// Read back from [`Self::to_json`]'s form.
    fn from_json(json: &serde_json::Value) -> Option<Self> {
        let crc32 = u32::from_str_radix(json.get("crc32")?.as_str()?, 16).ok()?;
        Some(Self { bytes: json.get("bytes")?.as_u64()?, crc32 })
    }
}

/// The key under which a CSV table's sidecar records the table's [`Content`].
pub const CONTENT_KEY: &str = "demsweep:content";

/// The start of the first line of a text file demsweep stamps ([`stamp`]).
const STAMP: &str = "# written by demsweep; crc32 of the lines below: ";

/// `text` headed by a line that binds it to demsweep ([`made_by_demsweep`]): the stamp with the
/// CRC-32 of `text`, so that a file edited since counts as the user's.
pub fn stamp(text: &str) -> String {
    format!("{STAMP}{:08x} (an edited file is kept)\n{text}", crc32fast::hash(text.as_bytes()))
}

/// Whether `bytes` start with [`stamp`]'s line and the rest has its CRC-32.
fn is_stamped(bytes: &[u8]) -> bool {
    let Some(rest) = bytes.strip_prefix(STAMP.as_bytes()) else { return false };
    let Some(end) = rest.iter().position(|&b| b == b'\n') else { return false };
    let recorded = std::str::from_utf8(rest.get(..8).unwrap_or_default()).ok();
    recorded.and_then(|hex| u32::from_str_radix(hex, 16).ok()) == Some(crc32fast::hash(&rest[end + 1..]))
}

/// Whether `bytes` are a report page demsweep wrote: an HTML document whose head holds
/// [`HTML_MARK`] before its `<title>`, or whose title ends " demsweep report" (earlier versions).
fn is_our_page(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(4096)];
    let Some(head) = head.strip_prefix(b"<!DOCTYPE html>") else { return false };
    let Some(title) = find(head, "<title>") else { return false };
    let Some(title_end) = find(head, "</title>").filter(|&end| end > title) else { return false };
    let head_ends = find(head, "</head>").unwrap_or(head.len());
    title_end < head_ends
        && (find(&head[..title], HTML_MARK).is_some() || head[..title_end].ends_with(b" demsweep report"))
}

/// Whether `bytes` are a PNG image with [`PNG_MARK`] in a chunk before its image data.
fn is_our_png(bytes: &[u8]) -> bool {
    let header = &bytes[..find(bytes, "IDAT").unwrap_or(0)];
    header.starts_with(b"\x89PNG\r\n\x1a\n") && find(header, &format!("tEXt{}\0{}", PNG_MARK.0, PNG_MARK.1)).is_some()
}

/// Whether `json`, in the file `name`, is an object demsweep wrote (its `dc:creator`); for a CSV
/// metadata sidecar (`NAME-metadata.json`), one that describes `NAME` (its `url`).
fn is_our_json(json: &serde_json::Value, name: &str) -> bool {
    let text = |key: &str| json.get(key).and_then(serde_json::Value::as_str);
    let described = name.strip_suffix("-metadata.json").is_none_or(|table| text("url") == Some(table));
    text("dc:creator") == Some("demsweep") && described
}

/// Whether the CSV table `bytes` at `path` is bound to its sidecar: demsweep's sidecar of it,
/// recording the table's [`Content`].
fn bound_to_sidecar(path: &Path, bytes: &[u8]) -> bool {
    let sidecar = metadata_path(path);
    let Some(json) = std::fs::read(&sidecar).ok().and_then(|text| serde_json::from_slice(&text).ok()) else {
        return false;
    };
    let name = sidecar.file_name().unwrap_or_default().to_string_lossy();
    is_our_json(&json, &name) && json.get(CONTENT_KEY).and_then(Content::from_json) == Some(Content::of(bytes))
}

/// The sidecar of the CSV file at `csv`: `<csv>-metadata.json` (`summary.csv` →
/// `summary.csv-metadata.json`, the file-specific metadata a CSVW processor locates first).
pub fn metadata_path(csv: &Path) -> PathBuf {
    let mut name = csv.file_name().unwrap_or_default().to_os_string();
    name.push("-metadata.json");
    csv.with_file_name(name)
}

/// Where `bytes` first hold `mark`.
fn find(bytes: &[u8], mark: &str) -> Option<usize> {
    bytes.windows(mark.len()).position(|w| w == mark.as_bytes())
}

/// Creates (or truncates) the file `path` after [`check_file`], without following a link.
pub fn create_file(path: &Path, inputs: &[&Path]) -> Result<File, GuardError> {
    check_file(path, inputs)?;
    open_no_follow(&plain(path), true).map_err(|e| refuse(path, Refusal::Io(format!("cannot create: {e}"))))
}

/// Writes `bytes` to the file `path` through [`write_with`], replacing any plain file.
pub fn write(path: &Path, bytes: &[u8], inputs: &[&Path]) -> Result<(), GuardError> {
    write_with(path, inputs, Existing::Any, |out| out.write_all(bytes))
}

/// Writes the file `path` whole or not at all, after [`check_replaceable`]: `body` writes into a
/// temporary file beside it (`.<name>.<pid>.partial`), which is flushed, synced and renamed onto
/// `path` once complete. On failure the temporary file is removed, `path` stays as it was, and the
/// error names `path`.
pub fn write_with(
    path: &Path,
    inputs: &[&Path],
    existing: Existing,
    body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), GuardError> {
    let path = &plain(path);
    check_replaceable(path, inputs, existing)?;
    let Some(name) = path.file_name() else { return Err(refuse(path, Refusal::WrongKind("a file"))) };
    let temporary = path.with_file_name(format!(".{}.{}.partial", name.to_string_lossy(), std::process::id()));
    let file =
        open_no_follow(&temporary, true).map_err(|e| refuse(path, Refusal::Io(format!("cannot create: {e}"))))?;
    let mut out = std::io::BufWriter::new(file);
    let written = body(&mut out)
        .and_then(|()| out.into_inner().map_err(std::io::IntoInnerError::into_error))
        .and_then(|file| file.sync_data())
        .and_then(|()| std::fs::rename(&temporary, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        refuse(path, Refusal::Io(format!("cannot write: {e}")))
    })
}

/// Opens `path` for reading and writing, created if missing and never truncated, without following
/// a symbolic link at it (a link is an error).
pub fn open_no_follow(path: &Path, truncate: bool) -> std::io::Result<File> {
    OpenOptions::new().read(true).write(true).create(true).truncate(truncate).custom_flags(libc::O_NOFOLLOW).open(path)
}

/// Refuses a symbolic link at `path` (a missing path is fine).
pub fn refuse_symlink(path: &Path) -> Result<(), GuardError> {
    match std::fs::symlink_metadata(plain(path)) {
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
pub fn same_file(a: &Path, b: &Path) -> bool {
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
        let out = &plain(out);
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
    if let Some(what) = protected(&place, true) {
        return Err(refuse(out, Refusal::Protected(what)));
    }
    for input in inputs {
        if std::fs::canonicalize(input).is_ok_and(|input| input.starts_with(&place)) {
            return Err(refuse(out, Refusal::ContainsInput(input.to_path_buf())));
        }
    }
    Ok(())
}

/// Refuses a folder that a command writes many files into (charts) when it is `/`, a home folder or
/// above the working folder: they belong in a folder of their own.
pub fn check_files_folder(folder: &Path) -> Result<(), GuardError> {
    let folder = &plain(folder);
    match resolved(folder).and_then(|place| protected(&place, false)) {
        Some(what) => Err(refuse(folder, Refusal::Protected(what))),
        None => Ok(()),
    }
}

/// What the resolved folder `place` is, when no output may replace it (or, unless `working`, be
/// written straight into it): `/`, a home folder, the working folder (with `working`) or one above it.
fn protected(place: &Path, working: bool) -> Option<&'static str> {
    if place.parent().is_none() {
        return Some("the root folder");
    }
    let home = std::env::var_os("HOME").and_then(|h| std::fs::canonicalize(h).ok());
    if home.is_some_and(|home| home == place) {
        return Some("a home folder");
    }
    let cwd = std::env::current_dir().ok().and_then(|d| std::fs::canonicalize(d).ok())?;
    match cwd.starts_with(place) && (working || cwd != place) {
        true if working => Some("the working folder or a folder above it"),
        true => Some("a folder above the working folder"),
        false => None,
    }
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

    #[test]
    fn a_trailing_slash_or_dot_names_the_link_not_the_folder_behind_it() {
        let dir = temp("slash");
        let target = dir.join("target");
        std::fs::create_dir_all(&target).unwrap();
        std::fs::write(target.join(marker_name("export")), "").unwrap();
        std::os::unix::fs::symlink(&target, dir.join("link")).unwrap();
        for written in ["link/", "link/.", "link//"] {
            let out = dir.join(written);
            assert_eq!(refuse_symlink(&out).unwrap_err().refusal, Refusal::Symlink, "{written}");
            assert_eq!(ReplacedFolder::prepare(&out, "export", &[], true).unwrap_err().refusal, Refusal::Symlink);
        }
        assert!(target.join(marker_name("export")).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_existing_file_is_replaced_only_when_demsweep_wrote_it_or_by_force() {
        let dir = temp("ours");
        let ours = Existing::Ours { force: false };
        let page = "<!DOCTYPE html><html><head><meta charset=\"utf-8\">";
        for (name, text, replaceable) in [
            ("notes.txt", "my notes\n".to_string(), false),
            ("t.csv", "a,b\r\n1,2\r\n".to_string(), false),
            ("t.csv", "sample,comment\r\nA1,looks fine\r\n".to_string(), false),
            ("p.html", format!("{page}{HTML_MARK}<title>t</title>"), true),
            ("p.html", format!("{page}<title>t</title></head><body><code>{HTML_MARK}</code>"), false),
            ("p.html", format!("<html><head>{HTML_MARK}<title>t</title>"), false),
            ("c.svg", format!("{SVG_MARK}<svg></svg>"), true),
            ("c.svg", format!("<svg>{SVG_MARK}</svg>"), false),
            ("best.toml", stamp("a = 1\n"), true),
            ("best.toml", stamp("a = 1\n").replace("a = 1", "a = 2"), false),
            ("s_tune.json", "{\"dc:creator\": \"demsweep\"}".to_string(), true),
            ("s_tune.json", "{\"mine\": \"dc:creator demsweep\"}".to_string(), false),
            ("t.csv-metadata.json", "{\"dc:creator\": \"demsweep\", \"url\": \"t.csv\"}".to_string(), true),
            ("t.csv-metadata.json", "{\"dc:creator\": \"demsweep\", \"url\": \"u.csv\"}".to_string(), false),
        ] {
            let file = dir.join(name);
            std::fs::write(&file, &text).unwrap();
            assert_eq!(check_replaceable(&file, &[], ours).is_ok(), replaceable, "{name}: {text:?}");
            assert!(check_replaceable(&file, &[], Existing::Ours { force: true }).is_ok());
            assert!(check_replaceable(&file, &[], Existing::Any).is_ok());
            std::fs::remove_file(&file).unwrap();
        }
        let file = dir.join("mine");
        std::fs::write(&file, "mine").unwrap();
        assert_eq!(write_with(&file, &[], ours, |_| Ok(())).unwrap_err().refusal, Refusal::NotMadeByDemsweep);
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_write_that_fails_leaves_the_earlier_file_and_no_temporary_one() {
        let dir = temp("whole");
        let file = dir.join("page.html");
        write(&file, b"earlier", &[]).unwrap();
        let failed = write_with(&file, &[], Existing::Any, |out| {
            out.write_all(b"half")?;
            Err(std::io::ErrorKind::StorageFull.into())
        });
        let error = failed.unwrap_err();
        assert_eq!(error.path, file);
        assert!(error.to_string().contains("cannot write: "), "{error}");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "earlier");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left");
        write(&file, b"new", &[]).unwrap();
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
