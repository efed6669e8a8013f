//! The time integration schemes a scene can name (`integrator.scheme`); the schemes themselves
//! are in `integrator`.

use serde::{Deserialize, Serialize};

/// Time integration scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorKind {
    /// The paper's scheme: Adams-Bashforth 2 velocities (AB1 first step), Adams-Moulton 2 positions.
    AdamsBashforthMoulton,
    /// Velocity Verlet, as in LAMMPS and LIGGGHTS.
    VelocityVerlet,
}
