//! The environment variables the runner reads: from how many disks a run uses the threads it is
//! given, and which vector instructions the engine's hot loops run in.

use super::RunnerError;
use crate::physics::parallel::PARALLEL_MIN_DISKS;
use crate::physics::vector::{self, Width};

/// The environment variable that sets from how many disks a run uses the threads it is given
/// (default [`PARALLEL_MIN_DISKS`]): for tests and measurements of small scenes.
pub const PARALLEL_MIN_DISKS_VARIABLE: &str = "DEMSWEEP_PARALLEL_MIN_DISKS";

/// The value of [`PARALLEL_MIN_DISKS_VARIABLE`], or the default.
pub fn parallel_min_disks() -> Result<usize, RunnerError> {
    std::env::var(PARALLEL_MIN_DISKS_VARIABLE).map_or(Ok(PARALLEL_MIN_DISKS), |text| min_disks_in(&text))
}

/// The disk count `text` (a value of [`PARALLEL_MIN_DISKS_VARIABLE`]) holds.
fn min_disks_in(text: &str) -> Result<usize, RunnerError> {
    text.trim().parse().map_err(|_| RunnerError::Environment {
        variable: PARALLEL_MIN_DISKS_VARIABLE,
        value: text.into(),
        expected: "a whole number of disks".into(),
    })
}

/// The environment variable that names the vector instructions the engine's hot loops run in
/// (`baseline`, `avx2`, `avx512`; default: the widest this CPU runs well, see
/// `physics::vector::width`): for measurements. Results are the same bits in every width.
pub const VECTOR_WIDTH_VARIABLE: &str = "DEMSWEEP_VECTOR";

/// Sets the width named by [`VECTOR_WIDTH_VARIABLE`], if it is set.
pub fn use_vector_width() -> Result<(), RunnerError> {
    if let Ok(text) = std::env::var(VECTOR_WIDTH_VARIABLE) {
        vector::use_width(width_in(&text)?);
    }
    Ok(())
}

/// The width `text` (a value of [`VECTOR_WIDTH_VARIABLE`]) names.
fn width_in(text: &str) -> Result<Width, RunnerError> {
    Width::parse(text.trim()).ok_or_else(|| {
        let names: Vec<_> = Width::ALL.iter().map(|w| w.name()).collect();
        RunnerError::Environment {
            variable: VECTOR_WIDTH_VARIABLE,
            value: text.into(),
            expected: format!("one of {}", names.join(", ")),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn environment_values_are_read_or_refused_as_typed_errors() {
        assert_eq!(min_disks_in(" 500 "), Ok(500));
        assert_eq!(width_in("avx2"), Ok(Width::Avx2));
        let refused = RunnerError::Environment {
            variable: VECTOR_WIDTH_VARIABLE,
            value: "avx1024".into(),
            expected: "one of baseline, avx2, avx512".into(),
        };
        assert_eq!(width_in("avx1024"), Err(refused));
        match min_disks_in("many") {
            Err(RunnerError::Environment { variable, value, .. }) => {
                assert_eq!((variable, value.as_str()), (PARALLEL_MIN_DISKS_VARIABLE, "many"))
            }
            other => panic!("{other:?}"),
        }
    }
}
