//! The Python the tests run their h5py and Playwright scripts with, by one rule: `$DEMSWEEP_PYTHON`
//! (which `scripts/test.sh` sets), else the virtual environment that script makes in the build
//! folder, `<target>/pyenv/bin/python`.

use std::path::PathBuf;
use std::process::Command;

/// `python SCRIPT`, with the tests' Python; panics, naming the way to get one, when there is none.
pub fn python(script: &str) -> Command {
    let python = match std::env::var_os("DEMSWEEP_PYTHON") {
        Some(path) => PathBuf::from(path),
        None => PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("../pyenv/bin/python"),
    };
    assert!(
        python.exists(),
        "no Python for the tests at {}: run the tests with scripts/test.sh, which makes it (h5py, numpy, playwright)",
        python.display()
    );
    let mut command = Command::new(python);
    command.arg(script);
    command
}
