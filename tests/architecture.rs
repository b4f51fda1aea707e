//! The module boundaries `src/lib.rs` states: each module imports only the
//! modules its row of the "Who may import whom" table names, and only
//! `render` and `editor` use wgpu, only `editor` egui. The table is read from
//! the crate docs, so the rule is written once. The GPU and window crates
//! belong to the cargo feature `editor`, and so do the modules that use them.

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

/// The modules `render` never imports, whatever the table says: it is a leaf
/// that draws the triangles, images and camera it is handed.
const RENDER_NEVER_IMPORTS: [&str; 5] = ["world", "shape", "animate", "picture", "editor"];

#[test]
fn render_knows_nothing_of_the_world_the_shapes_or_the_animation() {
    let lib = fs::read_to_string("src/lib.rs").expect("src/lib.rs");
    let table = allowed_imports(&lib);
    let Some((_, render_may)) = table.iter().find(|(module, _)| module == "render") else {
        panic!("src/lib.rs's table has no row for render");
    };
    let named: Vec<&str> = RENDER_NEVER_IMPORTS.iter().copied().filter(|m| render_may.contains(*m)).collect();
    assert!(named.is_empty(), "the table lets render import {named:?}");
    // The table's check covers the files; this one holds even if a row is loosened.
    let mut offenders = Vec::new();
    for path in files_of("render") {
        let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for (line_number, line) in code_lines(&text) {
            if let Some(used) = crate_paths(line).find(|used| RENDER_NEVER_IMPORTS.contains(used)) {
                offenders.push(format!("{}:{line_number}: render imports {used}", path.display()));
            }
        }
    }
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
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

/// Every `.rs` file under `src/` with its module path (`src/scene/layers.rs`: `scene::layers`).
fn source_files() -> Vec<(Vec<String>, PathBuf)> {
    let mut files = Vec::new();
    let mut dirs = vec![PathBuf::from("src")];
    while let Some(dir) = dirs.pop() {
        let entries = fs::read_dir(&dir).unwrap_or_else(|e| panic!("listing {}: {e}", dir.display()));
        for entry in entries {
            let path = entry.unwrap_or_else(|e| panic!("listing {}: {e}", dir.display())).path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|ext| ext == "rs") {
                let relative = path.strip_prefix("src").expect("under src").with_extension("");
                let mut module: Vec<String> =
                    relative.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
                if module.last().is_some_and(|last| last == "mod" || last == "lib" || last == "main") {
                    module.pop();
                }
                files.push((module, path));
            }
        }
    }
    files.sort();
    files
}

/// The files `text` (of module `me`) names through `crate::` or `super::` paths,
/// outside its tests; its own ancestors do not count (a child naming its parent's items).
fn imported_files(me: &[String], text: &str, files: &[(Vec<String>, PathBuf)]) -> BTreeSet<usize> {
    let code = text.split("#[cfg(test)]\nmod tests").next().unwrap_or(text);
    let mut imported = BTreeSet::new();
    for (_, line) in code_lines(code) {
        for (prefix, base) in [("crate::", &me[..0]), ("super::", &me[..me.len().saturating_sub(1)])] {
            for (at, _) in line.match_indices(prefix) {
                // `super::` inside `crate::a::super::` does not occur; skip `self::super::` and the like.
                if prefix == "super::" && line[..at].ends_with("::") {
                    continue;
                }
                let rest = &line[at + prefix.len()..];
                let mut path: Vec<String> = base.to_vec();
                for segment in rest.split("::") {
                    let end = segment.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(segment.len());
                    path.push(segment[..end].to_owned());
                    if end < segment.len() {
                        break;
                    }
                }
                // The longest prefix that is a file's module.
                let found =
                    (1..=path.len()).rev().find_map(|k| files.iter().position(|(module, _)| *module == path[..k]));
                if let Some(index) = found
                    && !me.starts_with(&files[index].0)
                {
                    imported.insert(index);
                }
            }
        }
    }
    imported
}

