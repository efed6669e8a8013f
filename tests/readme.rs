//! The README (and docs/) cannot drift from the code: every TOML block passes `demsweep check`, every
//! `demsweep` command shown names a subcommand and options that exist (its `--help` lists them), every
//! `cargo` command's example, bench or test target exists, every study a command names and every
//! script the text names exists,
//! and commands are written one way (`demsweep ...`, never `cargo run -- ...`).

mod runner_common;

use runner_common::demsweep;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// README.md and every Markdown file under docs/, with their text.
fn documents() -> Vec<(PathBuf, String)> {
    let mut paths = vec![Path::new(ROOT).join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(Path::new(ROOT).join("docs"))
        .expect("docs/")
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    paths.extend(docs);
    paths.into_iter().map(|path| (path.clone(), std::fs::read_to_string(&path).unwrap())).collect()
}

/// The fenced blocks of one language, with the line each starts on.
fn fenced_blocks(text: &str, language: &str) -> Vec<(usize, String)> {
    let mut blocks = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (number, line) in text.lines().enumerate() {
        match &mut current {
            Some(_) if line.trim_start().starts_with("```") => blocks.push(current.take().unwrap()),
            Some((_, block)) => {
                block.push_str(line);
                block.push('\n');
            }
            None if line.trim() == format!("```{language}") => current = Some((number + 1, String::new())),
            None => {}
        }
    }
    blocks
}

/// Every piece of code the text shows: the lines of indented and fenced blocks, and inline spans.
fn code_pieces(text: &str) -> Vec<(usize, String)> {
    let mut pieces = Vec::new();
    let mut fenced = false;
    for (number, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if fenced || line.starts_with("    ") {
            pieces.push((number + 1, line.to_string()));
        } else {
            let spans = line.split('`').skip(1).step_by(2);
            pieces.extend(spans.map(|span| (number + 1, span.to_string())));
        }
    }
    pieces
}

/// The words of each command starting with `program ` in a piece of code, up to a comment, a shell
/// separator or the end of an inline span.
fn commands<'a>(piece: &'a str, program: &str) -> Vec<Vec<&'a str>> {
    let mut found = Vec::new();
    let words: Vec<&str> = piece.split_whitespace().collect();
    for (start, _) in words.iter().enumerate().filter(|(_, w)| w.trim_start_matches(['$', '(', '`']) == program) {
        let mut ended = false;
        let command: Vec<&str> = words[start + 1..]
            .iter()
            .take_while(|w| {
                let take = !ended && !w.starts_with(['#', '`']) && !["&&", ";", "|", ":::"].contains(w);
                ended |= w.ends_with('`');
                take
            })
            .map(|w| w.trim_end_matches(['`', ',', ';', ')']))
            .collect();
        if !command.is_empty() {
            found.push(command);
        }
    }
    found
}

/// `--name` options in a command's words (`[--jobs N]`, `--keep=X`, `--resume \| --force`).
fn long_options<'a>(words: &[&'a str]) -> Vec<&'a str> {
    words
        .iter()
        .filter_map(|w| w.trim_start_matches('[').split(['=', ']']).next())
        .filter(|w| w.starts_with("--") && w.len() > 2)
        .collect()
}

/// `demsweep ARGS --help`, cached; `None` when there is no such command.
fn help<'a>(cache: &'a mut HashMap<Vec<String>, Option<String>>, args: &[&str]) -> Option<&'a String> {
    let key: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    cache
        .entry(key)
        .or_insert_with(|| {
            let out = demsweep(&[args, &["--help"]].concat());
            out.status.success().then(|| String::from_utf8_lossy(&out.stdout).into_owned())
        })
        .as_ref()
}

