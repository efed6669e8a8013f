//! Mindlin's tangential spring (eq 11 with the spec's fix).

use super::super::law::PairProperties;
use super::super::normal::contact_radius;
use super::super::sub_model::{NormalModel, Stiffness, TangentialModel};

/// `S_t = 8 G* √(R* δ)` (eq 11; **fix**: the normal overlap under the root, not the tangential
/// one): it grows with the Hertz contact radius, so it goes with the Hertz spring only.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MindlinTangential;

impl TangentialModel for MindlinTangential {
    #[inline(always)]
    fn stiffness<N: NormalModel>(&self, _: &N, p: &PairProperties, overlap: f64, _: Stiffness) -> Stiffness {
        Stiffness { scale: 8.0 * p.g_star, grade: contact_radius(p, overlap) }
    }

    fn unfit_with<N: NormalModel>(&self, normal: &N) -> Option<&'static str> {
        (!normal.hertzian()).then_some("grows with the Hertz contact radius and needs contact.normal = \"hertz\"")
    }
}
