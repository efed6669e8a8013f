//! The wall-time estimate `plan` prints for a study or a tune file.

/// Single-threaded cost of one particle-step assumed by the wall-time estimate (s).
pub const SECONDS_PER_PARTICLE_STEP: f64 = 50e-9;

/// Seconds in words: `42 s`, `12.5 min`, `3.2 h`.
pub fn duration(seconds: f64) -> String {
    match seconds {
        s if s < 10.0 => format!("{s:.1} s"),
        s if s < 90.0 => format!("{s:.0} s"),
        s if s < 5400.0 => format!("{:.1} min", s / 60.0),
        s => format!("{:.1} h", s / 3600.0),
    }
}
