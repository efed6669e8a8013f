//! The study file as text and as a TOML document that remembers where every key was written.

use std::collections::HashMap;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde::de::IntoDeserializer;
use toml::de::DeTable;

use super::errors::{Location, StudyError, StudyErrors};

/// A key path: table names from the root, e.g. `["scene", "material", "friction"]`.
pub(crate) type KeyPath = Vec<String>;

/// The study file's path and text.
pub(crate) struct StudyFile {
    /// Path as given.
    pub path: PathBuf,
    /// The file's text.
    pub text: String,
    /// Byte offset where each line starts.
    line_starts: Vec<usize>,
}

impl StudyFile {
    /// Reads the file (at most [`MAX_STUDY_BYTES`]); a failure is reported against the path.
    pub fn read(path: &Path) -> Result<Self, StudyErrors> {
        let text = read_text(path, MAX_STUDY_BYTES)
            .map_err(|e| StudyError::new(path, None, "", format!("cannot read the study file: {e}")))?;
        Ok(Self::new(path, text))
    }

    /// A study file with the given text.
    pub fn new(path: &Path, text: String) -> Self {
        let line_starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        Self { path: path.to_path_buf(), text, line_starts }
    }

    /// Line and column of a byte offset.
    pub fn locate(&self, offset: usize) -> Location {
        let line = self.line_starts.partition_point(|&start| start <= offset).max(1);
        let start = self.line_starts[line - 1];
        let column = self.text.get(start..offset.min(self.text.len())).map_or(1, |s| s.chars().count() + 1);
        Location { line, column }
    }

    /// A problem at `span` (when known) with `key`.
    pub fn error(&self, span: Option<Range<usize>>, key: impl Into<String>, reason: impl Into<String>) -> StudyError {
        StudyError::new(&self.path, span.map(|s| self.locate(s.start)), key, reason)
    }
}

/// Why a text file could not be read (the path is the caller's to name).
#[derive(Debug)]
pub enum ReadTextError {
    /// Opening or reading failed.
    Io(std::io::Error),
    /// The file is larger than allowed.
    TooLarge {
        /// The most bytes allowed.
        max_bytes: u64,
    },
    /// The file is not UTF-8 text.
    NotUtf8(std::string::FromUtf8Error),
}

impl fmt::Display for ReadTextError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadTextError::Io(e) => write!(f, "{e}"),
            ReadTextError::TooLarge { max_bytes } => {
                write!(f, "the file is larger than the {} MiB allowed", max_bytes >> 20)
            }
            ReadTextError::NotUtf8(e) => write!(f, "not UTF-8 text ({e})"),
        }
    }
}

impl std::error::Error for ReadTextError {}

/// Why a key path cannot be set in a table (`set_path`).
#[derive(Clone, Debug, PartialEq)]
pub enum SetPathError {
    /// No key at all.
    Empty,
    /// A key on the way holds a value, not a table.
    NotATable {
        /// The key, dotted.
        key: String,
        /// The TOML type of its value.
        found: &'static str,
    },
    /// The path ends at a named table of an array, not at a value in it.
    NamesATable {
        /// The path, dotted.
        path: String,
        /// The array, dotted.
        array: String,
    },
    /// An array of tables has no table with the name the path gives.
    NoSuchName {
        /// The array, dotted.
        array: String,
        /// The name asked for.
        name: String,
        /// The names its tables have.
        names: Vec<String>,
    },
}

impl fmt::Display for SetPathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SetPathError::Empty => write!(f, "an empty key path"),
            SetPathError::NotATable { key, found } => write!(f, "{key} is a {found}, not a table"),
            SetPathError::NamesATable { path, array } => write!(f, "{path} names a table of {array}, not a value"),
            SetPathError::NoSuchName { array, name, names } if names.is_empty() => {
                write!(f, "{array} has no table named {name:?} (it has no named tables)")
            }
            SetPathError::NoSuchName { array, name, names } => {
                let names: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
                write!(f, "{array} has no table named {name:?} (its names: {})", names.join(", "))
            }
        }
    }
}

impl std::error::Error for SetPathError {}

/// Largest study or tune file read (bytes): a study of a million runs takes a few kilobytes.
pub const MAX_STUDY_BYTES: u64 = 4 << 20;

