//! `analyze_and_load` compiles once but must answer exactly what `analyze` and
//! `load_script` answer separately, on every fixture and example.

use std::path::Path;

use gloc_compiler::analysis::analyze_and_load;
use gloc_compiler::{analyze, load_script, CompileOptions, Language, LoadOptions, Optimization};
use gloc_engine::sensors::SensorList;

fn gbasic_files() -> Vec<std::path::PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for folder in [
        "examples",
        "tests/fixtures/gbasic/ok",
        "tests/fixtures/gbasic/err",
        "tests/fixtures/gbasic/run",
    ] {
        // These folders are part of the repository: a missing one is a broken
        // checkout, not a folder to skip.
        let entries = std::fs::read_dir(root.join(folder))
            .unwrap_or_else(|error| panic!("cannot read {folder}: {error}"));
        for entry in entries.flatten() {
            if entry.path().extension().is_some_and(|ext| ext == "gbas") {
                files.push(entry.path());
            }
        }
    }
    files
}

#[test]
fn one_compile_answers_what_the_two_calls_answer() {
    let sensors = SensorList::embedded();
    let files = gbasic_files();
    assert!(files.len() >= 10, "found only {} GBASIC files", files.len());
    let options = LoadOptions {
        optimization: Optimization::Plain,
        cycle_budget: Some(500),
    };
    for path in files {
        let text = std::fs::read_to_string(&path).expect("fixture is text");
        let (analysis, loaded) = analyze_and_load(&text, &sensors, &options);
        let separate_analysis = analyze(&text, &sensors, &CompileOptions::default());
        let separate_load = load_script(&text, Language::Gbasic, &sensors, &options);
        let name = path.display();
        assert_eq!(
            analysis.diagnostics, separate_analysis.diagnostics,
            "{name}"
        );
        assert_eq!(
            analysis.symbols.len(),
            separate_analysis.symbols.len(),
            "{name}"
        );
        assert_eq!(loaded.diagnostics, separate_load.diagnostics, "{name}");
        assert_eq!(loaded.gloc_text, separate_load.gloc_text, "{name}");
        assert_eq!(
            loaded.program.is_some(),
            separate_load.program.is_some(),
            "{name}"
        );
        assert_eq!(
            loaded.stats.as_ref().map(|stats| stats.instructions),
            separate_load.stats.as_ref().map(|stats| stats.instructions),
            "{name}"
        );
    }
}
