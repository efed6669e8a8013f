//! The cheap corner: every lever at the end of its range that its time step and the measured settle
//! times say is cheaper.

use super::context::{Context, Flow};
use crate::tune::design;
use crate::tune::model::{Evaluator, Origin, TuneError};

/// A lever whose end moves a setting's predicted cost by less than this fraction leaves the cheap
/// corner at the centre of its range.
const CORNER_SLOPE: f64 = 0.05;

/// Most tries of the cheap corner, each nearer the centre than the one predicted invalid (and most
/// halvings of one lever's distance to the centre within a try).
const CORNER_TRIES: usize = 4;

/// The step: the cheap corner proposed ([`Context::propose_corner`]) and its first seeds run when
/// they fit the spend limit with room to verify it.
pub(super) fn step<E: Evaluator>(cx: &mut Context<'_, E>) -> Result<Flow, TuneError> {
    cx.corner = cx.propose_corner();
    if let Some(k) = cx.corner {
        cx.run_first(k)?;
    }
    Ok(Flow::Next)
}

impl<E: Evaluator> Context<'_, E> {
    /// The point a DEM engineer tries first: every lever at the end of its range that the predicted
    /// time step (screened at both ends, the other levers at the centre) and the measured settle
    /// times (else the lever's dissipation,
    /// [`SearchConfig::dissipation`](crate::tune::model::SearchConfig::dissipation)) say is cheaper
    /// ([`CORNER_SLOPE`]: a lever that moves neither stays at the reference's value,
    /// [`SearchConfig::home`](crate::tune::model::SearchConfig::home)); while predicted invalid,
    /// nearer the centre ([`Self::nearer_corner`]). Returns the runnable candidate, if one is new.
    /// A list lever (the integrator scheme) takes the value whose own corner is cheapest
    /// ([`Self::corner_choice`]).
    fn propose_corner(&mut self) -> Option<usize> {
        let mut corner = self.corner_choice();
        for _ in 0..CORNER_TRIES {
            let before = self.result.candidates.len();
            if let Some(k) = self.propose(&corner, Origin::Initial) {
                return Some(k);
            }
            if self.result.candidates.len() == before {
                return None;
            }
            corner = self.nearer_corner(&corner);
        }
        None
    }

    /// The next try after `corner` was predicted invalid: the cheapest predicted valid setting with
    /// one lever moved towards the centre (halving its distance up to [`CORNER_TRIES`] times; a
    /// restitution raised where it is the damping that breaks the step's limit keeps the step),
    /// else every lever halfway nearer.
    fn nearer_corner(&mut self, corner: &[f64]) -> Vec<f64> {
        let mut all = corner.to_vec();
        halfway_to_centre(&mut all);
        let mut best: Option<(Vec<f64>, f64)> = None;
        for d in 0..corner.len() {
            let mut one = corner.to_vec();
            for _ in 0..CORNER_TRIES {
                halfway_to_centre(&mut one[d..=d]);
                let screen = self.evaluator.screen(&design::snap(&one, &self.config.levels), None);
                if self.predicted_valid(&screen) {
                    let cost = screen.relative_cost.unwrap_or(f64::INFINITY);
                    if best.as_ref().is_none_or(|(_, c)| cost < *c) {
                        best = Some((one.clone(), cost));
                    }
                    break;
                }
            }
        }
        best.map_or(all, |(one, _)| one)
    }

    /// The cheap corner as first tried (see [`Self::propose_corner`]), before any is found invalid.
    fn corner_start(&mut self) -> Vec<f64> {
        let time_step = self.time_step_slopes();
        let settle = self.settle_fit().map(|fit| fit[1..].to_vec());
        (0..self.config.dims)
            .map(|d| {
                let settle = settle.as_ref().map_or(-2.0 * CORNER_SLOPE * self.config.dissipation[d], |s| s[d]);
                match time_step[d] + settle {
                    slope if slope.abs() < CORNER_SLOPE => self.config.home.get(d).copied().flatten().unwrap_or(0.5),
                    slope if slope < 0.0 => 1.0,
                    _ => 0.0,
                }
            })
            .collect()
    }

    /// The predicted cost of the cheap corner's time step, screened without proposing it (nearer
    /// the centre while predicted invalid, as [`Self::propose_corner`] does).
    pub(super) fn corner_cost(&mut self) -> Option<f64> {
        let corner = self.corner_choice();
        self.valid_corner_cost(corner)
    }

    /// The cheap corner's first try: [`Self::corner_start`], or the same with one list lever at
    /// another of its values (another integrator scheme, whose stable step differs) where that
    /// corner, once predicted valid, has the cheaper time step: each value's corner is priced at
    /// its own step. The first tried wins a tie.
    fn corner_choice(&mut self) -> Vec<f64> {
        let start = self.corner_start();
        let mut best = (start.clone(), self.valid_corner_cost(start.clone()).unwrap_or(f64::INFINITY));
        for other in list_values(&start, &self.config.levels) {
            if let Some(cost) = self.valid_corner_cost(other.clone())
                && cost < best.1
            {
                best = (other, cost);
            }
        }
        best.0
    }

    /// The predicted cost of the time step `corner` resolves to, moved nearer the centre while
    /// predicted invalid (at most [`CORNER_TRIES`] times); None when it cannot start or stays invalid.
    fn valid_corner_cost(&mut self, mut corner: Vec<f64>) -> Option<f64> {
        for _ in 0..CORNER_TRIES {
            let screen = self.evaluator.screen(&design::snap(&corner, &self.config.levels), None);
            if screen.predicted.is_err() {
                return None;
            }
            if self.predicted_valid(&screen) {
                return screen.relative_cost;
            }
            corner = self.nearer_corner(&corner);
        }
        None
    }
}

/// `point` with one list lever (`levels[d]` of `Some(n)`) moved to each of its other values' bin
/// centres, one list lever at a time.
fn list_values(point: &[f64], levels: &[Option<usize>]) -> Vec<Vec<f64>> {
    let own = design::snap(point, levels);
    let mut others = Vec::new();
    for (d, level) in levels.iter().enumerate() {
        let Some(n) = *level else { continue };
        for bin in 0..n {
            let centre = (bin as f64 + 0.5) / n as f64;
            if centre != own[d] {
                let mut other = point.to_vec();
                other[d] = centre;
                others.push(other);
            }
        }
    }
    others
}

/// Moves a point of the lever space halfway to the centre of every lever's range.
fn halfway_to_centre(point: &mut [f64]) {
    point.iter_mut().for_each(|x| *x = 0.5 + 0.5 * (*x - 0.5));
}
