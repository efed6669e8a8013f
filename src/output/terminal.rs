//! The text edge: every line the command, the runner and the Python module print goes through here.
//!
//! Control characters that come from inputs (study keys and values, file text, stored messages) are
//! escaped ([`escape`]) so that no input can move the cursor, retitle the terminal or hide text. A
//! failed write to standard output is remembered instead of ending the process: a closed pipe
//! (`| head`) silences the rest of the output, any other failure (a full disk) is reported by
//! [`stdout_failure`] once the work is done; progress lines thus never cost a run.

use std::borrow::Cow;
use std::fmt;
use std::io::{self, Write};
use std::sync::Mutex;

/// The first failure of a write to standard output, if any; later writes are skipped.
static STDOUT_FAILED: Mutex<Option<StdoutError>> = Mutex::new(None);

/// A write to standard output failed (other than its reader closing the pipe).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StdoutError {
    /// What kind of failure.
    pub kind: io::ErrorKind,
    /// The system's error number, when there is one.
    pub os_error: Option<i32>,
}

impl From<&io::Error> for StdoutError {
    fn from(error: &io::Error) -> Self {
        Self { kind: error.kind(), os_error: error.raw_os_error() }
    }
}

impl fmt::Display for StdoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let cause = self.os_error.map_or_else(|| io::Error::from(self.kind), io::Error::from_raw_os_error);
        write!(f, "cannot write to standard output: {cause}")
    }
}

impl std::error::Error for StdoutError {}

/// `text` with its control characters (but newlines, tabs and the `\r` of a `\r\n`) and the Unicode
/// direction overrides written as `\u{..}` escapes; borrowed when there is none.
pub fn escape(text: &str) -> Cow<'_, str> {
    let shown = |(at, c): (usize, char)| match c {
        '\n' | '\t' => true,
        '\r' => text[at + 1..].starts_with('\n'),
        _ => !c.is_control() && !is_direction_override(c),
    };
    if text.char_indices().all(shown) {
        return Cow::Borrowed(text);
    }
    let mut escaped = String::with_capacity(text.len() + 16);
    for (at, c) in text.char_indices() {
        if shown((at, c)) {
            escaped.push(c);
        } else {
            escaped.push_str(&format!("\\u{{{:x}}}", c as u32));
        }
    }
    Cow::Owned(escaped)
}

/// Whether `c` reorders the text after it (bidirectional embeddings, overrides and isolates).
fn is_direction_override(c: char) -> bool {
    matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// Writes `args` to standard output, escaped; a failure is remembered (see [`stdout_failure`]).
pub fn out(args: fmt::Arguments<'_>) {
    let mut failed = STDOUT_FAILED.lock().unwrap_or_else(|e| e.into_inner());
    if failed.is_some() {
        return;
    }
    let text = fmt::format(args);
    if let Err(e) = io::stdout().lock().write_all(escape(&text).as_bytes()) {
        *failed = Some(StdoutError::from(&e));
    }
}

/// Writes `args` to standard error, escaped; a failure is ignored (there is nowhere left to say it).
pub fn err(args: fmt::Arguments<'_>) {
    let text = fmt::format(args);
    let _ = io::stderr().lock().write_all(escape(&text).as_bytes());
}

/// Flushes standard output; the failure of a write to it, unless its reader closed the pipe (then
/// the output ends quietly, as `| head` asks).
pub fn stdout_failure() -> Option<StdoutError> {
    let mut failed = STDOUT_FAILED.lock().unwrap_or_else(|e| e.into_inner());
    if failed.is_none()
        && let Err(e) = io::stdout().lock().flush()
    {
        *failed = Some(StdoutError::from(&e));
    }
    failed.filter(|e| e.kind != io::ErrorKind::BrokenPipe)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_and_line_ends_kept() {
        assert!(matches!(escape("plain text\twith tab\n"), Cow::Borrowed(_)));
        assert_eq!(escape("a\u{1b}]0;title\u{7}b"), "a\\u{1b}]0;title\\u{7}b");
        assert_eq!(escape("nul\0 del\u{7f} c1\u{9b}"), "nul\\u{0} del\\u{7f} c1\\u{9b}");
        assert_eq!(escape("csv\r\nline\rover"), "csv\r\nline\\u{d}over");
        assert_eq!(escape("evil\u{202e}txt.exe"), "evil\\u{202e}txt.exe");
        assert_eq!(escape("grüße — 5 µm"), "grüße — 5 µm");
    }
}
