//! No input makes the compiler panic: random bytes, and every fixture cut and
//! mutated at many places, go through parse, check, codegen, `-O`, the loader and
//! the analysis; every diagnostic span stays inside the text.

use std::path::Path;

use gloc_compiler::{
    analyze, compile, load_script, CompileOptions, Language, LoadOptions, Optimization,
};
use gloc_engine::sensors::SensorList;
use gloc_testsupport::Rng;

fn exercise(text: &str, sensors: &SensorList) {
    for optimization in [Optimization::Plain, Optimization::Optimized] {
        let compiled = compile(text, sensors, &CompileOptions { optimization });
        for diagnostic in &compiled.diagnostics {
            assert!(
                diagnostic.span.start <= diagnostic.span.end
                    && diagnostic.span.end as usize <= text.len(),
                "span {:?} outside a text of {} bytes: {text:?}",
                diagnostic.span,
                text.len()
            );
        }
        if compiled.has_errors() {
            assert!(compiled.code.is_none());
        }
        let loaded = load_script(
            text,
            Language::Gbasic,
            sensors,
            &LoadOptions {
                optimization,
                cycle_budget: Some(10_000),
            },
        );
        for diagnostic in &loaded.diagnostics {
            assert!(
                diagnostic.span.end as usize <= text.len(),
                "{diagnostic:?} in {text:?}"
            );
        }
    }
    let analysis = analyze(text, sensors, &CompileOptions::default());
    for block in &analysis.blocks {
        assert!(block.span.end as usize <= text.len());
    }
}

const WORDS: &[&str] = &[
    "if",
    "then",
    "else",
    "elseif",
    "endif",
    "end",
    "while",
    "wend",
    "do",
    "loop",
    "until",
    "for",
    "to",
    "step",
    "next",
    "exit",
    "dim",
    "as",
    "integer",
    "float",
    "const",
    "label:",
    "goto",
    "yield",
    "print",
    "rem",
    "(",
    ")",
    ",",
    "=",
    "<>",
    "\\",
    "/",
    "*",
    "-",
    "mod",
    "and",
    "not",
    "\"",
    "\n",
    "m_depth",
    "x",
    "a(1)",
    "1e999",
    "99999999999999999999",
    "é",
    "\0",
    "'",
];

#[test]
fn random_and_mutated_programs_never_panic() {
    let sensors = SensorList::embedded();
    let mut rng = Rng::new(0x9E37_79B9_7F4A_7C15);
    for _ in 0..150 {
        let length = rng.index(200);
        let bytes: Vec<u8> = (0..length).map(|_| rng.next_u64() as u8).collect();
        exercise(&String::from_utf8_lossy(&bytes), &sensors);
        let words: Vec<&str> = (0..rng.index(40))
            .map(|_| WORDS[rng.index(WORDS.len())])
            .collect();
        exercise(&words.join(" "), &sensors);
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut sources = Vec::new();
    for dir in [
        "tests/fixtures/gbasic/ok",
        "tests/fixtures/gbasic/err",
        "tests/fixtures/gbasic/run",
        "examples",
    ] {
        for entry in std::fs::read_dir(root.join(dir)).expect("fixture folder") {
            let path = entry.expect("entry").path();
            if path
                .extension()
                .is_some_and(|extension| extension == "gbas")
            {
                sources.push(std::fs::read_to_string(path).expect("readable"));
            }
        }
    }
    for source in &sources {
        let boundaries: Vec<usize> = (0..=source.len())
            .filter(|at| source.is_char_boundary(*at))
            .collect();
        for _ in 0..12 {
            // Cut at a random place, or splice a random word in, or drop a random line.
            let mut text = source.clone();
            match rng.index(3) {
                0 => text.truncate(boundaries[rng.index(boundaries.len())]),
                1 => text.insert_str(
                    boundaries[rng.index(boundaries.len())],
                    WORDS[rng.index(WORDS.len())],
                ),
                _ => {
                    let lines: Vec<&str> = source.lines().collect();
                    let drop = rng.index(lines.len());
                    text = lines
                        .iter()
                        .enumerate()
                        .filter(|(index, _)| *index != drop)
                        .map(|(_, line)| format!("{line}\n"))
                        .collect();
                }
            }
            exercise(&text, &sensors);
        }
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let sensors = SensorList::embedded();
    let deep_parens = format!(
        "dim x as integer\nx = {}1{}\n",
        "(".repeat(100_000),
        ")".repeat(100_000)
    );
    let deep_minus = format!("dim x as integer\nx = {}1\n", "-".repeat(100_000));
    let deep_not = format!("dim x as integer\nx = {}1\n", "not ".repeat(100_000));
    let deep_ifs = format!(
        "{}yield\n{}",
        "if 1 then\n".repeat(20_000),
        "endif\n".repeat(20_000)
    );
    for text in [deep_parens, deep_minus, deep_not, deep_ifs] {
        let compiled = compile(&text, &sensors, &CompileOptions::default());
        assert!(compiled
            .diagnostics
            .iter()
            .any(|diagnostic| diagnostic.code == "E2008"));
        assert!(compiled.code.is_none());
    }
    // 90 levels are fine.
    let fine = format!(
        "dim x as integer\nx = {}1{}\nprint x\n",
        "(".repeat(90),
        ")".repeat(90)
    );
    assert!(!compile(&fine, &sensors, &CompileOptions::default()).has_errors());
    let nested = format!("{}yield\n{}", "while 1\n".repeat(90), "wend\n".repeat(90));
    for optimization in [Optimization::Plain, Optimization::Optimized] {
        let loaded = load_script(
            &nested,
            Language::Gbasic,
            &sensors,
            &LoadOptions::from(optimization),
        );
        assert!(loaded.program.is_some(), "{:?}", loaded.diagnostics);
    }
}
