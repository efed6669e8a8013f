//! Linear spring-dashpot (Cundall-Strack) law: constant stiffness, viscous damping.

use super::{Coefficients, ContactLaw, PairProperties};

/// `F_ne = k_n δ`, damping `2 β √(k m*)` (β is the damping ratio, so EDEM's e-β relation is exact
/// here), tangential stiffness `k_t = ratio · k_n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearSpringDashpot {
    /// Normal stiffness (N/m); `None`: the Hertz secant stiffness at an overlap of 1 % of R*.
    pub normal_stiffness: Option<f64>,
    /// Tangential stiffness as a fraction of the normal stiffness.
    pub tangential_ratio: f64,
}

impl LinearSpringDashpot {
    #[inline]
    fn stiffness(&self, p: &PairProperties) -> f64 {
        // Hertz secant at δ = 0.01 R*: 4/3 E* √R* δ^{1/2} = 4/3 E* R* · 0.1.
        self.normal_stiffness.unwrap_or((4.0 / 3.0) * p.e_star * p.r_star * 0.1)
    }
}

impl ContactLaw for LinearSpringDashpot {
    #[inline]
    fn coefficients(&self, p: &PairProperties, overlap: f64) -> Coefficients {
        let kn = self.stiffness(p);
        let kt = self.tangential_ratio * kn;
        Coefficients {
            normal_force: kn * overlap,
            normal_damping: 2.0 * p.beta * (kn * p.m_star).sqrt(),
            tangential_stiffness: kt,
            tangential_damping: 2.0 * p.beta * (kt * p.m_star).sqrt(),
        }
    }

    #[inline]
    fn normal_elastic_energy(&self, p: &PairProperties, overlap: f64) -> f64 {
        0.5 * self.stiffness(p) * overlap * overlap
    }

    fn name(&self) -> &'static str {
        "linear"
    }
}
