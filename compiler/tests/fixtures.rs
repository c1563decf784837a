//! Fixture tests: `tests/fixtures/gbasic/ok/*.gbas` compile to the `.gloc` beside
//! them (written by hand), and `err/*.gbas` give exactly the diagnostics in the
//! `.err` beside them, drawn under the lines in the one format of every test
//! (`gloc_testsupport::annotate`). Set `GLOC_BLESS=1` to print the GLOC and write
//! the `.err` files instead of comparing (then review them).

use std::path::{Path, PathBuf};

use gloc_compiler::{compile, load_script, CompileOptions, Language, LoadOptions, Optimization};
use gloc_engine::sensors::SensorList;
use gloc_engine::LineIndex;

fn fixture_dir(kind: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/gbasic")
        .join(kind)
}

fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("fixture folder exists")
        .map(|entry| entry.expect("readable entry").path())
        .filter(|path| {
            path.extension()
                .is_some_and(|extension| extension == "gbas")
        })
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no fixtures in {}", dir.display());
    files
}

fn render(text: &str, diagnostics: &[gloc_engine::Diagnostic]) -> String {
    let index = LineIndex::new(text);
    let mut rendered = String::new();
    for diagnostic in diagnostics {
        let (line, column) = index.line_col(text, diagnostic.span.start as usize);
        rendered.push_str(&format!(
            "{line}:{column} {} {}\n",
            diagnostic.code, diagnostic.message
        ));
        if let Some(help) = &diagnostic.help {
            rendered.push_str(&format!("  help: {help}\n"));
        }
    }
    rendered
}

#[test]
fn ok_fixtures_compile_to_their_gloc_and_pass_the_gloc_checker() {
    let sensors = SensorList::embedded();
    for path in sources(&fixture_dir("ok")) {
        let text = std::fs::read_to_string(&path).expect("readable fixture");
        let compiled = compile(&text, &sensors, &CompileOptions::default());
        assert!(
            !compiled.has_errors(),
            "{}: {}",
            path.display(),
            render(&text, &compiled.diagnostics)
        );
        let gloc = compiled.code.expect("no errors, so GLOC").gloc_text;
        if std::env::var_os("GLOC_BLESS").is_some() {
            println!("== {}\n{gloc}", path.display());
            continue;
        }
        let expected = std::fs::read_to_string(path.with_extension("gloc"))
            .expect("expected .gloc beside the fixture");
        assert_eq!(gloc, expected, "{}", path.display());
        for optimization in [Optimization::Plain, Optimization::Optimized] {
            let loaded = load_script(
                &text,
                Language::Gbasic,
                &sensors,
                &LoadOptions::from(optimization),
            );
            assert!(
                loaded.program.is_some(),
                "{} (optimization {optimization:?}): {}",
                path.display(),
                render(&text, &loaded.diagnostics)
            );
        }
    }
}

#[test]
fn err_fixtures_give_their_diagnostics_and_no_gloc() {
    let sensors = SensorList::embedded();
    for path in sources(&fixture_dir("err")) {
        let text = std::fs::read_to_string(&path).expect("readable fixture");
        let compiled = compile(&text, &sensors, &CompileOptions::default());
        assert!(
            compiled.code.is_none(),
            "{} compiled despite errors",
            path.display()
        );
        gloc_testsupport::expect_diagnostics(&path, &text, &compiled.diagnostics);
        for diagnostic in &compiled.diagnostics {
            assert!(
                diagnostic.span.end as usize <= text.len(),
                "{}: span out of bounds",
                path.display()
            );
        }
    }
}

#[test]
fn the_paper_figure_3_example_is_figure_3() {
    // examples/fig3.gbas must be the paper's Fig. 3 exactly (line numbers removed).
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/fig3.gbas");
    let text = std::fs::read_to_string(path).expect("examples/fig3.gbas");
    let fig3 = "label: state1\nif m_depth > 15.0 then\n  SCI_RUHP_BEHS = 128\n  goto state2\nendif\nyield\ngoto state1\nlabel: state2\nif m_depth < 5.0 then\n  SCI_RUHP_BEHS = 0\n  goto state3\nendif\nyield\ngoto state2\nlabel: state3\nyield\ngoto state3\n";
    assert_eq!(text, fig3);
}

#[test]
fn gloc_checker_findings_on_compiled_code_point_at_the_gbasic_statement() {
    let sensors = SensorList::embedded();
    let text = "dim x as integer\ngoto spin\nx = x + 1\nlabel: spin\n  goto spin\n";
    let loaded = load_script(text, Language::Gbasic, &sensors, &LoadOptions::default());
    assert!(
        loaded.program.is_none(),
        "a loop with neither yield nor exit is refused"
    );
    let rendered = render(text, &loaded.diagnostics);
    // Worked out by hand: `x = x + 1` (line 3) is unreachable after `goto`, and the
    // `goto spin` loop (line 5, indented by two) never yields.
    assert!(
        rendered.contains("3:1 W0112 unreachable code"),
        "{rendered}"
    );
    assert!(
        rendered.contains("5:3 E0111 this loop never yields and has no way out"),
        "{rendered}"
    );
    let spin = loaded
        .diagnostics
        .iter()
        .find(|d| d.code == "E0111")
        .expect("E0111");
    assert_eq!(&text[spin.span.range()], "goto spin");
}

#[test]
fn the_optimized_source_map_follows_the_renumbered_labels() {
    let sensors = SensorList::embedded();
    let text = std::fs::read_to_string(fixture_dir("ok").join("fig3.gbas")).expect("fig3");
    let compiled = compile(
        &text,
        &sensors,
        &CompileOptions {
            optimization: Optimization::Optimized,
        },
    );
    let code = compiled.code.expect("compiles");
    let map = code.build.source_map;
    let labels: Vec<(&str, u32)> = map
        .labels
        .iter()
        .map(|label| (label.name.as_str(), label.number))
        .collect();
    // -O keeps every label of Fig. 2 (all are jump targets) and numbers them in order
    // of appearance: state1, the first if's two, state2, the second if's two, state3.
    assert_eq!(labels, vec![("state1", 0), ("state2", 3), ("state3", 6)]);
    let gloc = code.gloc_text;
    assert!(
        gloc.contains("label 3\nloads 444,r0\nloadd 5.0,r1\n"),
        "{gloc}"
    );
}
