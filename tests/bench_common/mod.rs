//! Shared helpers of the benchmark tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// A fresh empty folder under the system's temporary folder, unique per test.
pub fn fresh_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("demsweep-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Lines of a CSV file: header, then rows.
pub fn csv_lines(path: &std::path::Path) -> Vec<String> {
    std::fs::read_to_string(path).unwrap().lines().map(String::from).collect()
}

/// The units of a CSV file's columns as its CSVW sidecar states them (empty where none).
pub fn units(path: &std::path::Path) -> Vec<String> {
    let sidecar = format!("{}-metadata.json", path.display());
    let meta: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(sidecar).unwrap()).unwrap();
    let columns = meta["tableSchema"]["columns"].as_array().unwrap().iter();
    columns.map(|c| c["schema:unitText"].as_str().unwrap_or("").to_string()).collect()
}
