//! A contact law composed of a normal spring, a damping and a tangential spring.

use super::law::{Coefficients, ContactLaw, PairProperties};
use super::sub_model::{DampingModel, NormalModel, TangentialModel};

/// The law of normal spring `N`, damping `D` (of both springs) and tangential spring `T`. The
/// composition is a type: each combination compiles to its own force loop, as a hand-written law
/// would.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Composed<N, D, T> {
    /// The normal spring.
    pub normal: N,
    /// The damping of both springs.
    pub damping: D,
    /// The tangential spring.
    pub tangential: T,
}

impl<N: NormalModel, D: DampingModel, T: TangentialModel> ContactLaw for Composed<N, D, T> {
    type State = N::State;

    #[inline]
    fn coefficients(&self, p: &PairProperties, overlap: f64, state: &mut N::State) -> Coefficients {
        let (normal_force, normal) = self.normal.load(p, overlap, state);
        let tangential = self.tangential.stiffness(&self.normal, p, overlap, normal);
        Coefficients {
            normal_force,
            normal_damping: self.damping.coefficient(p, normal),
            tangential_stiffness: tangential.value(),
            tangential_damping: self.damping.coefficient(p, tangential),
        }
    }

    #[inline]
    fn normal_elastic_energy(&self, p: &PairProperties, overlap: f64, state: &N::State) -> f64 {
        self.normal.elastic_energy(p, overlap, state)
    }
}
