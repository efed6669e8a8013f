//! The library's layers (README.md, "Development"; `src/lib.rs`): every `crate::<module>` path in
//! the code of `src/` goes down the layers, or sideways within a layer without a cycle.
//!
//! cli → workflow → tune / bench / report / plot → runner / stats / slurm → output → study → physics

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Top-level modules by layer, lowest first. The command-line front end (`src/cli*`, `src/main.rs`)
/// sits above them all and is not listed.
const LAYERS: [&[&str]; 6] = [
    &["physics"],
    &["study"],
    &["output"],
    &["runner", "stats", "slurm"],
    &["tune", "bench", "report", "plot", "export"],
    &["workflow"],
];

/// Imports that break the rule and are being removed. The test fails once one of them is gone, so
/// that the entry is deleted with it.
const BEING_REMOVED: [(&str, &str); 0] = [];

fn layer(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level module a file of `src/` belongs to (`src/output/writer.rs` → `output`).
fn owner(src: &Path, file: &Path) -> String {
    let first = file.strip_prefix(src).unwrap().components().next().unwrap();
    first.as_os_str().to_string_lossy().trim_end_matches(".rs").to_string()
}

/// The top-level modules named by `crate::<module>` in the code (comments left out) of `text`.
fn referenced(text: &str) -> BTreeSet<String> {
    let mut modules = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        for (at, _) in code.match_indices("crate::") {
            let rest = &code[at + "crate::".len()..];
            let name: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            if !name.is_empty() {
                modules.insert(name);
            }
        }
    }
    modules
}

/// Module → the other top-level modules it references.
fn import_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        let module = owner(&src, &file);
        let text = std::fs::read_to_string(&file).unwrap();
        let targets = graph.entry(module.clone()).or_default();
        targets.extend(referenced(&text).into_iter().filter(|m| *m != module));
    }
    graph
}

/// Whether `to` is reachable from `from` in `graph`.
fn reaches(graph: &BTreeMap<String, BTreeSet<String>>, from: &str, to: &str) -> bool {
    let (mut seen, mut stack) = (BTreeSet::new(), vec![from.to_string()]);
    while let Some(module) = stack.pop() {
        if module == to {
            return true;
        }
        if seen.insert(module.clone()) {
            stack.extend(graph.get(&module).into_iter().flatten().cloned());
        }
    }
    false
}

#[test]
fn imports_go_down_the_layers_without_cycles() {
    let mut graph = import_graph();
    let mut problems = Vec::new();
    for (module, target) in BEING_REMOVED {
        if !graph.get_mut(module).is_some_and(|targets| targets.remove(target)) {
            problems.push(format!("{module} → {target} is gone: delete it from BEING_REMOVED"));
        }
    }
    for (module, targets) in &graph {
        let Some(from) = layer(module) else { continue };
        for target in targets {
            match layer(target) {
                None => problems.push(format!("{module} → {target}: `{target}` is in no layer")),
                Some(to) if to > from => problems.push(format!("{module} → {target}: up the layers")),
                Some(to) if to == from && reaches(&graph, target, module) => {
                    problems.push(format!("{module} → {target}: a cycle within the layer"))
                }
                Some(_) => {}
            }
        }
    }
    assert!(problems.is_empty(), "layering broken:\n  {}", problems.join("\n  "));
}

#[test]
fn every_top_level_module_has_a_layer() {
    let graph = import_graph();
    let cli = ["cli", "main", "lib"];
    let unplaced: Vec<&String> = graph.keys().filter(|m| layer(m).is_none() && !cli.contains(&m.as_str())).collect();
    assert!(unplaced.is_empty(), "modules in no layer: {unplaced:?}");
}

#[test]
fn the_scan_sees_an_upward_import_and_a_cycle() {
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("output", referenced("use crate::stats::points::Points; // crate::plot in a comment")),
        ("stats", referenced("let t = crate::output::table::short_float(x);")),
    ]
    .into_iter()
    .map(|(m, t)| (m.to_string(), t))
    .collect();
    assert_eq!(graph["output"], BTreeSet::from(["stats".to_string()]));
    assert!(layer("output") < layer("stats"), "output → stats runs up");
    assert!(reaches(&graph, "stats", "output") && reaches(&graph, "output", "stats"));
}
