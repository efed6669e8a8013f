//! Energy bookkeeping of a run: the work of the contact forces and of the numerical damping,
//! integrated by the trapezoid rule over steps, from which the dissipated energy follows
//! (mechanical + dissipated = initial, up to integration error). Dissipated is what the works and
//! the stored elastic energy leave: elastic energy that leaves the contacts with no work done (a
//! spring cut back to a lowered Coulomb limit when a stage lowers friction) counts as dissipated,
//! as a sliding contact's does.

/// The works done so far, and the powers at the start of the last step to close its trapezoid.
#[derive(Clone, Debug, Default)]
pub(super) struct EnergyLedger {
    /// Work of the contact forces and torques so far (J).
    contact_work: f64,
    /// Their power at the start of the last step (W); `None` before the first step.
    last_power: Option<f64>,
    /// Work of the numerical damping so far (J, ≤ 0).
    damping_work: f64,
    /// Its power at the start of the last step (W).
    last_damping_power: f64,
    /// Elastic energy of the contacts at time zero (J).
    pub initial_elastic: f64,
}

impl EnergyLedger {
    /// Adds the trapezoid of the step that ended where this one starts, with the contact and
    /// damping powers at its start (W) and the time step `dt` (s).
    pub fn record_step(&mut self, power: f64, damping_power: f64, dt: f64) {
        if let Some(last) = self.last_power {
            self.contact_work += 0.5 * (last + power) * dt;
            self.damping_work += 0.5 * (self.last_damping_power + damping_power) * dt;
        }
        self.last_power = Some(power);
        self.last_damping_power = damping_power;
    }

    /// Closes the trapezoid of the step that ended here with the powers at its end (W) and its step
    /// `dt` (s), before the forces jump (a switch of stages changes them, the damping or the step):
    /// the next step's trapezoid starts from the powers after the jump, which
    /// [`Self::record_step`] then records without closing anything.
    pub fn close_before_jump(&mut self, (power, damping_power): (f64, f64), dt: f64) {
        self.record_step(power, damping_power, dt);
        self.last_power = None;
    }

    /// Removes energy taken out of the motion besides the forces' power (J), e.g. rolling resistance.
    pub fn remove(&mut self, energy: f64) {
        self.contact_work -= energy;
    }

    /// Whether the last step's power was finite (true before the first step).
    pub fn power_finite(&self) -> bool {
        self.last_power.is_none_or(f64::is_finite)
    }

    /// The works up to the current state (J): contact and numerical damping, each closing its last
    /// trapezoid with the powers (W) at the current velocities that `now` computes.
    pub fn works_now(&self, now: impl FnOnce() -> (f64, f64), dt: f64) -> (f64, f64) {
        match self.last_power {
            None => (self.contact_work, self.damping_work),
            Some(last) => {
                let (power, damping_power) = now();
                (
                    self.contact_work + 0.5 * (last + power) * dt,
                    self.damping_work + 0.5 * (self.last_damping_power + damping_power) * dt,
                )
            }
        }
    }

    /// Energy dissipated so far (J), given the contacts' elastic energy now and the works now.
    pub fn dissipated(&self, elastic: f64, works: (f64, f64)) -> f64 {
        self.initial_elastic - elastic - works.0 - works.1
    }
}

super::run_state::persist_fields!(EnergyLedger {
    contact_work,
    last_power,
    damping_work,
    last_damping_power,
    initial_elastic,
});