#[test]
fn no_two_source_files_import_each_other_directly_or_round_a_circle() {
    let files = source_files();
    assert!(files.len() > 50, "the files under src/: {}", files.len());
    let edges: Vec<BTreeSet<usize>> = files
        .iter()
        .map(|(module, path)| {
            let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            imported_files(module, &text, &files)
        })
        .collect();
    // A file is on a circle when it can reach itself.
    let mut circles = Vec::new();
    for start in 0..files.len() {
        let mut seen = vec![false; files.len()];
        let mut stack: Vec<usize> = edges[start].iter().copied().collect();
        while let Some(at) = stack.pop() {
            if at == start {
                circles.push(files[start].1.display().to_string());
                break;
            }
            if !std::mem::replace(&mut seen[at], true) {
                stack.extend(edges[at].iter().copied());
            }
        }
    }
    assert!(circles.is_empty(), "files on an import circle:\n{}", circles.join("\n"));
}

#[test]
fn imports_are_found_through_crate_and_super_paths() {
    let files: Vec<(Vec<String>, PathBuf)> = [vec![], vec!["scene"], vec!["scene", "layers"], vec!["scene", "schema"]]
        .into_iter()
        .map(|m| (m.into_iter().map(str::to_owned).collect::<Vec<_>>(), PathBuf::new()))
        .collect();
    let me = ["scene".to_owned(), "layers".to_owned()];
    let found = imported_files(&me, "use super::schema::{Access};\n// super::nothing\nuse super::Pin;", &files);
    assert_eq!(found, BTreeSet::from([3]), "schema, and not the parent");
    let found = imported_files(
        &me,
        "let x = crate::scene::schema::MAX;\n#[cfg(test)]\nmod tests {\nuse crate::scene::layers;",
        &files,
    );
    assert_eq!(found, BTreeSet::from([3]));
}

#[test]
fn only_app_rs_implements_the_editor_app() {
    let offenders: Vec<String> = source_files()
        .into_iter()
        .filter(|(module, _)| {
            module.first().is_some_and(|m| m == "editor") && module.get(1).is_some_and(|f| f != "app")
        })
        .filter(|(_, path)| fs::read_to_string(path).is_ok_and(|text| text.contains("impl DrapeApp")))
        .map(|(_, path)| path.display().to_string())
        .collect();
    assert!(offenders.is_empty(), "impl DrapeApp outside src/editor/app.rs: {offenders:?}");
}

/// The crates only the cargo feature `editor` brings in.
const EDITOR_CRATES: [&str; 6] = ["wgpu", "eframe", "egui", "pollster", "clap", "indicatif"];

#[test]
fn without_the_editor_feature_the_library_needs_no_gpu_or_window_crate() {
    let lib = fs::read_to_string("src/lib.rs").unwrap();
    let lines: Vec<&str> = lib.lines().collect();
    let gated: BTreeSet<&str> = lines
        .windows(2)
        .filter(|pair| pair[0].trim() == "#[cfg(feature = \"editor\")]")
        .filter_map(|pair| pair[1].strip_prefix("pub mod")?.trim().strip_suffix(';'))
        .collect();
    assert_eq!(gated, BTreeSet::from(["editor", "picture", "render", "render_job"]));
    let manifest = fs::read_to_string("Cargo.toml").unwrap();
    let feature = manifest.lines().find(|l| l.starts_with("editor = [")).expect("Cargo.toml names the editor feature");
    for name in EDITOR_CRATES.iter().filter(|&&name| name != "egui") {
        assert!(feature.contains(&format!("\"dep:{name}\"")), "the editor feature does not bring in {name}");
    }
    let mut offenders = Vec::new();
    for module in modules(&lib).iter().filter(|m| !gated.contains(m.as_str())) {
        for path in files_of(module) {
            let text = fs::read_to_string(&path).unwrap();
            for (number, line) in code_lines(&text) {
                let uses = |name: &str| line.contains(&format!("{name}::")) || line.contains(&format!("use {name}"));
                if let Some(name) = EDITOR_CRATES.iter().find(|&&name| uses(name)) {
                    offenders.push(format!("{}:{number} uses {name}", path.display()));
                }
            }
        }
    }
    assert!(offenders.is_empty(), "outside the editor feature's modules: {offenders:?}");
}