/// The UTF-8 text of the file at `path`, refused past `max_bytes` (so `/dev/zero` or a wrong file is
/// an error, not an exhausted memory) and without a leading byte-order mark (Excel's "CSV UTF-8",
/// Windows editors). The error says what is wrong, without the path.
pub fn read_text(path: &Path, max_bytes: u64) -> Result<String, ReadTextError> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(ReadTextError::Io)?;
    let mut bytes = Vec::new();
    file.take(max_bytes + 1).read_to_end(&mut bytes).map_err(ReadTextError::Io)?;
    if bytes.len() as u64 > max_bytes {
        return Err(ReadTextError::TooLarge { max_bytes });
    }
    let text = String::from_utf8(bytes).map_err(ReadTextError::NotUtf8)?;
    Ok(text.strip_prefix('\u{feff}').map(str::to_string).unwrap_or(text))
}

/// A parsed study: its values, and where each key (at any depth of tables) was written.
pub(crate) struct Document {
    /// The document's values.
    pub root: toml::Table,
    /// Span of every key that names a value or table, by key path.
    key_spans: HashMap<KeyPath, Range<usize>>,
}

impl Document {
    /// Parses the study text; every syntax error is reported.
    pub fn parse(file: &StudyFile) -> Result<Self, Vec<StudyError>> {
        let (table, errors) = DeTable::parse_recoverable(&file.text);
        if !errors.is_empty() {
            return Err(errors.iter().map(|e| syntax_error(file, e.span(), e.message())).collect());
        }
        let mut key_spans = HashMap::new();
        collect_spans(table.get_ref(), &mut Vec::new(), &mut key_spans);
        let root = toml::Table::deserialize(table.into_deserializer()).map_err(|e| {
            let span = e.span();
            let key =
                span.as_ref().and_then(|at| key_before(&key_spans, at.start)).map_or(String::new(), |k| dotted(&k));
            vec![file.error(span, key, value_error(e.message()))]
        })?;
        Ok(Self { root, key_spans })
    }

    /// Where the key `path` was written, if it was.
    pub fn span(&self, path: &[String]) -> Option<Range<usize>> {
        self.key_spans.get(path).cloned()
    }

    /// Where the deepest written key along `path` is (the key itself, else its closest parent table).
    pub fn nearest_span(&self, path: &[String]) -> Option<Range<usize>> {
        (1..=path.len()).rev().find_map(|n| self.span(&path[..n]))
    }

    /// The table at `key` of the root, if there is one.
    pub fn section(&self, key: &str) -> Option<&toml::Value> {
        self.root.get(key)
    }
}

/// A TOML syntax error; a duplicate key is named, with its table.
fn syntax_error(file: &StudyFile, span: Option<Range<usize>>, message: &str) -> StudyError {
    let Some(at) = span.clone().filter(|_| message.starts_with("duplicate key")) else {
        return file.error(span, "", format!("TOML syntax: {message}"));
    };
    let line_start = file.text[..at.start].rfind('\n').map_or(0, |i| i + 1);
    let written = file.text[line_start..].split(['=', '\n']).next().unwrap_or("").trim();
    let table = file.text[..line_start]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('['))
        .map(|header| header.trim_matches(|c| c == '[' || c == ']').trim());
    let key = table.map_or(written.to_string(), |t| format!("{t}.{written}"));
    let reason = format!("TOML syntax: `{written}` is given twice in this table: keep one of them");
    file.error(span, key, reason)
}

/// The key path written last before byte `offset` (the key whose value starts there).
fn key_before(spans: &HashMap<KeyPath, Range<usize>>, offset: usize) -> Option<KeyPath> {
    spans.iter().filter(|(_, span)| span.start <= offset).max_by_key(|(_, span)| span.start).map(|(k, _)| k.clone())
}

/// A value TOML cannot hold, in words.
fn value_error(message: &str) -> String {
    match message.split('`').nth(1).filter(|_| message.contains("as i128")) {
        Some(number) => {
            format!("{number} is out of range: TOML whole numbers lie between {} and {}", i64::MIN, i64::MAX)
        }
        None => format!("TOML: {message}"),
    }
}

