//! The library's layers (docs/development.md; `src/lib.rs`): every `crate::<module>` path in
//! the code of `src/` goes down the layers, or sideways within a layer without a cycle.
//!
//! cli → workflow → tune / bench / report / plot → runner / stats / slurm → output → study → physics
//!
//! The names of the pile metrics are written once, in their table (`src/physics/quantity.rs`): the
//! code of `src/` elsewhere reaches them through the table's entries, never as string literals.

use std::collections::{BTreeMap, BTreeSet};

use demsweep::physics::quantity::{PILE_METRICS, SETTLE_TIME};
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

/// A module path from the crate root (`["output", "writer"]` for `src/output/writer.rs`).
type ModulePath = Vec<String>;

/// Every file of `src/` by its module path (`src/lib.rs` is the root, `mod.rs` its folder's module).
fn module_files() -> BTreeMap<ModulePath, PathBuf> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files
        .into_iter()
        .filter(|f| !f.ends_with("main.rs"))
        .map(|file| {
            let mut path: ModulePath = file
                .strip_prefix(&src)
                .unwrap()
                .components()
                .map(|c| c.as_os_str().to_string_lossy().trim_end_matches(".rs").to_string())
                .collect();
            if path.last().is_some_and(|last| last == "mod" || last == "lib") {
                path.pop();
            }
            (path, file)
        })
        .collect()
}

/// The code of a file: comments and the `#[cfg(test)]` module at its end left out (tests may
/// reach anything they test).
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]\nmod tests").next().unwrap_or(text);
    text.lines().map(|line| line.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// The paths of a use tree or path expression starting at `text` (`a::{b, c::D}` → `a::b`, `a::c::D`).
fn paths_at(text: &str) -> Vec<Vec<String>> {
    let mut prefix = Vec::new();
    let mut rest = text;
    loop {
        let name: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
        if name.is_empty() {
            break;
        }
        prefix.push(name.clone());
        rest = &rest[name.len()..];
        let Some(after) = rest.strip_prefix("::") else { break };
        rest = after;
        if let Some(group) = rest.strip_prefix('{') {
            let (mut depth, mut start, mut paths) = (0, 0, Vec::new());
            for (at, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        paths.extend(paths_at(group[start..at].trim()));
                        break;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        paths.extend(paths_at(group[start..at].trim()));
                        start = at + 1;
                    }
                    _ => {}
                }
            }
            return paths.into_iter().map(|p: Vec<String>| [prefix.clone(), p].concat()).collect();
        }
    }
    vec![prefix]
}

/// The module paths named in `code` of module `module`: `crate::…`, `super::…`, `self::…`, and
/// `use child::…` of its own child modules; `pub use` re-exports left out (a facade, not a use).
fn named_paths(code: &str, module: &[String], files: &BTreeMap<ModulePath, PathBuf>) -> Vec<ModulePath> {
    let mut found = Vec::new();
    for statement in code.split(';') {
        let statement = statement.trim_start();
        if statement.starts_with("pub use") || statement.starts_with("pub(crate) use") {
            continue;
        }
        if let Some(tree) = statement.strip_prefix("use ") {
            let first: String = tree.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            if files.contains_key(&[module, &[first]].concat()) {
                found.extend(paths_at(tree).into_iter().map(|p| [module.to_vec(), p].concat()));
            }
        }
        found.extend(child_paths(statement, module, files));
        for start in ["crate::", "super::", "self::"] {
            for (at, _) in statement.match_indices(start) {
                let boundary = statement[..at].chars().last().is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_'));
                if !boundary {
                    continue;
                }
                let base: ModulePath = match start {
                    "crate::" => Vec::new(),
                    "super::" => module[..module.len().saturating_sub(1)].to_vec(),
                    _ => module.to_vec(),
                };
                let tree = &statement[at + start.len()..];
                found.extend(paths_at(tree).into_iter().map(|p| [base.clone(), p].concat()));
            }
        }
    }
    found
}

