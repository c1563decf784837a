//! The tidy checks, as rust-analyzer's `tidy.rs` does them: habits of the house that a
//! compiler does not enforce, each a function returning the problems it found (empty:
//! clean). `cargo xtask tidy` prints them; `xtask/tests/tidy.rs` fails on any.
//!
//! - every Rust module opens with a `//!` line saying what it is for;
//! - every crate takes the workspace's lints, and lsp and dap deny `print_stdout`;
//! - `unsafe` is forbidden in every crate but the engine;
//! - every diagnostic code in the sources is in the registry;
//! - no function outside tests is longer than [`MAX_FUNCTION_LINES`], except the few
//!   listed in [`LONG_FUNCTIONS`], which may not grow (a ratchet);
//! - no two modules of `cli` or `dap` import each other, directly or round a circle,
//!   except the circles listed in [`KNOWN_CIRCLES`] (a ratchet too);
//! - each crate depends on exactly the workspace crates the picture of the layers in
//!   ARCHITECTURE.md gives it (`name ──► a, b, c`), so the picture is the truth.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The longest a function outside tests may be.
pub const MAX_FUNCTION_LINES: usize = 150;

/// Functions longer than [`MAX_FUNCTION_LINES`], with their length when last measured:
/// each may shrink, none may grow, and no other may join them.
pub const LONG_FUNCTIONS: &[(&str, &str, usize)] = &[];

/// Import circles between the modules of a crate when the check came in (each listed by
/// its modules in name order): they may be broken, no new one may appear.
pub const KNOWN_CIRCLES: &[&[&str]] = &[];

/// The workspace's root (this crate sits in it).
pub fn workspace_root() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent()
        .map_or_else(|| here.to_path_buf(), Path::to_path_buf)
}

