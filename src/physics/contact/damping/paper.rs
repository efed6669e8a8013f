//! The paper's damping (eqs 7, 12).

use super::super::law::PairProperties;
use super::super::sub_model::{DampingModel, Stiffness};
use super::beta::scaled_by_beta;

/// `2·√(5/6)`: the paper's damping prefactor (eqs 7 and 12).
const DAMPING_PREFACTOR: f64 = 1.825_741_858_350_553_8;

/// `c = 2√(5/6) β √(S m*)` for a spring of stiffness `S` (EDEM's; Tsuji's form with `α = √5 β` for
/// a Hertz spring).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PaperDamping;

impl DampingModel for PaperDamping {
    #[inline(always)]
    fn coefficient(&self, p: &PairProperties, spring: Stiffness) -> f64 {
        scaled_by_beta(DAMPING_PREFACTOR, p, spring)
    }
}