/// The paths in `statement` that start with a bare child module of `module` (`summary::write_csv(…)`
/// in `output/mod.rs`): a name right after no `::`, `.` or identifier character, followed by `::`.
fn child_paths(statement: &str, module: &[String], files: &BTreeMap<ModulePath, PathBuf>) -> Vec<ModulePath> {
    let mut found = Vec::new();
    for (at, _) in statement.match_indices("::") {
        let before = &statement[..at];
        let name_start = before.rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
        let name = &before[name_start..];
        let preceded = before[..name_start].trim_end().chars().last();
        if name.is_empty() || preceded.is_some_and(|c| c == ':' || c == '.' || c.is_ascii_alphanumeric()) {
            continue;
        }
        if !files.contains_key(&[module, &[name.to_string()]].concat()) {
            continue;
        }
        found.extend(paths_at(&statement[name_start..]).into_iter().map(|p| [module.to_vec(), p].concat()));
    }
    found
}

/// The file an item path lands in: the longest prefix that is a file, following that file's
/// `pub use` re-exports of the next name.
fn resolve(path: &[String], files: &BTreeMap<ModulePath, PathBuf>, exports: &Exports) -> Option<ModulePath> {
    let module = (0..=path.len()).rev().map(|n| path[..n].to_vec()).find(|p| files.contains_key(p))?;
    match path.get(module.len()).and_then(|name| exports.get(&(module.clone(), name.clone()))) {
        Some(target) if target != path => resolve(target, files, exports),
        _ => Some(module),
    }
}

/// `(module, name)` → the path a `pub use` of that module re-exports as `name`.
type Exports = BTreeMap<(ModulePath, String), Vec<String>>;

fn exports(files: &BTreeMap<ModulePath, PathBuf>) -> Exports {
    let mut exports = Exports::new();
    for (module, file) in files {
        let code = code(&std::fs::read_to_string(file).unwrap());
        for statement in code.split(';').map(str::trim_start) {
            let Some(tree) = statement.strip_prefix("pub use ").or_else(|| statement.strip_prefix("pub(crate) use "))
            else {
                continue;
            };
            let (base, tree) = match tree.split_once("::") {
                Some(("crate", rest)) => (Vec::new(), rest),
                Some(("super", rest)) => (module[..module.len().saturating_sub(1)].to_vec(), rest),
                Some(("self", rest)) => (module.clone(), rest),
                _ => (module.clone(), tree),
            };
            for path in paths_at(tree) {
                if let Some(name) = path.last().filter(|n| *n != "self") {
                    exports.insert((module.clone(), name.clone()), [base.clone(), path].concat());
                }
            }
        }
    }
    exports
}

/// File → the other files it uses.
fn file_graph() -> BTreeMap<String, BTreeSet<String>> {
    let files = module_files();
    let exports = exports(&files);
    let label = |m: &ModulePath| if m.is_empty() { "lib".to_string() } else { m.join("/") };
    let mut graph = BTreeMap::new();
    for (module, file) in &files {
        let code = code(&std::fs::read_to_string(file).unwrap());
        let targets: BTreeSet<String> = named_paths(&code, module, &files)
            .iter()
            .filter_map(|path| resolve(path, &files, &exports))
            .filter(|target| target != module)
            .map(|target| label(&target))
            .collect();
        graph.insert(label(module), targets);
    }
    graph
}

/// The groups of files that reach each other (strongly connected, more than one file).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    let mut groups: Vec<BTreeSet<String>> = Vec::new();
    for file in graph.keys() {
        if groups.iter().any(|g| g.contains(file)) {
            continue;
        }
        let group: BTreeSet<String> =
            graph.keys().filter(|other| reaches(graph, file, other) && reaches(graph, other, file)).cloned().collect();
        if group.len() > 1 {
            groups.push(group);
        }
    }
    groups
}

/// File cycles being removed (by another change): the test fails once one is gone, so that the entry
/// is deleted with it.
const CYCLES_BEING_REMOVED: [&[&str]; 0] = [];

