//! What `check` says of dropped placement: how far up the box each distinct pile reaches.

use demsweep::physics::config::PlacementKind;
use demsweep::physics::number::significant;
use demsweep::physics::placement::{self, Fill};
use demsweep::study::Plan;

/// One line per distinct box, disks and dropped placement of the plan (the seed left out): the
/// first such run's pile, its top as a share of `domain.height` and the area its disks fill below it.
pub fn fill_notes(plan: &Plan) -> Vec<String> {
    let mut seen = Vec::new();
    let mut notes = Vec::new();
    for run in plan.runs.iter().filter(|r| r.scene.placement.kind == PlacementKind::Dropped) {
        let s = &run.scene;
        let mut setup = (s.domain.clone(), s.particles.clone(), s.placement.clone());
        setup.2.seed = 0;
        if seen.contains(&setup) {
            continue;
        }
        seen.push(setup);
        let Ok(disks) = placement::generate(s) else { continue };
        let fill = Fill::of(s, &disks);
        notes.push(format!(
            "placement.kind = \"dropped\": {} disks rest up to {} m, {} % of domain.height ({} m), filling {} of \
             the box's area below that (placement seed {}, run {})",
            fill.count,
            significant(fill.top, 4),
            significant(100.0 * fill.height_fraction, 3),
            significant(s.domain.height, 6),
            significant(fill.area_fraction, 3),
            s.placement.seed,
            run.id
        ));
    }
    notes
}
