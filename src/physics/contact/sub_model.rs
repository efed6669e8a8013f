//! The four kinds of contact sub-model a law is composed of ([`super::Composed`]): the normal
//! spring, the damping of both springs, the tangential spring and the rolling resistance. Each model
//! is one file implementing its kind's trait, listed in the table of [`super::table`].

use super::law::{ContactState, PairProperties};

/// A spring stiffness `scale · grade` (N/m), kept as its two factors: `scale` a constant of the
/// contact class (e.g. `2E*`), `grade` what varies per contact (e.g. `√(R*δ)`). A damping model
/// takes the square root of each factor apart, so that the class constant's root is a loop invariant
/// and each contact costs one square root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stiffness {
    /// Factor constant over a contact class.
    pub scale: f64,
    /// Factor that varies from contact to contact.
    pub grade: f64,
}

impl Stiffness {
    /// A stiffness given whole (`scale` 1).
    #[inline(always)]
    pub fn whole(value: f64) -> Self {
        Self { scale: 1.0, grade: value }
    }

    /// The stiffness, `scale · grade` (N/m).
    #[inline(always)]
    pub fn value(self) -> f64 {
        self.scale * self.grade
    }
}

/// Problems with a model's parameters, as (key within its `[contact.<table>]`, reason).
pub type Problems = Vec<(&'static str, String)>;

/// The normal spring: elastic force, the stiffness damping and tangential models scale with, and
/// the elastic energy it stores.
pub trait NormalModel: Copy + Send + Sync + 'static {
    /// Per-contact history of the model's own (`()` for none), see [`super::ContactLaw::State`].
    type State: ContactState;
    /// Elastic normal force (N) at overlap `overlap > 0` (m), and the stiffness that damping and
    /// tangential models scale with (for a nonlinear spring its tangent, for a plastic one its
    /// loading stiffness), updating the contact's `state`.
    fn load(&self, pair: &PairProperties, overlap: f64, state: &mut Self::State) -> (f64, Stiffness);
    /// Elastic energy stored at overlap `overlap` in `state` (J).
    fn elastic_energy(&self, pair: &PairProperties, overlap: f64, state: &Self::State) -> f64;
    /// Tangential over normal stiffness of the `linear` tangential model with this spring.
    fn tangential_stiffness_ratio(&self) -> f64;
    /// Whether this is the Hertz spring, whose contact radius `√(R*δ)` Mindlin's spring grows with.
    fn hertzian(&self) -> bool {
        false
    }
    /// Problems with its parameters.
    fn problems(&self) -> Problems {
        Vec::new()
    }
}

/// The damping of a spring: the dashpot coefficient that goes with a stiffness.
pub trait DampingModel: Copy + Send + Sync + 'static {
    /// Damping coefficient (N·s/m) of a spring of stiffness `spring` in contact `pair` (applied to
    /// the normal and the tangential spring alike).
    fn coefficient(&self, pair: &PairProperties, spring: Stiffness) -> f64;
    /// Problems with its parameters.
    fn problems(&self) -> Problems {
        Vec::new()
    }
}

/// The tangential spring (its history and the Coulomb cap are the shared [`super::resolve`]'s).
pub trait TangentialModel: Copy + Send + Sync + 'static {
    /// Tangential stiffness at overlap `overlap` with normal spring `normal`, whose stiffness there
    /// is `normal_stiffness`.
    fn stiffness<N: NormalModel>(
        &self,
        normal: &N,
        pair: &PairProperties,
        overlap: f64,
        normal_stiffness: Stiffness,
    ) -> Stiffness;
    /// Why it cannot go with the normal spring `normal`, if it cannot.
    fn unfit_with<N: NormalModel>(&self, _normal: &N) -> Option<&'static str> {
        None
    }
}

/// Rolling resistance: a moment against each disk's spin of `c · F_n · R` per contact, summed by
/// the contact stage (`super::super::rolling` applies it).
pub trait RollingModel: Copy + Send + Sync + 'static {
    /// The coefficient `c` for a contact class whose material gives rolling friction `rolling_friction`.
    fn coefficient(&self, rolling_friction: f64) -> f64;
}
