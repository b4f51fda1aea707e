//! The module boundaries `src/lib.rs` states: each module imports only the
//! modules its row of the "Who may import whom" table names, and only
//! `render` and `editor` use wgpu, only `editor` egui. The table is read from
//! the crate docs, so the rule is written once.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// (module, modules it may import) for every row of the table in `src/lib.rs`.
fn allowed_imports(lib: &str) -> Vec<(String, BTreeSet<String>)> {
    let names = |cell: &str| -> BTreeSet<String> { cell.split('`').skip(1).step_by(2).map(str::to_owned).collect() };
    let mut rows = Vec::new();
    for line in lib.lines().filter_map(|l| l.strip_prefix("//! | ")) {
        let mut cells = line.split('|');
        let (Some(modules), Some(may)) = (cells.next(), cells.next()) else { continue };
        // The header row names no module in backticks.
        for module in names(modules) {
            rows.push((module, names(may)));
        }
    }
    rows
}

/// The crate's top-level modules, from `pub mod NAME;` in `src/lib.rs`.
fn modules(lib: &str) -> Vec<String> {
    lib.lines().filter_map(|l| l.strip_prefix("pub mod")?.trim().strip_suffix(';').map(str::to_owned)).collect()
}

/// Every `.rs` file of module `name`: `src/NAME.rs` and everything under `src/NAME/`.
fn files_of(name: &str) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let file = Path::new("src").join(format!("{name}.rs"));
    if file.is_file() {
        files.push(file);
    }
    let mut dirs = vec![Path::new("src").join(name)];
    while let Some(dir) = dirs.pop() {
        let Ok(entries) = fs::read_dir(&dir) else { continue };
        for entry in entries {
            let path = entry.unwrap_or_else(|e| panic!("listing {}: {e}", dir.display())).path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|ext| ext == "rs") {
                files.push(path);
            }
        }
    }
    files
}

/// The code of a file without its comments (whole comment lines and what follows `//`).
fn code_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .filter(|(_, line)| !line.trim_start().starts_with("//"))
        .map(|(index, line)| (index + 1, line.split("//").next().unwrap_or(line)))
}

/// The names `NAME` in `crate::NAME` on a line.
fn crate_paths(line: &str) -> impl Iterator<Item = &str> {
    line.match_indices("crate::").filter_map(move |(at, _)| {
        let rest = &line[at + "crate::".len()..];
        let end = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len());
        (end > 0).then(|| &rest[..end])
    })
}

#[test]
fn every_module_imports_only_what_the_crate_docs_allow() {
    let lib = fs::read_to_string("src/lib.rs").expect("src/lib.rs");
    let table = allowed_imports(&lib);
    let modules = modules(&lib);
    assert!(modules.len() > 5, "the modules of src/lib.rs: {modules:?}");
    let mut problems = Vec::new();
    for module in &modules {
        let Some((_, allowed)) = table.iter().find(|(name, _)| name == module) else {
            problems.push(format!("{module} has no row in the table of src/lib.rs"));
            continue;
        };
        for path in files_of(module) {
            let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            for (line_number, line) in code_lines(&text) {
                for used in crate_paths(line) {
                    if used != module && modules.contains(&used.to_owned()) && !allowed.contains(used) {
                        problems.push(format!("{}:{line_number}: {module} imports {used}", path.display()));
                    }
                }
                let words = line.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'));
                let (gpu, ui) = words.fold((false, false), |(gpu, ui), word| {
                    (gpu || word == "wgpu", ui || word == "eframe" || word.starts_with("egui"))
                });
                if gpu && !["render", "editor"].contains(&module.as_str()) || ui && module != "editor" {
                    problems.push(format!("{}:{line_number}: {module} uses wgpu or egui", path.display()));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_table_is_read_as_written() {
    let lib = "//! | `scene` | `atomic_file` |\n//! | `atomic_file`, `mesh` | nothing of Drape |\n";
    let table = allowed_imports(lib);
    assert_eq!(table.len(), 3);
    assert_eq!(table[0], ("scene".to_owned(), BTreeSet::from(["atomic_file".to_owned()])));
    assert!(table[1].1.is_empty() && table[2].0 == "mesh");
    assert_eq!(crate_paths("use crate::scene::{Layer}; crate::mesh::Mesh").collect::<Vec<_>>(), ["scene", "mesh"]);
}
