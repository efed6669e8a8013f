//! The root attributes of a results file: which study (and shard) it holds, written once at creation.

use std::collections::HashMap;
use std::fmt;
use std::str::FromStr;
use std::time::{SystemTime, UNIX_EPOCH};

use hdf5_pure::AttrValue;

/// Shard `index` of `count` (1-based: `1/4` … `4/4`), as given to `--shard K/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShardSpec {
    /// Which shard, 1 ≤ index ≤ count.
    pub index: usize,
    /// How many shards the study is split into.
    pub count: usize,
}

impl fmt::Display for ShardSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for ShardSpec {
    type Err = String;

    /// Parses `K/N` with 1 ≤ K ≤ N.
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("shard must be K/N with 1 <= K <= N (e.g. 2/8), got `{s}`");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = k.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Self { index, count })
    }
}

/// A shard's identity and the plan indices assigned to it.
#[derive(Clone, Debug, PartialEq)]
pub struct ShardInfo {
    /// Which shard.
    pub spec: ShardSpec,
    /// Plan indices of the runs this shard runs, ascending.
    pub runs: Vec<usize>,
}

/// What a results file holds (its root attributes).
#[derive(Clone, Debug, PartialEq)]
pub struct FileHeader {
    /// Study name.
    pub study_name: String,
    /// The study file's text, verbatim.
    pub study_text: String,
    /// The study fingerprint: results of one study carry the same one.
    pub fingerprint: String,
    /// demsweep version that created the file.
    pub demsweep_version: String,
    /// Creation time, UTC ISO 8601.
    pub created: String,
    /// Number of runs in the whole plan.
    pub planned_runs: usize,
    /// Set for a shard file.
    pub shard: Option<ShardInfo>,
}

const STUDY_NAME: &str = "study_name";
const STUDY_TEXT: &str = "study_text";
const FINGERPRINT: &str = "fingerprint";
const VERSION: &str = "demsweep_version";
const CREATED: &str = "created";
const PLANNED_RUNS: &str = "planned_runs";
const SHARD: &str = "shard";
const SHARD_RUNS: &str = "shard_runs";

impl FileHeader {
    /// The root attributes (at most eight, so they stay in the root's object header).
    pub fn to_attrs(&self) -> Vec<(&'static str, AttrValue)> {
        let mut attrs = vec![
            (STUDY_NAME, AttrValue::String(self.study_name.clone())),
            (STUDY_TEXT, AttrValue::String(self.study_text.clone())),
            (FINGERPRINT, AttrValue::String(self.fingerprint.clone())),
            (VERSION, AttrValue::String(self.demsweep_version.clone())),
            (CREATED, AttrValue::String(self.created.clone())),
            (PLANNED_RUNS, AttrValue::I64(self.planned_runs as i64)),
        ];
        if let Some(shard) = &self.shard {
            attrs.push((SHARD, AttrValue::String(shard.spec.to_string())));
            attrs.push((SHARD_RUNS, AttrValue::I64Array(shard.runs.iter().map(|&i| i as i64).collect())));
        }
        attrs
    }

    /// Reads the header back; the error names the missing or malformed attribute.
    pub fn from_attrs(attrs: &HashMap<String, AttrValue>) -> Result<Self, String> {
        let text = |name: &str| {
            attrs.get(name).and_then(AttrValue::as_str).map(str::to_string).ok_or(format!("no `{name}` root attribute"))
        };
        let planned = attrs.get(PLANNED_RUNS).and_then(AttrValue::as_i64).ok_or("no `planned_runs` root attribute")?;
        let shard = match attrs.get(SHARD).and_then(AttrValue::as_str) {
            None => None,
            Some(spec) => {
                let runs =
                    attrs.get(SHARD_RUNS).and_then(AttrValue::to_i64s).ok_or("no `shard_runs` root attribute")?;
                Some(ShardInfo { spec: spec.parse()?, runs: runs.iter().map(|&i| i as usize).collect() })
            }
        };
        Ok(Self {
            study_name: text(STUDY_NAME)
                .and_then(|name| crate::study::name::check_name(&name).map(|()| name).map_err(|e| e.to_string()))?,
            study_text: text(STUDY_TEXT)?,
            fingerprint: text(FINGERPRINT)?,
            demsweep_version: text(VERSION)?,
            created: text(CREATED)?,
            planned_runs: planned as usize,
            shard,
        })
    }
}

/// The current time as UTC ISO 8601 (`2024-05-01T12:34:56Z`).
pub fn utc_now() -> String {
    let secs = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    utc_iso8601(secs)
}

/// Seconds since the Unix epoch as UTC ISO 8601 (proleptic Gregorian calendar).
pub fn utc_iso8601(secs: u64) -> String {
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Civil-from-days (H. Hinnant): shift the epoch to 0000-03-01 so leap days end each era's year.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z", rem / 3600, rem / 60 % 60, rem % 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iso8601_matches_known_dates() {
        assert_eq!(utc_iso8601(0), "1970-01-01T00:00:00Z");
        assert_eq!(utc_iso8601(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(utc_iso8601(1_709_251_199), "2024-02-29T23:59:59Z");
        assert_eq!(utc_iso8601(4_102_444_800), "2100-01-01T00:00:00Z");
    }

    #[test]
    fn shard_spec_parses_and_rejects() {
        assert_eq!("2/8".parse::<ShardSpec>(), Ok(ShardSpec { index: 2, count: 8 }));
        for bad in ["0/3", "4/3", "3", "a/b", "1/0"] {
            assert!(bad.parse::<ShardSpec>().unwrap_err().contains("K/N"), "{bad}");
        }
    }
}
