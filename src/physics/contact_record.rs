//! One contact of a state as the pile metrics, the contact network and a restart see it: which
//! disk, what it touches, its forces and its history.

/// What a contact touches besides its first disk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    /// Another disk (index).
    Disk(usize),
    /// A wall (index in the box's walls; 0 is the floor).
    Wall(usize),
}

/// One contact of a state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PileContact {
    /// The first disk.
    pub disk: usize,
    /// What it touches.
    pub partner: Partner,
    /// Unit normal from the disk towards its partner.
    pub normal: [f64; 2],
    /// Normal force (N), repulsive when positive.
    pub normal_force: f64,
    /// Tangential force (N).
    pub tangential_force: f64,
    /// Sliding friction coefficient of the contact.
    pub friction: f64,
    /// Overlap over the smaller radius.
    pub overlap_ratio: f64,
    /// Tangential spring ξ (m) and the law's state as a number: the contact's history, as the
    /// next step starts from it (what a restart needs).
    pub history: (f64, f64),
}

/// Relative tolerance of "at the Coulomb limit" in [`PileContact::is_sliding`].
const SLIDING_TOLERANCE: f64 = 1e-9;

impl PileContact {
    pub(super) fn carries_force(&self) -> bool {
        self.normal_force > 0.0
    }

    /// Whether the contact has friction and its tangential force sits on the Coulomb limit `μ F_n`.
    pub fn is_sliding(&self) -> bool {
        self.friction > 0.0
            && self.tangential_force.abs() >= self.friction * self.normal_force * (1.0 - SLIDING_TOLERANCE)
    }

    /// The two disks of a disk–disk contact; `None` for a wall contact.
    pub(super) fn disks(&self) -> Option<(usize, usize)> {
        match self.partner {
            Partner::Disk(j) => Some((self.disk, j)),
            Partner::Wall(_) => None,
        }
    }
}
