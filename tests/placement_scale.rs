//! The overlap check of placement files is O(N) in time and memory: 60 000 copies of one disk (every
//! pair overlapping: 1.8e9 pairs) are refused with the worst overlap and a count, and 60 000 disks on
//! a lattice pass, both without listing every pair (this took 2.2 GB and aborted before).

mod study_support;

use study_support::StudyDir;

/// A study of `count` disks of radius 2 mm read from `rows` (x, y) in a 1 m square box.
fn study(dir: &StudyDir, count: usize, rows: impl Iterator<Item = (f64, f64)>) -> std::path::PathBuf {
    let lines: Vec<String> = rows.map(|(x, y)| format!("{x},{y},0.002")).collect();
    dir.write("disks.csv", &format!("x,y,r\n{}\n", lines.join("\n")));
    dir.write(
        "heap.toml",
        &format!(
            "name = \"heap\"\n[scene]\nparticles.count = {count}\nparticles.radius = 0.002\ndomain.width = 1.0\n\
             domain.height = 1.0\nplacement.kind = \"file\"\nplacement.file = \"disks.csv\"\n"
        ),
    )
}

#[test]
fn sixty_thousand_coincident_disks_are_refused_with_a_count() {
    let dir = StudyDir::new("heap");
    let path = study(&dir, 60_000, (0..60_000).map(|_| (0.5, 0.5)));
    let errors = study_support::errors_at(&path);
    assert_eq!(errors.len(), 1, "{errors:?}");
    let text = errors[0].to_string();
    assert!(text.contains("disks 1 and 2 (rows 1 and 2 of the file) overlap by 2 radii"), "{text}");
    assert!(text.contains("at least") && text.contains("the disks are heaped"), "{text}");
}

#[test]
fn sixty_thousand_disks_on_a_lattice_pass() {
    let dir = StudyDir::new("lattice");
    let lattice = (0..60_000).map(|k| (0.003 + 0.0041 * (k % 240) as f64, 0.003 + 0.0041 * (k / 240) as f64));
    let plan = demsweep::study::load(&study(&dir, 60_000, lattice)).unwrap_or_else(|e| panic!("{e}"));
    assert!(plan.warnings.iter().all(|w| !w.to_string().contains("overlap")), "{:?}", plan.warnings);
}