/// Problems with one `demsweep` command: an unknown subcommand or option.
fn demsweep_problems(words: &[&str], cache: &mut HashMap<Vec<String>, Option<String>>) -> Vec<String> {
    let Some(&subcommand) = words.first().filter(|w| w.chars().all(|c| c.is_ascii_lowercase())) else {
        return option_problems(words, &[], cache);
    };
    let Some(top) = help(cache, &[subcommand]).cloned() else {
        return vec![format!("no subcommand `{subcommand}`")];
    };
    // A command with subcommands (bench): the next word names one, or several as `a|b|c`.
    let nested: Vec<String> = match words.get(1) {
        Some(word) if top.contains("\nCommands:") => word.replace('\\', "").split('|').map(str::to_string).collect(),
        _ => vec![String::new()],
    };
    let mut problems = Vec::new();
    for name in &nested {
        let path: Vec<&str> = [subcommand, name.as_str()].into_iter().filter(|w| !w.is_empty()).collect();
        problems.extend(option_problems(words, &path, cache));
    }
    problems
}

/// The `--options` in `words` that `demsweep PATH --help` does not list (or that there is no such command).
fn option_problems(words: &[&str], path: &[&str], cache: &mut HashMap<Vec<String>, Option<String>>) -> Vec<String> {
    let Some(text) = help(cache, path) else {
        return vec![format!("no subcommand `{}`", path.join(" "))];
    };
    let listed = |option: &str| text.split(|c: char| c.is_whitespace() || c == ',').any(|w| w == option);
    let command = ["demsweep"].iter().chain(path).copied().collect::<Vec<_>>().join(" ");
    long_options(words).into_iter().filter(|o| !listed(o)).map(|o| format!("`{command}` has no {o}")).collect()
}

/// Problems with one `cargo` command: a target that does not exist, or a `cargo run` of demsweep.
fn cargo_problems(words: &[&str]) -> Vec<String> {
    let mut problems = Vec::new();
    for pair in words.windows(2) {
        let folder = match pair[0] {
            "--example" => "examples",
            "--bench" => "benches",
            "--test" => "tests",
            _ => continue,
        };
        if pair[1].chars().all(|c| c.is_ascii_uppercase()) {
            continue; // a placeholder: `--test NAME`
        }
        if !Path::new(ROOT).join(folder).join(format!("{}.rs", pair[1])).exists() {
            problems.push(format!("no {folder}/{}.rs", pair[1]));
        }
    }
    if words.first() == Some(&"run") && !words.contains(&"--example") {
        problems.push(
            "write `demsweep ...` (installed by `cargo install --locked --path .`), not `cargo run -- ...`".into(),
        );
    }
    problems
}

/// Bundled files named by `words` (starting with one of `folders`) that do not exist.
fn missing_files(words: &[&str], folders: &[&str]) -> Vec<String> {
    words
        .iter()
        .map(|w| w.trim_matches(['`', ',', ';', ')', '(']))
        .filter(|w| folders.iter().any(|p| w.starts_with(p)) && !w.contains(['{', '<', '*']))
        .filter(|w| !Path::new(ROOT).join(w).exists())
        .map(|w| format!("no file {w}"))
        .collect()
}

/// The README is a front page; the guide is the chapters of docs/.
#[test]
fn the_readme_is_a_front_page_and_the_guide_is_in_docs() {
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 300, "README.md has {lines} lines: move guide text into a chapter of docs/");
    let chapters = documents().into_iter().filter(|(path, _)| path.parent() == Some(&Path::new(ROOT).join("docs")));
    let unlinked: Vec<PathBuf> = chapters
        .map(|(path, _)| path)
        .filter(|path| path.file_name().is_some_and(|n| n != "README.md"))
        .filter(|path| !readme.contains(&format!("(docs/{})", path.file_name().unwrap().to_string_lossy())))
        .collect();
    assert!(unlinked.is_empty(), "chapters the README does not link to: {unlinked:?}");
    assert!(readme.contains("cargo install --locked --path ."), "install with the tested Cargo.lock");
}

#[test]
fn every_toml_block_passes_check() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("readme_blocks");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut checked = 0;
    for (path, text) in documents() {
        for (line, block) in fenced_blocks(&text, "toml") {
            let file = dir.join(format!("block_{checked}.toml"));
            std::fs::write(&file, &block).unwrap();
            let out = demsweep(&["check", file.to_str().unwrap()]);
            let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
            assert!(out.status.success(), "{}:{line}: the TOML block fails `demsweep check`:\n{said}", path.display());
            assert!(said.starts_with("ok: "), "{}:{line}: {said}", path.display());
            checked += 1;
        }
    }
    assert!(checked >= 2, "the README shows a study file and a tune file");
}

