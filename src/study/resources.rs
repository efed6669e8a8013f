//! Will a study fit the machine? The memory one run's state needs against the machine's memory, and
//! the size of a study's results against the free space of the output folder. Both are estimates
//! made before anything runs; where the machine cannot say (no `/proc/meminfo`, no `statvfs`) the
//! check is skipped.

use std::path::Path;

use super::{OutputOptions, Plan};
use crate::physics::SceneConfig;
use crate::physics::quantity;

/// Memory one disk takes while it is simulated (bytes): its state and forces (14 arrays of `f64`),
/// the integrator's previous accelerations (3), its initial state (6, held by the plan and the run),
/// its share of the Verlet list (about four pairs, each written twice while the list is rebuilt, with
/// its spring) and of the cell grid.
pub const BYTES_PER_DISK: u64 = 800;

/// Bytes of one disk in a recorded state (final state or frame): 7 `f64` columns.
const SNAPSHOT_BYTES_PER_DISK: u64 = 7 * 8;

/// Estimated memory one run of `scene` needs (bytes), by what takes it: the disks' simulation state
/// and final state, the recorded frames and the histories, each with the scene key that sets it.
fn run_memory_parts(scene: &SceneConfig) -> [(&'static str, u64); 3] {
    let disks = scene.particles.count as u64;
    let frames = frame_count(scene).saturating_mul(disks).saturating_mul(SNAPSHOT_BYTES_PER_DISK);
    [
        ("particles.count", disks.saturating_mul(BYTES_PER_DISK + SNAPSHOT_BYTES_PER_DISK)),
        (if scene.run.frame_interval.is_some() { "run.frame_interval" } else { "run.frame_times" }, frames),
        ("run.sample_interval", samples(scene).saturating_mul(quantity::history_bytes_per_sample())),
    ]
}

/// Estimated memory one run of `scene` needs (bytes): the disks' simulation state plus what it
/// records (histories, final state and frames) until it is written.
pub fn run_memory(scene: &SceneConfig) -> u64 {
    run_memory_parts(scene).iter().fold(0, |sum, (_, part)| sum.saturating_add(*part))
}

/// The largest description of a datatype a results file can hold, in bytes: HDF5 keeps it in one
/// object header message, whose size field has 16 bits.
const DATATYPE_LIMIT: usize = 65_535;

/// Why the results file cannot store the end times of `scene`'s stages, if it cannot: they are one
/// row of float fields named by the stages (`stage_end_times`), whose description (8 bytes, then a
/// field's name, a NUL, its offset in the fewest bytes that hold the row's size and an 8-byte
/// float's 20-byte description per stage) must fit `DATATYPE_LIMIT`. The key is `stages`.
pub fn stage_table_problem(scene: &SceneConfig) -> Option<(&'static str, String)> {
    let count = scene.stages.len();
    let offset = (1..8).find(|bytes| (count * 8) >> (8 * bytes) == 0).unwrap_or(8);
    let size = 8 + scene.stages.iter().map(|s| s.name.len() + 1 + offset + 20).sum::<usize>();
    (size > DATATYPE_LIMIT).then(|| {
        let reason = format!(
            "{count} stages need {size} bytes to describe their end times in the results file, past HDF5's \
             limit of {DATATYPE_LIMIT} bytes for one datatype: use fewer stages or shorter stage names"
        );
        ("stages", reason)
    })
}

/// Why a run of `scene` cannot fit in this machine's memory, if it cannot, with the scene key that
/// takes most of it (`None` also where the machine's memory is unknown).
pub fn memory_problem(scene: &SceneConfig) -> Option<(&'static str, String)> {
    let need = run_memory(scene);
    let total = memory_total()?;
    let (key, _) = run_memory_parts(scene).into_iter().max_by_key(|(_, part)| *part)?;
    (need > total).then(|| {
        let (what, fix) = match key {
            "particles.count" => (format!("{} disks", scene.particles.count), "lower particles.count"),
            "run.sample_interval" => (format!("{} history samples", samples(scene)), "raise run.sample_interval"),
            "run.frame_interval" => (format!("{} frames", frame_count(scene)), "raise run.frame_interval"),
            _ => (format!("{} frames", frame_count(scene)), "list fewer run.frame_times"),
        };
        let reason = format!(
            "{what} need about {} of memory to simulate (about {} bytes per disk), but this machine has {} \
             (MemTotal in /proc/meminfo): {fix} or run it on a larger machine",
            bytes(need),
            need / (scene.particles.count as u64).max(1),
            bytes(total)
        );
        (key, reason)
    })
}

/// Estimated size of one run's results (bytes) with `output`: histories, final state and frames,
/// uncompressed (compression saves about a quarter).
pub fn run_output(scene: &SceneConfig, output: &OutputOptions) -> u64 {
    let disks = scene.particles.count as u64;
    let histories = if output.histories { samples(scene) * quantity::history_bytes_per_sample() } else { 0 };
    let finals = if output.final_states { disks * SNAPSHOT_BYTES_PER_DISK } else { 0 };
    let frames = if output.frames { frame_count(scene) * disks * SNAPSHOT_BYTES_PER_DISK } else { 0 };
    histories + finals + frames
}

/// A warning when the plan's results would not fit in the free space of `out_dir` (or of its
/// nearest existing parent folder); `None` when they fit or the free space is unknown.
pub fn output_space_warning(plan: &Plan, out_dir: &Path) -> Option<String> {
    let need: u64 = plan.runs.iter().map(|r| run_output(&r.scene, &plan.output)).sum();
    let existing = out_dir.ancestors().find(|p| p.is_dir()).unwrap_or(Path::new("."));
    let free = free_space(existing)?;
    (need > free).then(|| {
        format!(
            "{}: the results of {} runs need about {} (histories, final states and frames, uncompressed; \
             compression saves about a quarter), but {} has {} free",
            plan.study_path.display(),
            plan.runs.len(),
            bytes(need),
            std::path::absolute(existing).unwrap_or_else(|_| existing.to_path_buf()).display(),
            bytes(free)
        )
    })
}

/// History samples of a run: one at the start and one per sample interval (at most one per step
/// of a fixed time step; a relative one is not resolved here).
fn samples(scene: &SceneConfig) -> u64 {
    let steps = scene.integrator.fixed_time_step().map_or(f64::INFINITY, |dt| scene.total_steps(dt) as f64);
    (scene.run.duration / scene.run.sample_interval).floor().min(steps) as u64 + 1
}

/// Frames a run records: its frame times within the duration plus one per frame interval.
fn frame_count(scene: &SceneConfig) -> u64 {
    let run = &scene.run;
    let listed = run.frame_times.iter().filter(|t| **t <= run.duration).count() as u64;
    let periodic = run.frame_interval.map_or(0.0, |i| (run.duration / i).floor());
    listed + periodic.min(u32::MAX as f64) as u64
}

/// The machine's physical memory (bytes), from `/proc/meminfo`.
fn memory_total() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Free space available to this user in the file system holding `dir` (bytes).
#[cfg(unix)]
#[allow(unsafe_code)] // one libc call; std has no free-space query
fn free_space(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let path = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    let mut stats = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: `path` is a NUL-terminated string and `stats` is a valid place for statvfs to fill.
    if unsafe { libc::statvfs(path.as_ptr(), stats.as_mut_ptr()) } != 0 {
        return None;
    }
    // SAFETY: statvfs returned 0, so it filled `stats`.
    let stats = unsafe { stats.assume_init() };
    #[allow(clippy::useless_conversion)] // the field types differ between platforms
    Some(u64::from(stats.f_bavail).saturating_mul(u64::from(stats.f_frsize)))
}

#[cfg(not(unix))]
fn free_space(_dir: &Path) -> Option<u64> {
    None
}

/// Bytes in words: `512 B`, `3.2 MB`, `80.0 TB` (powers of 1000).
pub fn bytes(n: u64) -> String {
    const UNITS: [&str; 6] = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut value = n as f64;
    let mut unit = 0;
    while value >= 1000.0 && unit + 1 < UNITS.len() {
        value /= 1000.0;
        unit += 1;
    }
    if unit == 0 { format!("{n} B") } else { format!("{value:.1} {}", UNITS[unit]) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_in_decimal_units() {
        assert_eq!(bytes(512), "512 B");
        assert_eq!(bytes(3_200_000), "3.2 MB");
        assert_eq!(bytes(80_000_000_000_000), "80.0 TB");
    }

    #[test]
    fn output_estimate_counts_histories_states_and_frames() {
        let mut scene = SceneConfig::default();
        scene.run.frame_times = vec![0.0, 1.0, 99.0];
        let all = OutputOptions::default();
        let samples = 1501;
        // A sample: 11 `f64` series and a `u32` contact count (92 bytes).
        assert_eq!(run_output(&scene, &all), samples * 92 + 3 * 300 * 56);
        let none = OutputOptions { histories: false, final_states: false, frames: false };
        assert_eq!(run_output(&scene, &none), 0);
        assert_eq!(run_memory(&scene), 300 * (800 + 3 * 56) + samples * 92);
    }
}