/// A `static` (or a `thread_local!`) whose value can change is state shared
/// by every caller, hidden behind functions that look pure: caches belong to
/// the value that uses them (an `Evaluator`'s rest shapes and posed solids).
/// These few are allowed, each for the reason given: (file, static, why).
const MUTABLE_STATICS_ALLOWED: [(&str, &str, &str); 7] = [
    ("src/atomic_file.rs", "COMPANIONS", "files staged on this thread go in with its next atomic write"),
    ("src/atomic_file.rs", "REGISTRY", "temporaries a signal's clean-up removes: a handler reaches only statics"),
    ("src/atomic_file.rs", "SWEPT", "each directory is swept of dead processes' temporaries once per process"),
    ("src/atomic_file.rs", "COUNTER", "temporary names unique within the process"),
    ("src/atomic_file.rs", "WAKE_FD", "the pipe the signal handler writes to: a handler reaches only statics"),
    ("src/atomic_file.rs", "INSTALLED", "the signal handlers are installed once per process"),
    ("src/main.rs", "SUMMARY_TO_STDERR", "set once before any output when the output file is stdout itself"),
];

/// Types whose value changes behind a shared reference.
const INTERIOR_MUTABILITY: [&str; 5] = ["Mutex", "RwLock", "Cell", "Atomic", "UnsafeCell"];

/// `(name, declaration)` of every `static` in `code` that can change: `static
/// mut`, a type holding one of [`INTERIOR_MUTABILITY`] (a `OnceLock` of
/// plain data is set once and stays), and every static of a `thread_local!`.
fn mutable_statics(code: &str) -> Vec<(String, String)> {
    let mut found = Vec::new();
    let mut in_thread_local = false;
    for (_, line) in code_lines(code) {
        let trimmed = line.trim_start();
        if trimmed.starts_with("thread_local!") {
            in_thread_local = true;
        }
        let declaration = ["pub static ", "pub(crate) static ", "static "].iter().find_map(|p| trimmed.strip_prefix(p));
        if let Some(rest) = declaration {
            let rest = rest.strip_prefix("mut ").map_or(rest, |r| r);
            let name: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            let type_text = rest.split('=').next().unwrap_or(rest);
            let mutable = in_thread_local
                || trimmed.contains("static mut ")
                || INTERIOR_MUTABILITY.iter().any(|marker| type_text.contains(marker));
            if mutable && !name.is_empty() {
                found.push((name, trimmed.to_owned()));
            }
        }
        if in_thread_local && trimmed.starts_with('}') {
            in_thread_local = false;
        }
    }
    found
}

#[test]
fn no_static_holds_mutable_state_outside_the_allow_list() {
    let mut offenders = Vec::new();
    let mut allowed_seen = BTreeSet::new();
    for (_, path) in source_files() {
        let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let file = path.display().to_string().replace('\\', "/");
        for (name, declaration) in mutable_statics(&text) {
            let allowed = MUTABLE_STATICS_ALLOWED.iter().find(|(f, n, _)| *f == file && *n == name);
            match allowed {
                Some(entry) => {
                    allowed_seen.insert(entry.1);
                }
                None => offenders.push(format!("{file}: {declaration}")),
            }
        }
    }
    assert!(offenders.is_empty(), "statics that can change, not on the allow-list:\n{}", offenders.join("\n"));
    let stale: Vec<_> = MUTABLE_STATICS_ALLOWED.iter().filter(|(_, n, _)| !allowed_seen.contains(n)).collect();
    assert!(stale.is_empty(), "allow-list entries whose static is gone (remove them): {stale:?}");
}

#[test]
fn mutable_statics_are_told_from_constant_ones() {
    let code = "static A: Mutex<Vec<u8>> = Mutex::new(Vec::new());\n\
                pub static B: &str = \"Mutex\";\n\
                static C: OnceLock<GpuContext> = OnceLock::new();\n\
                static D: std::sync::atomic::AtomicU64 = AtomicU64::new(0);\n\
                // static E: Mutex<u8> = Mutex::new(0);\n\
                static mut F: u8 = 0;\n\
                thread_local! {\n    static G: RefCell<u8> = const { RefCell::new(0) };\n    static H: u8 = 0;\n}\n\
                static I: OnceLock<Mutex<u8>> = OnceLock::new();\n";
    let names: Vec<String> = mutable_statics(code).into_iter().map(|(name, _)| name).collect();
    assert_eq!(names, ["A", "D", "F", "G", "H", "I"]);
}

/// Where the project describes itself: none of it may cite numbered work
/// periods, helpers or issues (history belongs in commit messages).
const SELF_DESCRIBING: [&str; 9] =
    ["src", "tests", "benches", "examples", ".ci", "docs", "README.md", "ARCHITECTURE.md", "BENCHMARKS.md"];

/// Words that, followed by a number, name a period of work or a tracker's entry.
const WORK_PERIOD_WORDS: [&str; 6] = ["session", "issue", "sprint", "ticket", "helper", "milestone"];