fn collect_spans(table: &DeTable<'_>, prefix: &mut KeyPath, spans: &mut HashMap<KeyPath, Range<usize>>) {
    for (key, value) in table.iter() {
        prefix.push(key.get_ref().to_string());
        spans.entry(prefix.clone()).or_insert_with(|| key.span());
        if let Some(inner) = value.get_ref().as_table() {
            collect_spans(inner, prefix, spans);
        } else if let Some(items) = value.get_ref().as_array() {
            // The tables of an array named by their `name` (`[[scene.stages]]`): their keys under it.
            for item in items {
                let Some(inner) = item.get_ref().as_table() else { continue };
                let name = inner.iter().find(|(k, _)| k.get_ref().as_ref() == "name");
                let Some(name) = name.and_then(|(_, v)| v.get_ref().as_str()) else { continue };
                prefix.push(name.to_string());
                spans.entry(prefix.clone()).or_insert_with(|| item.span());
                collect_spans(inner, prefix, spans);
                prefix.pop();
            }
        }
        prefix.pop();
    }
}

/// Every non-table value and empty table under `table` with its key path (relative to `table`).
pub(crate) fn leaves(table: &toml::Table) -> Vec<(KeyPath, &toml::Value)> {
    let mut out = Vec::new();
    collect_leaves(table, &mut Vec::new(), &mut out);
    out
}

fn collect_leaves<'a>(table: &'a toml::Table, prefix: &mut KeyPath, out: &mut Vec<(KeyPath, &'a toml::Value)>) {
    for (key, value) in table {
        prefix.push(key.clone());
        match value.as_table() {
            Some(inner) if !inner.is_empty() => collect_leaves(inner, prefix, out),
            _ => out.push((prefix.clone(), value)),
        }
        prefix.pop();
    }
}

/// Sets `path` in `table` to `value`, creating missing tables on the way. In an array of tables
/// with names (`[[scene.stages]]`), the next key of the path names the table.
pub(crate) fn set_path(table: &mut toml::Table, path: &[String], value: toml::Value) -> Result<(), SetPathError> {
    let (last, parents) = path.split_last().ok_or(SetPathError::Empty)?;
    let mut here = table;
    let mut depth = 0;
    while depth < parents.len() {
        let key = &parents[depth];
        here = match here.entry(key.clone()).or_insert_with(|| toml::Value::Table(toml::Table::new())) {
            toml::Value::Table(inner) => inner,
            toml::Value::Array(items) => {
                depth += 1;
                let name = path.get(depth).ok_or(SetPathError::Empty)?;
                let index = named(items, name).ok_or_else(|| no_such_name(&path[..depth], name, items))?;
                items[index].as_table_mut().expect("a named table")
            }
            other => {
                return Err(SetPathError::NotATable { key: dotted(&path[..=depth]), found: other.type_str() });
            }
        };
        depth += 1;
    }
    if depth > parents.len() {
        return Err(SetPathError::NamesATable { path: dotted(path), array: dotted(&path[..depth - 1]) });
    }
    here.insert(last.clone(), value);
    Ok(())
}

/// Sets each of `values` in `table` with [`set_path`], those that rename a table of an array last:
/// every path names the tables of arrays as `table` names them, whatever the order of `values`.
pub(crate) fn set_paths<'a>(
    table: &mut toml::Table,
    values: impl IntoIterator<Item = (&'a [String], toml::Value)>,
) -> Result<(), SetPathError> {
    let (names, others): (Vec<_>, Vec<_>) =
        values.into_iter().partition(|(path, _)| path.last().is_some_and(|key| key == "name"));
    for (path, value) in others.into_iter().chain(names) {
        set_path(table, path, value)?;
    }
    Ok(())
}

/// Where in `items` the table whose `name` is `name` is.
fn named(items: &[toml::Value], name: &str) -> Option<usize> {
    items.iter().position(|t| t.is_table() && t.get("name").and_then(|n| n.as_str()) == Some(name))
}

/// Why `name` names none of `items` (the array at `array`).
fn no_such_name(array: &[String], name: &str, items: &[toml::Value]) -> SetPathError {
    let names = items.iter().filter_map(|item| item.get("name").and_then(|n| n.as_str())).map(String::from).collect();
    SetPathError::NoSuchName { array: dotted(array), name: name.to_string(), names }
}