#[test]
fn no_import_cycle_between_files() {
    let mut found = cycles(&file_graph());
    let mut problems = Vec::new();
    for expected in CYCLES_BEING_REMOVED {
        let expected: BTreeSet<String> = expected.iter().map(|f| f.to_string()).collect();
        match found.iter().position(|g| *g == expected) {
            Some(at) => drop(found.remove(at)),
            None => problems.push(format!("{expected:?} is gone: delete it from CYCLES_BEING_REMOVED")),
        }
    }
    problems.extend(found.iter().map(|g| g.iter().cloned().collect::<Vec<_>>().join(" ↔ ")));
    assert!(problems.is_empty(), "files that import each other:\n  {}", problems.join("\n  "));
}

#[test]
fn the_file_scan_sees_use_trees_and_re_exports() {
    assert_eq!(
        paths_at("output::{self, header::{FileHeader, utc_now}, OutputError};"),
        [
            vec!["output", "self"],
            vec!["output", "header", "FileHeader"],
            vec!["output", "header", "utc_now"],
            vec!["output", "OutputError"]
        ]
    );
    let module = |p: &str| p.split('/').map(str::to_string).collect::<ModulePath>();
    let files: BTreeMap<ModulePath, PathBuf> =
        ["output", "output/writer", "output/sink"].map(|m| (module(m), PathBuf::from(m))).into_iter().collect();
    let exports = Exports::from([((module("output"), "ResultsWriter".into()), module("output/writer/ResultsWriter"))]);
    let named = named_paths(
        "use super::writer::RunResult; let w = crate::output::ResultsWriter::new();",
        &module("output/sink"),
        &files,
    );
    let resolved: Vec<ModulePath> = named.iter().filter_map(|p| resolve(p, &files, &exports)).collect();
    assert_eq!(resolved, [module("output/writer"), module("output/writer")]);
    let graph: BTreeMap<String, BTreeSet<String>> =
        [("a", ["b"]), ("b", ["c"]), ("c", ["a"])].map(|(f, t)| (f.into(), t.map(String::from).into())).into();
    assert_eq!(cycles(&graph), [BTreeSet::from(["a".to_string(), "b".to_string(), "c".to_string()])]);
}

/// The table the pile metrics' names are written in.
const METRIC_TABLE: &str = "physics/quantity.rs";

/// The names of the pile metrics and of the settle time, as the table declares them.
fn metric_names() -> Vec<&'static str> {
    PILE_METRICS.iter().map(|m| m.name).chain([SETTLE_TIME.name]).collect()
}

/// The string literals of `code` that are one of `names` (`"pile_height"`), each with its line.
fn metric_literals(code: &str, names: &[&str]) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (line, text) in code.lines().enumerate() {
        for name in names {
            if text.contains(&format!("\"{name}\"")) {
                found.push((line + 1, name.to_string()));
            }
        }
    }
    found
}

#[test]
fn pile_metric_names_are_written_only_in_their_table() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let (mut files, names) = (Vec::new(), metric_names());
    rust_files(&src, &mut files);
    let mut problems = Vec::new();
    for file in files.iter().filter(|f| !f.ends_with(METRIC_TABLE)) {
        let code = code(&std::fs::read_to_string(file).unwrap());
        for (line, name) in metric_literals(&code, &names) {
            let file = file.strip_prefix(&src).unwrap().display();
            problems.push(format!("src/{file}:{line}: \"{name}\" (use its entry of the pile metrics' table)"));
        }
    }
    assert!(problems.is_empty(), "pile metric names outside {METRIC_TABLE}:\n  {}", problems.join("\n  "));
}

#[test]
fn the_literal_scan_sees_a_metric_name_but_not_a_longer_one() {
    let names = metric_names();
    assert!(names.contains(&"pile_height") && names.contains(&"settle_time"), "{names:?}");
    let code = code("let a = m[\"pile_height\"];\nlet b = \"pile_height_mean\"; // \"settle_time\"");
    assert_eq!(metric_literals(&code, &names), [(1, "pile_height".to_string())]);
}