/// The references to work periods or issues in `line`: one of
/// [`WORK_PERIOD_WORDS`] (any case, optionally plural) followed by a number,
/// with or without a `#` or `-` between, or an issue named as the owner of
/// something (the possessive, as in naming whose targets or case a bench measures).
fn work_period_references(line: &str) -> Vec<String> {
    // Lower case, so that the excerpts below index the text they were found in.
    let lower = line.to_lowercase();
    let starts_word = |at: usize| lower[..at].chars().next_back().is_none_or(|c| !c.is_alphanumeric());
    let mut found = Vec::new();
    for word in WORK_PERIOD_WORDS {
        for (at, _) in lower.match_indices(word) {
            let after = &lower[at + word.len()..];
            let number = after.strip_prefix('s').unwrap_or(after).trim_start_matches([' ', '#', '-']);
            if starts_word(at) && number.starts_with(|c: char| c.is_ascii_digit()) {
                found.push(lower[at..].chars().take(word.len() + 4).collect());
            }
        }
    }
    let possessive = format!("{}'s", WORK_PERIOD_WORDS[1]);
    for (at, _) in lower.match_indices(&possessive) {
        if starts_word(at) {
            found.push(lower[at..].chars().take(20).collect());
        }
    }
    found
}

/// Every file under `roots` (files or folders), recursively.
fn files_under(roots: &[&str]) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending: Vec<PathBuf> = roots.iter().map(PathBuf::from).collect();
    while let Some(path) = pending.pop() {
        if path.is_dir() {
            let entries = fs::read_dir(&path).unwrap_or_else(|e| panic!("listing {}: {e}", path.display()));
            pending.extend(entries.map(|e| e.unwrap_or_else(|e| panic!("listing {}: {e}", path.display())).path()));
        } else if path.is_file() {
            files.push(path);
        }
    }
    files.sort();
    files
}

#[test]
fn the_project_speaks_of_itself_not_of_work_periods_or_issues() {
    let mut offenders = Vec::new();
    for path in files_under(&SELF_DESCRIBING) {
        // Pictures, caches and other binary files say nothing.
        let Ok(text) = fs::read_to_string(&path) else { continue };
        for (index, line) in text.lines().enumerate() {
            for reference in work_period_references(line) {
                offenders.push(format!("{}:{}: {reference}", path.display(), index + 1));
            }
        }
    }
    assert!(offenders.is_empty(), "references to work periods or issues:\n{}", offenders.join("\n"));
}

#[test]
fn work_period_references_are_told_from_ordinary_words() {
    let cited = [
        format!("(BENCHMARKS.md, session {})", 27),
        format!("the scenes Issue #{} names", 20),
        format!("the session-{} guard", 9),
        format!("as in sessions {} and 10", 9),
        format!("the animation {}'s targets", "issue"),
    ];
    for line in &cited {
        assert_eq!(work_period_references(line).len(), 1, "{line}");
    }
    let ordinary = [
        "w.session.follow = true; let session = &w.session;",
        "each [`Issue`] names its value's path; 3 issues found",
        "the output helpers (directories, side files)",
        "relax iterations 1 000 000 is more than 100 000",
        "a new session and new per-document panels",
    ];
    for line in ordinary {
        assert!(work_period_references(line).is_empty(), "{line}");
    }
}

/// The editor's state types. Each changes its own fields, through methods
/// named for what the user did, so a field's writers are found in the file
/// that defines the type (for `ViewportPanel`, the viewport's folder): none
/// of their fields is `pub`, `pub(crate)`, `pub(super)` or `pub(in …)`.
const EDITOR_STATE_TYPES: [&str; 16] = [
    "DrapeApp",
    "Workspace",
    "Session",
    "Shown",
    "Document",
    "ViewportPanel",
    "StaleCloth",
    "TimelinePanel",
    "ClothPanel",
    "LayersPanel",
    "CollidersPanel",
    "ReferencesPanel",
    "ShotPanel",
    "Files",
    "ExportWindow",
    "RenderWindow",
];

/// Fields of an editor state type that are open because they hold other
/// state types, whose own fields are private: (type, field, its type).
const EDITOR_STATE_HELD_OPENLY: [(&str, &str, &str); 3] =
    [("Workspace", "doc", "Document"), ("Workspace", "shown", "Shown"), ("Workspace", "session", "Session")];

