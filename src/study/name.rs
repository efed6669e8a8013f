//! Study names: every output file is named `<name>.h5`, `<name>_summary.csv`, … inside `--out`, so
//! a name must be a safe file stem on every platform.

use std::fmt;

/// Longest study name, in characters (file names stay well under the usual 255-byte limit).
pub const MAX_NAME_CHARS: usize = 100;

/// The rule a study name must follow, as shown in messages.
pub const NAME_RULE: &str = "a study name is 1 to 100 ASCII letters, digits, spaces and `_` `-` `.`, \
                             starting with a letter or digit (it names the output files)";

/// What makes a study name unsafe as a file stem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NameProblem {
    /// No character.
    Empty,
    /// More than [`MAX_NAME_CHARS`] characters (how many).
    TooLong(usize),
    /// A character not allowed.
    Contains(char),
    /// A first character other than a letter or digit.
    StartsWith(char),
}

/// A study name that is not a safe file stem, and why; the text names the rule.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NameError {
    /// The name.
    pub name: String,
    /// What is wrong with it.
    pub problem: NameProblem,
}

impl fmt::Display for NameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "the study name {} ", shown(&self.name))?;
        match self.problem {
            NameProblem::Empty => write!(f, "is empty")?,
            NameProblem::TooLong(n) => write!(f, "has {n} characters")?,
            NameProblem::Contains(c) => write!(f, "contains {c:?}")?,
            NameProblem::StartsWith(c) => write!(f, "starts with {c:?}")?,
        }
        write!(f, ": {NAME_RULE}")
    }
}

impl std::error::Error for NameError {}

/// Checks that `name` is a safe file stem: not empty, at most [`MAX_NAME_CHARS`], only ASCII
/// letters, digits, spaces, `_`, `-` and `.`, starting with a letter or digit (so no path
/// separators, `..`, hidden files, control characters or NUL). The error says what is wrong and
/// the rule.
pub fn check_name(name: &str) -> Result<(), NameError> {
    let problem = if name.is_empty() {
        NameProblem::Empty
    } else if name.chars().count() > MAX_NAME_CHARS {
        NameProblem::TooLong(name.chars().count())
    } else if let Some(c) = name.chars().find(|&c| !(c.is_ascii_alphanumeric() || " _-.".contains(c))) {
        NameProblem::Contains(c)
    } else if !name.starts_with(|c: char| c.is_ascii_alphanumeric()) {
        NameProblem::StartsWith(name.chars().next().unwrap_or_default())
    } else {
        return Ok(());
    };
    Err(NameError { name: name.to_string(), problem })
}

/// The name quoted, shortened when long.
fn shown(name: &str) -> String {
    if name.chars().count() > 40 {
        format!("{:?}…", name.chars().take(40).collect::<String>())
    } else {
        format!("{name:?}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn safe_stems_pass_and_paths_do_not() {
        for good in ["paper_table1", "my study", "run-2.b", "A"] {
            assert_eq!(check_name(good), Ok(()), "{good}");
        }
        let reason = |name: &str| check_name(name).unwrap_err().to_string();
        assert!(reason("../../x").contains("contains '/'"), "{}", reason("../../x"));
        assert!(reason("/abs/path").contains("contains '/'"));
        assert!(reason("a\\b").contains("contains '\\\\'"), "{}", reason("a\\b"));
        assert!(reason(".").contains("starts with '.'"));
        assert!(reason("..").contains("starts with '.'"));
        assert!(reason("").contains("is empty"));
        assert!(reason("a\0b").contains("contains '\\0'"));
        assert!(reason("tab\there").contains("contains '\\t'"));
        assert!(reason("café").contains("contains 'é'"));
        assert!(reason(&"x".repeat(560)).contains("has 560 characters"));
        assert!(reason(&"x".repeat(560)).ends_with(NAME_RULE));
        assert_eq!(check_name(&"x".repeat(MAX_NAME_CHARS)), Ok(()));
    }
}
