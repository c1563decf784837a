//! GBASIC's built-in functions as a script sees them, against what docs/gbasic.md
//! says of each (worked by hand, not read from the table): the type of a call on
//! integer and on float arguments, the GLOC instruction it compiles to, the name
//! reserved; and the editor grammars colour exactly the table's names.

use gloc_compiler::builtins::BUILTINS;
use gloc_compiler::{compile, CompileOptions};
use gloc_engine::sensors::SensorList;

/// Whether `expr` is an integer (assignable to an integer variable), and its GLOC.
fn typed(expr: &str) -> (bool, String) {
    let sensors = SensorList::embedded();
    let compile_with = |target: &str| {
        let source = format!(
            "dim i as integer\ndim f as float\ndim n as integer\ndim x as float\ni = 2\nf = 2.5\n{target} = {expr}\nprint {target}\n"
        );
        compile(&source, &sensors, &CompileOptions::default())
    };
    let as_float = compile_with("x");
    assert!(!as_float.has_errors(), "{expr}: {:?}", as_float.diagnostics);
    let as_integer = compile_with("n");
    (
        !as_integer.has_errors(),
        as_float.code.map(|code| code.gloc_text).unwrap_or_default(),
    )
}

#[test]
fn each_builtin_has_the_documented_type_and_instruction() {
    // (call, integer result?, an instruction its GLOC holds)
    let expected = [
        ("abs(i)", true, "abs "),
        ("abs(f)", false, "abs "),
        ("sqrt(i)", false, "sqrt "),
        ("sqrt(f)", false, "sqrt "),
        ("min(i, i)", true, "min "),
        ("min(i, f)", false, "min "),
        ("max(i, i)", true, "max "),
        ("max(f, i)", false, "max "),
        ("int(f)", true, "d2i "),
        ("int(i)", true, ""),
        ("float(i)", false, "i2d "),
        ("float(f)", false, ""),
    ];
    for (call, integer, instruction) in expected {
        let (is_integer, gloc) = typed(call);
        assert_eq!(is_integer, integer, "{call}");
        assert!(gloc.contains(instruction), "{call}: {gloc}");
    }
    // int(i) and float(f) are the value itself: no conversion instruction.
    assert!(!typed("int(i)").1.contains("d2i"));
    assert!(!typed("float(f)").1.contains("i2d"));
    // Every built-in of the table is among those worked out above.
    for info in BUILTINS {
        assert!(
            expected
                .iter()
                .any(|(call, ..)| call.starts_with(&format!("{}(", info.name))),
            "{} has no expectation here",
            info.name
        );
    }
}

#[test]
fn builtin_names_are_reserved_and_calls_check_their_arity() {
    let sensors = SensorList::embedded();
    for info in BUILTINS {
        let compiled = compile(
            &format!("dim {} as integer\n", info.name.to_ascii_uppercase()),
            &sensors,
            &CompileOptions::default(),
        );
        assert!(
            compiled
                .diagnostics
                .iter()
                // `float` is a type keyword as well.
                .any(|diagnostic| diagnostic.message.contains("built-in")
                    || diagnostic.message.contains("keyword")),
            "{}: {:?}",
            info.name,
            compiled.diagnostics
        );
        let too_many = vec!["1.5"; info.params.len() + 1].join(", ");
        let compiled = compile(
            &format!("dim x as float\nx = {}({too_many})\n", info.name),
            &sensors,
            &CompileOptions::default(),
        );
        assert!(compiled.has_errors(), "{}({too_many})", info.name);
    }
}

/// The names inside `(?i)\b(abs|sqrt|…)\b` or `\<\%(abs\|sqrt\|…\)\>`.
fn names_after(text: &str, marker: &str, separator: &str, end: &str) -> Vec<String> {
    let start = text
        .find(marker)
        .map(|at| at + marker.len())
        .unwrap_or(text.len());
    let rest = &text[start..];
    let inner = &rest[..rest.find(end).unwrap_or(rest.len())];
    let mut names: Vec<String> = inner.split(separator).map(str::to_string).collect();
    names.sort();
    names
}

#[test]
fn editor_grammars_colour_the_tables_names() {
    let mut table: Vec<String> = BUILTINS.iter().map(|info| info.name.to_string()).collect();
    table.sort();
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let vim = std::fs::read_to_string(format!("{root}/editors/nvim/syntax/gbasic.vim"))
        .expect("gbasic.vim");
    let vim_line = vim
        .lines()
        .find(|line| line.contains("gbasicBuiltin") && line.contains("syn match"))
        .expect("the gbasicBuiltin match");
    assert_eq!(names_after(vim_line, "\\<\\%(", "\\|", "\\)"), table);
    let code = std::fs::read_to_string(format!(
        "{root}/editors/vscode/syntaxes/gbasic.tmLanguage.json"
    ))
    .expect("gbasic.tmLanguage.json");
    let code_line = code
        .lines()
        .find(|line| line.contains("(?=\\\\s*\\\\()"))
        .expect("the built-in call pattern");
    assert_eq!(names_after(code_line, "\\\\b(", "|", ")"), table);
}
