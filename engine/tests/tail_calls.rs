//! The threaded interpreter's handlers (`src/vm/threaded.rs`) tail-call in the
//! release build: each one ends by jumping to the next handler, never by
//! calling it (a call per op would grow the stack until it overflows).
//!
//! Rust does not guarantee tail calls, so this reads the machine code: it
//! builds `gloc-engine` with the release profile (into its own target
//! directory, `target/tail-calls`, so that it never waits on the lock of the
//! build running this test), disassembles the library with `objdump` (GNU
//! binutils; the test fails, it does not skip, when `objdump` is missing) and
//! checks every handler (every function named `vm::threaded::op_*`; each one
//! that the op table or `fused_handler` names must be among them): no indirect call through a
//! register (how a call to the next handler looks), and an indirect jump
//! through a register (the tail call) in every handler that goes on to a next op.
#![cfg(all(
    target_os = "linux",
    any(target_arch = "x86_64", target_arch = "aarch64")
))]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The demangled path of the handlers: `vm::threaded::op_*`.
const PREFIX: &str = "gloc_engine::vm::threaded::";

/// Handlers that stop the threaded code instead of going on: they return.
const STOPPING: [&str; 3] = ["op_yield", "op_halt", "op_output"];

/// The handler names `Slot::new` chooses from, read from the source: the plain ops'
/// in the op table (`src/vm/code.rs`), the fused ops' in `fused_handler`.
fn handler_names() -> BTreeSet<String> {
    let read = |file: &str| {
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(file))
            .unwrap_or_else(|error| panic!("{file} is readable: {error}"))
    };
    let table = read("src/vm/code.rs");
    let start = table
        .find("macro_rules! op_table {")
        .and_then(|at| table[at..].find("plain {").map(|plain| at + plain))
        .expect("the op table names each plain op's handler");
    let end = start
        + table[start..]
            .find("pub(super) use op_table;")
            .expect("the op table ends");
    let source = read("src/vm/threaded.rs");
    let fused_start = source
        .find("fn fused_handler(")
        .expect("the fused ops' handlers are chosen in fused_handler");
    let fused_end = fused_start
        + source[fused_start..]
            .find("\n}\n")
            .expect("fused_handler ends");
    let body = format!(
        "{}\n{}",
        &table[start..end],
        &source[fused_start..fused_end]
    );
    let mut names = BTreeSet::new();
    for (index, _) in body.match_indices("op_") {
        let boundary = index == 0
            || !body[..index]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_');
        if !boundary {
            continue;
        }
        let name: String = body[index..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        names.insert(name);
    }
    names
}

/// Builds the release library and returns its path.
fn release_library() -> PathBuf {
    let manifest_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target_dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest_dir.join("../target"))
        .join("tail-calls");
    let status = Command::new(env!("CARGO"))
        .current_dir(manifest_dir)
        .args(["build", "--release", "--offline", "--quiet", "--lib"])
        .args(["-p", "gloc-engine", "--target-dir"])
        .arg(&target_dir)
        .status()
        .expect("cargo runs");
    assert!(status.success(), "the release build of gloc-engine failed");
    target_dir.join("release/libgloc_engine.rlib")
}

