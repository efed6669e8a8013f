//! Why disks could not be placed.

/// Why disks could not be placed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlacementError {
    /// Key path the problem belongs to.
    pub key: String,
    /// What went wrong, with how many disks fit.
    pub reason: String,
}

impl std::fmt::Display for PlacementError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.key, self.reason)
    }
}

impl std::error::Error for PlacementError {}
