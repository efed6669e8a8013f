//! The writer's lock on a results file: one process at a time creates, overwrites, resumes or
//! merges into `<results>.lock`'s results file. The lock is an OS advisory lock on the file
//! `<results>.lock` (released by the kernel however the process ends, `kill -9` included); the
//! file's text says who holds it. The holder removes the file before releasing the lock, so a
//! finished run leaves none (one killed leaves an empty one, which the next run takes). A process
//! that locked a file just removed by its holder finds that the path no longer names it, and tries
//! again: two processes never hold locks on two different files of the same name.

use std::fs::{File, TryLockError};
use std::io::{Read, Seek, Write};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use super::header::utc_now;
use super::{OutputError, OutputReason};

/// A held lock on a results file; released when dropped.
#[derive(Debug)]
pub struct ResultsLock {
    file: File,
    path: PathBuf,
}

/// How many times a lock is tried while its file keeps being removed under it by other holders.
const ATTEMPTS: usize = 100;

/// The lock file of a results file: `<results>.lock`.
pub fn lock_path(results: &Path) -> PathBuf {
    let mut name = results.file_name().unwrap_or_default().to_os_string();
    name.push(".lock");
    results.with_file_name(name)
}

impl ResultsLock {
    /// Takes the lock of `results` without waiting; the refusal names who holds it and what to do.
    pub fn acquire(results: &Path) -> Result<Self, OutputError> {
        let path = lock_path(results);
        for _ in 0..ATTEMPTS {
            let file = lock_file(results, &path)?;
            if names(&path, &file) {
                return Self::hold(file, path);
            }
        }
        Err(OutputError::at(&path, OutputReason::LockContended))
    }

    /// Writes who holds the locked `file` into it.
    fn hold(mut file: File, path: PathBuf) -> Result<Self, OutputError> {
        let holder = format!("pid {} on {} since {}\n", std::process::id(), hostname(), utc_now());
        let written = file.set_len(0).and_then(|()| file.rewind()).and_then(|()| file.write_all(holder.as_bytes()));
        written.map_err(|e| OutputError::io(&path, e))?;
        Ok(Self { file, path })
    }
}

/// Opens (creating it if missing) and locks the lock file at `path` of `results`; refused when another
/// process holds it.
fn lock_file(results: &Path, path: &Path) -> Result<File, OutputError> {
    super::guard::refuse_symlink(path).map_err(|e| OutputError::refused(path, e))?;
    let mut file = super::guard::open_no_follow(path, false)
        .map_err(|e| OutputError::io_doing(path, "cannot create the lock file", e))?;
    match file.try_lock() {
        Ok(()) => Ok(file),
        Err(TryLockError::WouldBlock) => {
            let mut holder = String::new();
            let _ = file.read_to_string(&mut holder);
            Err(OutputError::at(results, OutputReason::Locked { holder: holder.trim().to_string() }))
        }
        Err(TryLockError::Error(e)) => {
            Err(OutputError::io_doing(path, "cannot lock (does this file system support locks?)", e))
        }
    }
}

/// Whether `path` names the open `file` (and not another file, or none, since it was opened).
fn names(path: &Path, file: &File) -> bool {
    match (std::fs::symlink_metadata(path), file.metadata()) {
        (Ok(at_path), Ok(open)) => at_path.dev() == open.dev() && at_path.ino() == open.ino(),
        _ => false,
    }
}

impl Drop for ResultsLock {
    /// Removes the lock file (when its path still names it), then releases the lock by closing it.
    fn drop(&mut self) {
        if names(&self.path, &self.file) {
            let _ = std::fs::remove_file(&self.path);
        } else {
            let _ = self.file.set_len(0);
        }
    }
}

/// This machine's host name (`/proc/sys/kernel/hostname`, else `$HOSTNAME`), or `?`.
fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map_or_else(|| "?".to_string(), |name| name.trim().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_is_refused_naming_the_holder_until_the_first_is_dropped() {
        let dir = std::env::temp_dir().join(format!("demsweep-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let results = dir.join("s.h5");
        assert_eq!(lock_path(&results), dir.join("s.h5.lock"));
        let first = ResultsLock::acquire(&results).unwrap();
        let refused = ResultsLock::acquire(&results).unwrap_err();
        assert_eq!(refused.path, results);
        let pid = format!("pid {} on ", std::process::id());
        match &*refused.reason {
            OutputReason::Locked { holder } => assert!(holder.starts_with(&pid), "{refused}"),
            other => panic!("{other:?}"),
        }
        assert!(refused.to_string().contains(&pid) && refused.to_string().contains("--resume"), "{refused}");
        drop(first);
        assert!(!lock_path(&results).exists(), "released: no lock file left");
        drop(ResultsLock::acquire(&results).unwrap());
        assert!(!lock_path(&results).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_lock_on_a_file_its_holder_removed_is_taken_again_on_the_new_file() {
        let dir = std::env::temp_dir().join(format!("demsweep-relock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let results = dir.join("s.h5");
        let path = lock_path(&results);
        let stale = lock_file(&results, &path).unwrap(); // locked, then its file removed under it
        std::fs::remove_file(&path).unwrap();
        assert!(!names(&path, &stale));
        let taken = ResultsLock::acquire(&results).unwrap();
        assert!(names(&path, &taken.file), "the lock is on the file the path names");
        drop(stale);
        let refused = ResultsLock::acquire(&results).unwrap_err();
        assert!(matches!(*refused.reason, OutputReason::Locked { .. }), "{refused}");
        drop(taken);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