/// `line` without a leading `pub`, `pub(crate)`, `pub(in …)` and the like.
fn without_visibility(line: &str) -> &str {
    let Some(rest) = line.strip_prefix("pub") else { return line };
    let rest = match rest.strip_prefix('(') {
        Some(inside) => inside.split_once(')').map_or(rest, |(_, after)| after),
        None => rest,
    };
    rest.strip_prefix(' ').unwrap_or(line)
}

/// `(struct name, field name, field type)` of every open (`pub…`) field of
/// every struct defined with braces in `code`.
fn open_fields(code: &str) -> Vec<(String, String, String)> {
    let mut found = Vec::new();
    let mut current: Option<String> = None;
    for (_, line) in code_lines(code) {
        let trimmed = line.trim();
        if let Some(name) = current.as_ref() {
            if trimmed.starts_with('}') && line.starts_with('}') {
                current = None;
            } else if let Some(rest) = trimmed.strip_prefix("pub")
                && let Some((field, ty)) = rest.trim_start_matches(|c: char| c != ' ').trim().split_once(':')
                && line.starts_with("    ")
                && !line.starts_with("     ")
            {
                found.push((name.clone(), field.trim().to_owned(), ty.trim().trim_end_matches(',').to_owned()));
            }
            continue;
        }
        if let Some(rest) = without_visibility(trimmed).strip_prefix("struct ")
            && trimmed.ends_with('{')
            && !line.starts_with(' ')
        {
            let name = rest.split(|c: char| !c.is_alphanumeric() && c != '_').next().unwrap_or_default();
            current = Some(name.to_owned());
        }
    }
    found
}

#[test]
fn editor_state_types_have_no_open_fields() {
    let mut offenders = Vec::new();
    let mut defined = BTreeSet::new();
    for path in files_under(&["src/editor"]) {
        let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
        for (_, line) in code_lines(&text) {
            let declared = without_visibility(line);
            if let Some(name) = EDITOR_STATE_TYPES.iter().find(|n| declared.starts_with(&format!("struct {n} "))) {
                defined.insert(*name);
            }
        }
        for (ty, field, field_ty) in open_fields(&text) {
            let held = EDITOR_STATE_HELD_OPENLY.contains(&(ty.as_str(), field.as_str(), field_ty.as_str()));
            if EDITOR_STATE_TYPES.contains(&ty.as_str()) && !held {
                offenders.push(format!("{}: {ty}.{field}", path.display()));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "open fields on editor state types (add a method named for the action):\n{}",
        offenders.join("\n")
    );
    let missing: Vec<_> = EDITOR_STATE_TYPES.iter().filter(|n| !defined.contains(*n)).collect();
    assert!(
        missing.is_empty(),
        "editor state types not found under src/editor (renamed? update the list): {missing:?}"
    );
}

#[test]
fn open_fields_are_found_in_struct_definitions_only() {
    let code = "pub struct Shown {\n    pub scene: Scene,\n    mesh: Arc<Mesh>,\n    pub(super) ghosts: Vec<Ghost>,\n}\n\
                impl Shown {\n    pub fn scene(&self) -> &Scene {\n        &self.scene\n    }\n}\n\
                struct Job {\n    pub done: bool,\n}\npub(in crate::editor) struct Window {\n    pub(crate) open: bool,\n}\n";
    let found = open_fields(code);
    let expected = [
        ("Shown", "scene", "Scene"),
        ("Shown", "ghosts", "Vec<Ghost>"),
        ("Job", "done", "bool"),
        ("Window", "open", "bool"),
    ];
    assert_eq!(found, expected.map(|(a, b, c)| (a.to_owned(), b.to_owned(), c.to_owned())));
}

/// Only the workspace replaces the state it holds openly.
#[test]
fn only_the_workspace_replaces_the_document_what_is_shown_or_the_session() {
    let mut offenders = Vec::new();
    for path in files_under(&["src/editor"]) {
        if path.ends_with("workspace.rs") {
            continue;
        }
        let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
        for (number, line) in code_lines(&text) {
            for (_, field, _) in EDITOR_STATE_HELD_OPENLY {
                let Some(at) = line.find(&format!(".{field} =")) else { continue };
                if !line[at..].starts_with(&format!(".{field} ==")) {
                    offenders.push(format!("{}:{number}: {}", path.display(), line.trim()));
                }
            }
        }
    }
    assert!(offenders.is_empty(), "the workspace's parts replaced outside workspace.rs:\n{}", offenders.join("\n"));
}

/// Functions that may still allow clippy's argument count away, and why. An
/// entry whose function no longer does fails too, so the list only shrinks.
const MANY_ARGUMENTS_ALLOWED: [(&str, &str); 0] = [];

/// Whether `line` is an attribute that allows or expects clippy's `too_many_arguments`.
fn allows_many_arguments(line: &str) -> bool {
    let trimmed = line.trim_start();
    (trimmed.starts_with("#[") || trimmed.starts_with("#!["))
        && (trimmed.contains("allow(") || trimmed.contains("expect("))
        && trimmed.contains(concat!("too_many", "_arguments"))
}

/// The name of the first function declared in `lines`, if any.
fn first_function<'a>(lines: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    lines.take(4).find_map(|line| {
        let rest = &line[line.find("fn ")? + 3..];
        Some(&rest[..rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len())])
    })
}

