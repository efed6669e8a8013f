//! Every section's defaults: a scene key not given takes its value from here.

use super::{
    BroadPhaseKind, ContactConfig, DampingConfig, DomainConfig, IntegratorConfig, IntegratorKind, LimitsConfig,
    MaterialConfig, NeighborConfig, ParticlesConfig, PlacementConfig, PlacementKind, PourConfig, RunConfig,
    SceneConfig, SettleConfig, WallMaterialConfig,
};

impl Default for SceneConfig {
    fn default() -> Self {
        Self {
            domain: DomainConfig::default(),
            particles: ParticlesConfig::default(),
            placement: PlacementConfig::default(),
            material: MaterialConfig::default(),
            wall_material: WallMaterialConfig::default(),
            contact: ContactConfig::default(),
            gravity: [0.0, -9.81],
            integrator: IntegratorConfig::default(),
            damping: DampingConfig::default(),
            run: RunConfig::default(),
            settle: SettleConfig::default(),
            limits: LimitsConfig::default(),
            neighbors: NeighborConfig::default(),
            stages: Vec::new(),
        }
    }
}

impl Default for DomainConfig {
    fn default() -> Self {
        Self { width: 0.4, height: 0.6, lid: false, periodic_x: false }
    }
}

impl Default for ParticlesConfig {
    fn default() -> Self {
        Self { count: 300, radius: 0.01, radius_max: None, radii: None, size_distribution: None, thickness: 1.0 }
    }
}

impl Default for PlacementConfig {
    fn default() -> Self {
        Self {
            kind: PlacementKind::Random,
            seed: 12345,
            lattice_gap: 0.05,
            lattice_hexagonal: false,
            file: None,
            contacts: None,
            max_attempts: 10_000,
            lowered_by: 0.0,
            pour: PourConfig::default(),
        }
    }
}

impl Default for PourConfig {
    fn default() -> Self {
        Self {
            rate: None,
            mass_rate: None,
            x_min: None,
            x_max: None,
            y_min: None,
            y_max: None,
            velocity: [0.0, 0.0],
            velocity_spread: 0.0,
        }
    }
}

impl Default for MaterialConfig {
    fn default() -> Self {
        Self {
            density: 1000.0,
            youngs_modulus: 1e9,
            poisson_ratio: None,
            shear_modulus: None,
            beta: None,
            restitution: None,
            friction: 0.5,
            rolling_friction: 0.0,
        }
    }
}

impl Default for IntegratorConfig {
    fn default() -> Self {
        Self {
            scheme: IntegratorKind::AdamsBashforthMoulton,
            time_step: None,
            contact_time_fraction: None,
            rayleigh_fraction: None,
        }
    }
}

impl Default for DampingConfig {
    fn default() -> Self {
        Self { local: 0.0, local_gravity: true, viscous: 0.0 }
    }
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            duration: 1.5,
            sample_interval: 1e-3,
            stop_at_settle: true,
            frame_times: Vec::new(),
            frame_interval: None,
        }
    }
}

impl Default for SettleConfig {
    fn default() -> Self {
        Self { ubf_threshold: 1e-2, hold_time: 0.05, kinetic_energy_threshold: None }
    }
}

impl Default for LimitsConfig {
    fn default() -> Self {
        Self {
            max_overlap_ratio: 0.5,
            overlap_warning_ratio: 0.1,
            energy_growth_ratio: 0.5,
            energy_balance_tolerance: 0.01,
            contact_time_fraction: 0.1,
            damping_rate_fraction: 0.5,
        }
    }
}

impl Default for NeighborConfig {
    fn default() -> Self {
        Self { broad_phase: BroadPhaseKind::Grid, skin_ratio: 0.3 }
    }
}
