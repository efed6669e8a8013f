//! Whether the kept metrics can be measured on the reference's pile, said before anything runs: a
//! kept metric undefined on the reference's runs gives no margin, and the tune stops after them.

use super::spec::TuneSpec;
use super::validity::disks_of;
use crate::physics::number::short;
use crate::physics::pile::{PREDICTED_PACKING, predicted_interior_window};
use crate::physics::quantity::PACKING_FRACTION_INTERIOR;

/// A warning (`keep.<metric>: …`) for each kept metric predicted undefined, or resting on a few
/// disks, on the reference's pile: the interior packing fraction where the predicted interior
/// window is under two largest diameters tall.
pub fn kept_metric_warnings(spec: &TuneSpec) -> Vec<String> {
    let metric = PACKING_FRACTION_INTERIOR.name;
    if !spec.keep.iter().any(|k| k.metric == metric) {
        return Vec::new();
    }
    let Ok(disks) = disks_of(&spec.reference, spec.initial.as_deref().map(Vec::as_slice)) else { return Vec::new() };
    let diameter = 2.0 * disks.iter().map(|d| d.r).fold(0.0, f64::max);
    let (depth, window) = predicted_interior_window(disks.iter().map(|d| d.r), spec.reference.domain.width);
    if window >= diameter {
        return Vec::new();
    }
    let what = if window > 0.0 {
        format!(
            "predicted {} m tall, under one largest diameter: {metric} rests on a few disks, and is undefined (NaN) \
             on seeds whose pile settles lower",
            short(window)
        )
    } else {
        format!("predicted empty: {metric} is undefined (NaN)")
    };
    vec![format!(
        "keep.{metric}: the pile is predicted {} m deep ({} largest diameters: the disks' area over the box width at \
         a packing of {PREDICTED_PACKING}), and the interior window leaves out 2 largest diameters ({} m) above the \
         floor and below the highest disk top (about one above that depth), so it is {what}; keep packing_fraction \
         or surface_height instead, or deepen the pile (more disks or a narrower box)",
        short(depth),
        short(depth / diameter),
        short(2.0 * diameter),
    )]
}