/// A function's arguments are gathered into types with names (a layer's
/// `LayerFrame`, the approximation's `TrianglePlacer`), not allowed past
/// clippy's count, and the count is clippy's own.
#[test]
fn no_function_allows_too_many_arguments_and_the_threshold_is_clippys() {
    let mut offenders = Vec::new();
    let mut allowed_seen = BTreeSet::new();
    for path in files_under(&["src", "tests", "benches", "fuzz/fuzz_targets", "examples"]) {
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
        let lines: Vec<(usize, &str)> = code_lines(&text).collect();
        for (at, (number, line)) in lines.iter().enumerate().filter(|(_, (_, line))| allows_many_arguments(line)) {
            let function = first_function(lines[at + 1..].iter().map(|(_, line)| *line));
            match MANY_ARGUMENTS_ALLOWED.iter().find(|(name, _)| Some(*name) == function) {
                Some((name, _)) => {
                    allowed_seen.insert(*name);
                }
                None => offenders.push(format!("{}:{number}: {}", path.display(), line.trim())),
            }
        }
    }
    assert!(offenders.is_empty(), "allows of too_many_arguments:\n{}", offenders.join("\n"));
    let stale: Vec<_> = MANY_ARGUMENTS_ALLOWED.iter().filter(|(name, _)| !allowed_seen.contains(name)).collect();
    assert!(stale.is_empty(), "allow-list entries whose function no longer allows it (remove them): {stale:?}");
    for config in ["clippy.toml", ".clippy.toml", "Cargo.toml"] {
        let Ok(text) = fs::read_to_string(config) else { continue };
        for (number, line) in code_lines(&text) {
            let line = line.split('#').next().unwrap_or(line);
            assert!(
                !line.contains("too-many-arguments") && !line.contains(concat!("too_many", "_arguments")),
                "{config}:{number}: clippy's argument count is raised or allowed: {}",
                line.trim()
            );
        }
    }
}

#[test]
fn allows_of_many_arguments_are_told_from_other_attributes() {
    assert!(allows_many_arguments(concat!("    #[allow(clippy::too_many", "_arguments)]")));
    assert!(allows_many_arguments(concat!("#![expect(clippy::too_many", "_arguments, reason = \"x\")]")));
    assert!(allows_many_arguments(concat!("#[cfg_attr(test, allow(clippy::too_many", "_arguments))]")));
    assert!(!allows_many_arguments("#[allow(clippy::type_complexity)]"));
    assert!(!allows_many_arguments(concat!("let note = \"too_many", "_arguments\";")));
    let item = ["/// Doc.", "#[inline]", "pub(super) fn place_row(", "    a: u8,"];
    assert_eq!(first_function(item.into_iter()), Some("place_row"));
    assert_eq!(first_function(["struct Row {", "}"].into_iter()), None);
}

/// One module style: a module with children is a folder with its `mod.rs`,
/// never a `foo.rs` beside a `foo/` folder.
#[test]
fn a_module_with_children_is_a_folder_with_its_mod_rs() {
    let beside: Vec<String> = files_under(&["src"])
        .into_iter()
        .filter(|file| file.extension().is_some_and(|ext| ext == "rs") && file.with_extension("").is_dir())
        .map(|file| file.display().to_string())
        .collect();
    assert!(
        beside.is_empty(),
        "modules written as a file beside their folder (move each to its folder's mod.rs): {beside:?}"
    );
}