/// The workspace's member crates, read from the root Cargo.toml.
pub fn members(root: &Path) -> Vec<String> {
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap_or_default();
    let Some(start) = manifest.find("members = [") else {
        return Vec::new();
    };
    let end = start + manifest[start..].find(']').unwrap_or(0);
    manifest[start..end]
        .split('"')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// Every `.rs` file under `dir`, skipping build output and hidden folders.
pub fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            if path.is_dir() {
                if name != "target" && !name.starts_with('.') && name != "node_modules" {
                    pending.push(path);
                }
            } else if name.ends_with(".rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

fn shown(root: &Path, path: &Path) -> String {
    path.strip_prefix(root)
        .unwrap_or(path)
        .display()
        .to_string()
}

/// Every member's Rust files (sources, tests, benches).
fn member_files(root: &Path) -> Vec<PathBuf> {
    members(root)
        .iter()
        .flat_map(|member| rust_files(&root.join(member)))
        .collect()
}

/// Files that do not open with a `//!` line.
pub fn module_docs(root: &Path) -> Vec<String> {
    member_files(root)
        .iter()
        .filter(|path| {
            let text = std::fs::read_to_string(path).unwrap_or_default();
            !text.trim_start().starts_with("//!")
        })
        .map(|path| {
            format!(
                "{}: does not open with a `//!` line saying what it is for",
                shown(root, path)
            )
        })
        .collect()
}

/// Crates that do not take the workspace's lints; lints the workspace must deny.
pub fn workspace_lints(root: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap_or_default();
    for lint in [
        "unwrap_used",
        "dbg_macro",
        "todo",
        "undocumented_unsafe_blocks",
    ] {
        if !manifest.contains(&format!("{lint} = \"deny\"")) {
            problems.push(format!(
                "Cargo.toml: [workspace.lints] must deny clippy::{lint}"
            ));
        }
    }
    for member in members(root) {
        let text =
            std::fs::read_to_string(root.join(&member).join("Cargo.toml")).unwrap_or_default();
        if !text.contains("[lints]\nworkspace = true") {
            problems.push(format!(
                "{member}/Cargo.toml: does not take the workspace lints (`[lints] workspace = true`)"
            ));
        }
    }
    for protocol in ["lsp", "dap"] {
        let lib =
            std::fs::read_to_string(root.join(protocol).join("src/lib.rs")).unwrap_or_default();
        if !lib.contains("#![deny(clippy::print_stdout)]") {
            problems.push(format!(
                "{protocol}/src/lib.rs: its stdout is its protocol, so it must deny print_stdout"
            ));
        }
    }
    problems
}

/// Crate roots (other than the engine's) without `#![forbid(unsafe_code)]`.
pub fn unsafe_outside_the_engine(root: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    for member in members(root) {
        if member == "engine" {
            continue;
        }
        for crate_root in ["src/lib.rs", "src/main.rs"] {
            let path = root.join(&member).join(crate_root);
            let Ok(text) = std::fs::read_to_string(&path) else {
                continue;
            };
            if !text.contains("#![forbid(unsafe_code)]") {
                problems.push(format!(
                    "{}: only the engine may use `unsafe`: add `#![forbid(unsafe_code)]`",
                    shown(root, &path)
                ));
            }
        }
    }
    problems
}

/// The code literals (`"E0101"`, `"W2302"`, `"S0107"`) in the non-test part of a file
/// (before its first `#[cfg(test)]`), with their line numbers.
fn code_literals(text: &str) -> Vec<(usize, String)> {
    let code_part = text.split("#[cfg(test)]").next().unwrap_or("");
    let mut found = Vec::new();
    for (number, line) in code_part.lines().enumerate() {
        let bytes = line.as_bytes();
        for start in 0..bytes.len().saturating_sub(6) {
            let candidate = &bytes[start..start + 7];
            if candidate[0] == b'"'
                && candidate[6] == b'"'
                && matches!(candidate[1], b'E' | b'W' | b'S')
                && candidate[2..6].iter().all(u8::is_ascii_digit)
            {
                found.push((number + 1, line[start + 1..start + 6].to_string()));
            }
        }
    }
    found
}

/// Diagnostic codes written in the sources but missing from the registry, and how many
/// code literals were seen (so a test can tell that the scan still finds them).
pub fn unregistered_codes(root: &Path) -> (Vec<String>, usize) {
    let mut problems = Vec::new();
    let mut seen = 0;
    for member in members(root) {
        for path in rust_files(&root.join(&member).join("src")) {
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            for (line, code) in code_literals(&text) {
                seen += 1;
                if gloc_engine::codes::lookup(&code).is_none() {
                    problems.push(format!(
                        "{}:{line}: {code} is not in gloc_engine::codes (register it there, with a \
                         one-line doc, and in docs/diagnostics.md)",
                        shown(root, &path)
                    ));
                }
            }
        }
    }
    (problems, seen)
}

/// A line with its comments, strings and character literals blanked, so braces and
/// keywords in them do not count. Block comments are rare here and not handled.
fn code_only(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut chars = line.chars().peekable();
    let mut in_string = false;
    while let Some(c) = chars.next() {
        if in_string {
            match c {
                '\\' => {
                    chars.next();
                }
                '"' => {
                    in_string = false;
                    out.push('"');
                }
                _ => {}
            }
            continue;
        }
        match c {
            '"' => {
                in_string = true;
                out.push('"');
            }
            '/' if chars.peek() == Some(&'/') => break,
            '\'' => {
                // A character literal ('{', '\n', '\'') or a lifetime ('a).
                let rest: String = chars.clone().take(4).collect();
                let literal = if rest.starts_with('\\') {
                    rest.find('\'').filter(|&end| end >= 2).map(|end| end + 1)
                } else if rest.chars().nth(1) == Some('\'') {
                    Some(2)
                } else {
                    None
                };
                match literal {
                    Some(length) => {
                        for _ in 0..length {
                            chars.next();
                        }
                        out.push_str("' '");
                    }
                    None => out.push('\''),
                }
            }
            _ => out.push(c),
        }
    }
    out
}

/// The name of the function a line starts (`fn name`, with any qualifiers), if it does.
fn function_name(code: &str) -> Option<String> {
    let words: Vec<&str> = code.split_whitespace().collect();
    let position = words.iter().position(|word| *word == "fn")?;
    let qualifiers_only = words[..position].iter().all(|word| {
        matches!(
            *word,
            "pub" | "const" | "async" | "unsafe" | "extern" | "\"C\"" | "default"
        ) || word.starts_with("pub(")
    });
    if !qualifiers_only {
        return None;
    }
    let name: String = words
        .get(position + 1)?
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    (!name.is_empty()).then_some(name)
}

/// Every function of a file outside `#[cfg(test)]` modules: (name, first line, lines).
pub fn function_lengths(text: &str) -> Vec<(String, usize, usize)> {
    let mut found = Vec::new();
    // Open functions: (name, first line, the depth their body opens at).
    let mut open: Vec<(String, usize, usize)> = Vec::new();
    let mut pending: Option<(String, usize)> = None;
    let mut depth = 0usize;
    let mut test_module_depth: Option<usize> = None;
    let mut test_attribute = false;
    for (index, line) in text.lines().enumerate() {
        let code = code_only(line);
        if code.trim_start().starts_with("#[cfg(test)]") {
            test_attribute = true;
        }
        if test_module_depth.is_none() {
            if let Some(name) = function_name(&code) {
                pending = Some((name, index));
            }
        }
        for c in code.chars() {
            match c {
                '{' => {
                    if test_attribute && test_module_depth.is_none() {
                        test_module_depth = Some(depth);
                        test_attribute = false;
                    }
                    if let Some((name, start)) = pending.take() {
                        open.push((name, start, depth));
                    }
                    depth += 1;
                }
                '}' => {
                    depth = depth.saturating_sub(1);
                    if open.last().is_some_and(|(_, _, at)| *at == depth) {
                        if let Some((name, start, _)) = open.pop() {
                            found.push((name, start + 1, index - start + 1));
                        }
                    }
                    if test_module_depth == Some(depth) {
                        test_module_depth = None;
                    }
                }
                // `fn f();` in a trait: no body.
                ';' if pending.as_ref().is_some_and(|(_, start)| *start == index) => {
                    pending = None;
                }
                _ => {}
            }
        }
        if !code.trim().is_empty() && !code.trim_start().starts_with("#[") {
            test_attribute = test_attribute && code.trim_start().starts_with("#[");
        }
    }
    found
}

/// Functions in the members' `src/` longer than [`MAX_FUNCTION_LINES`] and not in
/// [`LONG_FUNCTIONS`], or grown past their entry there.
pub fn long_functions(root: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    for member in members(root) {
        for path in rust_files(&root.join(&member).join("src")) {
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            let file = shown(root, &path);
            for (name, line, length) in function_lengths(&text) {
                if length <= MAX_FUNCTION_LINES {
                    continue;
                }
                let allowed = LONG_FUNCTIONS
                    .iter()
                    .find(|(at, known, _)| *at == file && *known == name)
                    .map(|(_, _, limit)| *limit);
                match allowed {
                    Some(limit) if length <= limit => {}
                    Some(limit) => problems.push(format!(
                        "{file}:{line}: `{name}` is {length} lines, more than the {limit} it was \
                         allowed when the check came in: split it by concern"
                    )),
                    None => problems.push(format!(
                        "{file}:{line}: `{name}` is {length} lines, more than {MAX_FUNCTION_LINES}: \
                         split it by concern"
                    )),
                }
            }
        }
    }
    problems
}

/// The modules of a crate's `src/` and the modules each names (`crate::NAME`).
fn module_graph(root: &Path, krate: &str) -> BTreeMap<String, BTreeSet<String>> {
    let src = root.join(krate).join("src");
    let mut graph = BTreeMap::new();
    for path in rust_files(&src) {
        let Ok(relative) = path.strip_prefix(&src) else {
            continue;
        };
        // A module is its top-level file (`a.rs` and `a/b.rs` are both `a`).
        let module = relative
            .components()
            .next()
            .map(|part| {
                part.as_os_str()
                    .to_string_lossy()
                    .trim_end_matches(".rs")
                    .to_string()
            })
            .unwrap_or_default();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let code_part = text.split("#[cfg(test)]").next().unwrap_or("");
        let uses: &mut BTreeSet<String> = graph.entry(module.clone()).or_default();
        for (at, _) in code_part.match_indices("crate::") {
            let name: String = code_part[at + "crate::".len()..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() && name != module {
                uses.insert(name);
            }
        }
    }
    graph
}

/// The strongly connected components of more than one module (Tarjan, iteratively).
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let names: Vec<&String> = graph.keys().collect();
    let index_of: BTreeMap<&String, usize> =
        names.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let edges: Vec<Vec<usize>> = names
        .iter()
        .map(|name| {
            graph[*name]
                .iter()
                .filter_map(|to| index_of.get(to).copied())
                .collect()
        })
        .collect();
    let count = names.len();
    let (mut index, mut low) = (vec![usize::MAX; count], vec![0; count]);
    let (mut on_stack, mut stack) = (vec![false; count], Vec::new());
    let mut next = 0;
    let mut components = Vec::new();
    for start in 0..count {
        if index[start] != usize::MAX {
            continue;
        }
        // (node, the next edge to look at)
        let mut work = vec![(start, 0usize)];
        while let Some(&mut (node, ref mut edge)) = work.last_mut() {
            if *edge == 0 && index[node] == usize::MAX {
                index[node] = next;
                low[node] = next;
                next += 1;
                stack.push(node);
                on_stack[node] = true;
            }
            if let Some(&to) = edges[node].get(*edge) {
                *edge += 1;
                if index[to] == usize::MAX {
                    work.push((to, 0));
                } else if on_stack[to] {
                    low[node] = low[node].min(index[to]);
                }
                continue;
            }
            work.pop();
            if let Some(&(parent, _)) = work.last() {
                low[parent] = low[parent].min(low[node]);
            }
            if low[node] == index[node] {
                let mut component = Vec::new();
                while let Some(member) = stack.pop() {
                    on_stack[member] = false;
                    component.push(names[member].clone());
                    if member == node {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    components.push(component);
                }
            }
        }
    }
    components
}

/// Import circles between the modules of `cli` and `dap` not in [`KNOWN_CIRCLES`] (a
/// circle that grew counts as new).
pub fn import_circles(root: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    for krate in ["cli", "dap"] {
        for circle in circles(&module_graph(root, krate)) {
            let files: Vec<String> = circle
                .iter()
                .map(|module| format!("{krate}/src/{module}.rs"))
                .collect();
            let known = KNOWN_CIRCLES.iter().any(|allowed| {
                files
                    .iter()
                    .all(|file| allowed.iter().any(|known| known == file))
            });
            if !known {
                problems.push(format!(
                    "{krate}: these modules import each other round a circle: {}; move what \
                     they share into a module of its own",
                    files.join(", ")
                ));
            }
        }
    }
    problems
}

/// Every check's problems, in order.
pub fn all(root: &Path) -> Vec<String> {
    let mut problems = module_docs(root);
    problems.extend(workspace_lints(root));
    problems.extend(unsafe_outside_the_engine(root));
    problems.extend(unregistered_codes(root).0);
    problems.extend(long_functions(root));
    problems.extend(import_circles(root));
    problems.extend(layers(root));
    problems
}

/// The layers as ARCHITECTURE.md draws them: each ` folder ──► a, b, c   what it is`
/// line of its crate picture (a crate with no arrow depends on no workspace crate).
pub fn drawn_layers(architecture: &str) -> BTreeMap<String, BTreeSet<String>> {
    let mut layers = BTreeMap::new();
    let Some(start) = architecture.find("The crates and what each depends on") else {
        return layers;
    };
    let Some(block) = architecture[start..].split("```").nth(1) else {
        return layers;
    };
    for line in block.lines() {
        let Some(name) = line.split_whitespace().next() else {
            continue;
        };
        let depends = match line.split_once("──►") {
            Some((_, rest)) => {
                // The list ends at the first run of two spaces (the description).
                let list = rest.trim_start().split("  ").next().unwrap_or("");
                list.split(',')
                    .map(|name| name.trim().to_string())
                    .filter(|name| !name.is_empty())
                    .collect()
            }
            None => BTreeSet::new(),
        };
        layers.insert(name.to_string(), depends);
    }
    layers
}

/// The workspace crates a member's manifest lists under `[dependencies]` (not dev or
/// build dependencies), by folder name.
fn manifest_dependencies(manifest: &str, folders: &BTreeMap<String, String>) -> BTreeSet<String> {
    let mut section = "";
    let mut found = BTreeSet::new();
    for line in manifest.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            section = line;
            continue;
        }
        if section != "[dependencies]" {
            continue;
        }
        let key = line.split(['.', '=', ' ']).next().unwrap_or("");
        if let Some(folder) = folders.get(key) {
            found.insert(folder.clone());
        }
    }
    found
}

/// Each member's workspace dependencies against the picture in ARCHITECTURE.md.
pub fn layers(root: &Path) -> Vec<String> {
    let architecture = std::fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap_or_default();
    let drawn = drawn_layers(&architecture);
    let members = members(root);
    let manifest = |member: &str| {
        std::fs::read_to_string(root.join(member).join("Cargo.toml")).unwrap_or_default()
    };
    // Package name → folder.
    let folders: BTreeMap<String, String> = members
        .iter()
        .filter_map(|member| {
            let text = manifest(member);
            let name = text
                .lines()
                .find_map(|line| line.trim().strip_prefix("name = "))?
                .trim_matches('"')
                .to_string();
            Some((name, member.clone()))
        })
        .collect();
    let mut problems = Vec::new();
    // The picture lists front ends first: a crate may depend only on crates drawn
    // below it, so no dependency runs back up the layers.
    let order: Vec<&str> = architecture
        .split("The crates and what each depends on")
        .nth(1)
        .and_then(|rest| rest.split("```").nth(1))
        .unwrap_or("")
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .collect();
    let position = |name: &str| order.iter().position(|drawn| *drawn == name);
    for (member, depends) in &drawn {
        for dependency in depends {
            if position(dependency) <= position(member) {
                problems.push(format!(
                    "ARCHITECTURE.md: {member} depends on {dependency}, which is not drawn below it"
                ));
            }
        }
    }
    for member in &members {
        let Some(expected) = drawn.get(member) else {
            problems.push(format!(
                "{member}: not in ARCHITECTURE.md's picture of the crates and their dependencies"
            ));
            continue;
        };
        let actual = manifest_dependencies(&manifest(member), &folders);
        if &actual != expected {
            let extra: Vec<&String> = actual.difference(expected).collect();
            let missing: Vec<&String> = expected.difference(&actual).collect();
            problems.push(format!(
                "{member}/Cargo.toml depends on {actual:?}, ARCHITECTURE.md draws {expected:?} \
                 (not drawn: {extra:?}; drawn but not a dependency: {missing:?}): change the \
                 dependency or the picture, and keep no dependency running back up the layers"
            ));
        }
    }
    problems
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn function_lengths_count_from_fn_to_the_closing_brace_outside_tests() {
        let text = "fn a() {\n    let x = '{';\n    // }\n    let s = \"}\";\n}\n\nimpl X {\n    pub(crate) fn b(&self) -> u8 {\n        1\n    }\n}\n#[cfg(test)]\nmod tests {\n    fn c() {\n    }\n}\n";
        assert_eq!(
            function_lengths(text),
            vec![("a".to_string(), 1, 5), ("b".to_string(), 8, 3)]
        );
    }

    #[test]
    fn the_picture_of_the_layers_is_read_line_by_line() {
        let text = "The crates and what each depends on (…):\n\n```\n cli      ──► lsp, engine   (clap)\n engine                    the core\n```\n";
        let layers = drawn_layers(text);
        assert_eq!(
            layers.get("cli"),
            Some(&BTreeSet::from(["lsp".to_string(), "engine".to_string()]))
        );
        assert_eq!(layers.get("engine"), Some(&BTreeSet::new()));
        let folders = BTreeMap::from([("gloc-engine".to_string(), "engine".to_string())]);
        let manifest =
            "[dependencies]\ngloc-engine.workspace = true\n[dev-dependencies]\ngloc-lsp = 1\n";
        assert_eq!(
            manifest_dependencies(manifest, &folders),
            BTreeSet::from(["engine".to_string()])
        );
    }

    #[test]
    fn a_circle_of_three_modules_is_one_component() {
        let mut graph = BTreeMap::new();
        for (from, to) in [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")] {
            graph
                .entry(from.to_string())
                .or_insert_with(BTreeSet::new)
                .insert(to.to_string());
        }
        graph.insert("d".to_string(), BTreeSet::new());
        assert_eq!(
            circles(&graph),
            vec![vec!["a".to_string(), "b".to_string(), "c".to_string()]]
        );
    }
}