/// The disassembly of `library`, one entry per function: name → instructions.
fn disassemble(library: &Path) -> BTreeMap<String, Vec<Vec<String>>> {
    let output = Command::new("objdump")
        .args(["-d", "-C", "--no-show-raw-insn"])
        .arg(library)
        .output()
        .unwrap_or_else(|error| {
            panic!(
                "could not run objdump ({error}): install GNU binutils \
                 (apt-get install binutils); this test reads the disassembly"
            )
        });
    assert!(
        output.status.success(),
        "objdump failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = String::from_utf8_lossy(&output.stdout);
    let mut functions: BTreeMap<String, Vec<Vec<String>>> = BTreeMap::new();
    let mut current: Option<(String, Vec<String>)> = None;
    for line in text.lines() {
        // A symbol: `0000000000000000 <gloc_engine::vm::threaded::op_add>:`.
        if let Some(name) = line
            .split_once(" <")
            .filter(|(address, _)| address.chars().all(|c| c.is_ascii_hexdigit()))
            .and_then(|(_, rest)| rest.strip_suffix(">:"))
        {
            if let Some((name, body)) = current.take() {
                functions.entry(name).or_default().push(body);
            }
            current = Some((name.to_string(), Vec::new()));
        } else if let (Some((_, body)), Some((_, instruction))) =
            (current.as_mut(), line.split_once(":\t"))
        {
            body.push(instruction.trim().to_string());
        }
    }
    if let Some((name, body)) = current {
        functions.entry(name).or_default().push(body);
    }
    functions
}

/// Splits an instruction into its mnemonic and operands.
fn parts(instruction: &str) -> (&str, &str) {
    let instruction = instruction.split('#').next().unwrap_or("").trim();
    let (mnemonic, operands) = instruction
        .split_once(char::is_whitespace)
        .unwrap_or((instruction, ""));
    (mnemonic, operands.trim())
}

/// A transfer through a register (or memory addressed by one): where the next
/// handler's address comes from. A call through the GOT (`*0x0(%rip)`, a
/// library function such as `fmod`) is not one.
fn through_register(operands: &str) -> bool {
    if cfg!(target_arch = "aarch64") {
        operands.starts_with('x')
    } else {
        operands.starts_with('*') && operands.contains("%r") && !operands.contains("(%rip)")
    }
}

fn is_indirect_call(instruction: &str) -> bool {
    let (mnemonic, operands) = parts(instruction);
    match mnemonic {
        "call" | "callq" => through_register(operands),
        "blr" => true,
        _ => false,
    }
}

fn is_indirect_jump(instruction: &str) -> bool {
    let (mnemonic, operands) = parts(instruction);
    match mnemonic {
        "jmp" | "jmpq" => through_register(operands),
        "br" => true,
        _ => false,
    }
}

#[test]
fn every_handler_of_the_release_build_ends_in_a_jump() {
    let names = handler_names();
    assert!(
        names.len() >= 45,
        "Slot::new names {} handlers: {names:?}",
        names.len()
    );
    let functions = disassemble(&release_library());
    let mut problems = Vec::new();
    for name in &names {
        if !functions.contains_key(&format!("{PREFIX}{name}")) {
            problems.push(format!("{name}: not in the disassembly"));
        }
    }
    let handlers = functions
        .iter()
        .filter_map(|(name, bodies)| Some((name.strip_prefix(PREFIX)?, bodies)))
        .filter(|(name, _)| name.starts_with("op_"));
    for (name, bodies) in handlers {
        for body in bodies {
            for instruction in body.iter().filter(|i| is_indirect_call(i)) {
                problems.push(format!(
                    "{name}: `{instruction}` calls through a register (a handler must jump to the next one)"
                ));
            }
            let jumps = body.iter().any(|i| is_indirect_jump(i));
            if !STOPPING.contains(&name) && !jumps {
                problems.push(format!(
                    "{name}: no indirect jump, so no tail call to the next handler:\n  {}",
                    body.join("\n  ")
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checks_recognise_calls_and_jumps() {
    // What a handler that calls the next one compiles to, and what a tail call
    // and a library call compile to (x86-64 AT&T syntax, as objdump prints it).
    if cfg!(target_arch = "x86_64") {
        assert!(is_indirect_call("call   *%rax"));
        assert!(is_indirect_call("call   *0x98(%rdi)"));
        assert!(!is_indirect_call(
            "call   *0x0(%rip)        # 63 <gloc_engine::vm::threaded::op_mod_k+0x63>"
        ));
        assert!(!is_indirect_call("call   34 <f+0x34>"));
        assert!(is_indirect_jump("jmp    *%r9"));
        assert!(!is_indirect_jump("jmp    4c <f+0x4c>"));
    } else {
        assert!(is_indirect_call("blr\tx8"));
        assert!(is_indirect_jump("br\tx8"));
        assert!(!is_indirect_call("bl\t0 <fmod>"));
    }
}