#[test]
fn every_command_shown_exists_as_written() {
    let mut cache = HashMap::new();
    let mut problems = Vec::new();
    let mut seen = 0;
    for (path, text) in documents() {
        for (line, piece) in code_pieces(&text) {
            let words: Vec<&str> = piece.split_whitespace().collect();
            let scripts = missing_files(&words, &["scripts/"]);
            problems.extend(scripts.into_iter().map(|p| format!("{}:{line}: {p}", path.display())));
            let found = commands(&piece, "demsweep").into_iter().map(|c| (c, true));
            for (words, is_demsweep) in found.chain(commands(&piece, "cargo").into_iter().map(|c| (c, false))) {
                let mut wrong =
                    if is_demsweep { demsweep_problems(&words, &mut cache) } else { cargo_problems(&words) };
                wrong.extend(missing_files(&words, &["studies/"]));
                let program = if is_demsweep { "demsweep" } else { "cargo" };
                let shown = format!("{}:{line}: `{program} {}`", path.display(), words.join(" "));
                problems.extend(wrong.into_iter().map(|p| format!("{shown}: {p}")));
                seen += 1;
            }
        }
    }
    assert!(problems.is_empty(), "commands shown that do not exist as written:\n{}", problems.join("\n"));
    assert!(seen > 30, "only {seen} commands found: the extraction is broken");
}

#[test]
fn the_checker_catches_an_unknown_option_and_subcommand() {
    let mut cache = HashMap::new();
    let command = commands("    demsweep run s.toml --jobz 2   # a typo", "demsweep");
    assert_eq!(command, vec![vec!["run", "s.toml", "--jobz", "2"]]);
    assert_eq!(demsweep_problems(&command[0], &mut cache), vec!["`demsweep run` has no --jobz"]);
    assert_eq!(demsweep_problems(&["bench", "accuracy|speed"], &mut cache), vec!["no subcommand `bench speed`"]);
    assert!(demsweep_problems(&["summary", "R.h5", "[--by-point", "[--metric", "NAME]...]"], &mut cache).is_empty());
    assert_eq!(cargo_problems(&["run", "--release", "--", "plot"]).len(), 1);
    assert!(cargo_problems(&["run", "--release", "--example", "settled_pile", "--", "300"]).is_empty());
}

/// The relative links of a Markdown text (`[text](path)`, without an address or an anchor).
fn relative_links(text: &str) -> Vec<&str> {
    text.split("](")
        .skip(1)
        .filter_map(|rest| rest.split(')').next())
        .map(|link| link.split('#').next().unwrap_or(link))
        .filter(|link| !link.is_empty() && !link.contains("://"))
        .collect()
}

#[test]
fn the_repository_stands_alone() {
    let mut problems = Vec::new();
    for (path, text) in documents() {
        let folder = path.parent().unwrap();
        let broken = relative_links(&text).into_iter().filter(|link| !folder.join(link).exists());
        problems.extend(broken.map(|link| format!("{}: link to {link}, which does not exist", path.display())));
    }
    // Paths outside the repository (the project's private notes) mean nothing in a clone.
    let outside = ["spec", "reference", "paper"].map(|folder| format!("shared/{folder}"));
    let mut files = vec![Path::new(ROOT).join("README.md"), Path::new(ROOT).join("Cargo.toml")];
    for folder in ["src", "tests", "benches", "examples", "scripts", "studies", "docs"] {
        files.extend(files_under(&Path::new(ROOT).join(folder)));
    }
    for file in files {
        let Ok(text) = std::fs::read_to_string(&file) else { continue };
        let named = outside.iter().filter(|o| text.contains(o.as_str()));
        problems.extend(named.map(|o| format!("{} refers to {o}, which is not in the repository", file.display())));
    }
    for file in ["LICENSE", "CITATION.cff"] {
        if !Path::new(ROOT).join(file).is_file() {
            problems.push(format!("no {file}"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap().map(Result::unwrap) {
        let path = entry.path();
        if path.is_dir() { files.extend(files_under(&path)) } else { files.push(path) }
    }
    files
}