/// A table holding only `value` at `path`.
pub(crate) fn tree_with(path: &[String], value: toml::Value) -> toml::Table {
    let mut table = toml::Table::new();
    set_path(&mut table, path, value).expect("a fresh table has no values in the way");
    table
}

/// [`tree_with`] for checking a value of `base` on its own: a named table of an array on the way
/// (a stage of `[[scene.stages]]`) is copied from `base` whole, so the value is checked in it.
pub(crate) fn tree_within(base: &toml::Table, path: &[String], value: toml::Value) -> toml::Table {
    let mut here = base;
    for (depth, key) in path.iter().enumerate() {
        match here.get(key) {
            Some(toml::Value::Table(inner)) => here = inner,
            Some(toml::Value::Array(items)) => {
                let Some(index) = path.get(depth + 1).and_then(|name| named(items, name)) else { break };
                let mut item = items[index].as_table().expect("a named table").clone();
                if set_path(&mut item, &path[depth + 2..], value.clone()).is_err() {
                    break;
                }
                return tree_with(&path[..=depth], toml::Value::Array(vec![toml::Value::Table(item)]));
            }
            _ => break,
        }
    }
    tree_with(path, value)
}

/// A key path as written in TOML: segments joined by dots, quoted where they are not bare keys.
pub(crate) fn dotted(path: &[String]) -> String {
    path.iter().map(|k| quoted_key(k)).collect::<Vec<_>>().join(".")
}

/// A single key as written in TOML: bare when possible, else quoted.
pub(crate) fn quoted_key(key: &str) -> String {
    let bare = !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare { key.to_string() } else { toml::Value::String(key.to_string()).to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(text: &str) -> StudyFile {
        StudyFile::new(Path::new("s.toml"), text.to_string())
    }

    #[test]
    fn locate_gives_one_based_line_and_column() {
        let f = file("a = 1\n\nbc = 2\n");
        assert_eq!(f.locate(0), Location { line: 1, column: 1 });
        assert_eq!(f.locate(7), Location { line: 3, column: 1 });
        assert_eq!(f.locate(10), Location { line: 3, column: 4 });
    }

    #[test]
    fn key_spans_cover_headers_dotted_keys_and_nesting() {
        let f = file("name = \"x\"\n[scene.material]\nfriction = 0.3\n[sweep]\n\"material.beta\" = [1, 2]\n");
        let doc = Document::parse(&f).unwrap();
        let at =
            |p: &[&str]| doc.span(&p.iter().map(|s| s.to_string()).collect::<Vec<_>>()).map(|s| f.locate(s.start).line);
        assert_eq!(at(&["name"]), Some(1));
        assert_eq!(at(&["scene", "material"]), Some(2));
        assert_eq!(at(&["scene", "material", "friction"]), Some(3));
        assert_eq!(at(&["sweep", "material.beta"]), Some(5));
        let deeper: Vec<String> = ["scene", "material", "density"].iter().map(|s| s.to_string()).collect();
        assert_eq!(doc.nearest_span(&deeper).map(|s| f.locate(s.start).line), Some(2));
    }

    #[test]
    fn syntax_errors_are_located() {
        let errors = Document::parse(&file("a = 1\nb = = 2\n")).err().unwrap();
        assert_eq!(errors[0].location.map(|l| l.line), Some(2));
        assert!(errors[0].reason.starts_with("TOML syntax"), "{}", errors[0].reason);
    }

    #[test]
    fn set_path_creates_tables_and_refuses_to_descend_into_values() {
        let mut t: toml::Table = toml::from_str("[material]\nfriction = 0.5\n").unwrap();
        let path = |s: &str| s.split('.').map(String::from).collect::<Vec<_>>();
        set_path(&mut t, &path("settle.hold_time"), toml::Value::Float(0.1)).unwrap();
        assert_eq!(t["settle"]["hold_time"].as_float(), Some(0.1));
        let err = set_path(&mut t, &path("material.friction.x"), toml::Value::Float(0.1)).unwrap_err();
        assert_eq!(err.to_string(), "material.friction is a float, not a table");
        assert_eq!(dotted(&path("material.friction")), "material.friction");
        assert_eq!(dotted(&["sweep".to_string(), "a.b".to_string()]), "sweep.\"a.b\"");
    }
}
