//! Helpers shared by the engine's integration tests.

use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::program::Program;
use gloc_engine::sensors::SensorList;

/// Parses and checks a GLOC script against the embedded sensor list; a script
/// with errors fails the test, naming them and showing the script.
pub fn program(text: &str) -> Arc<Program> {
    let parsed = gloc::parse(text);
    let checked = gloc::check(&parsed, &SensorList::embedded(), &CheckOptions::default());
    let errors: Vec<_> = checked
        .diagnostics
        .iter()
        .filter(|diagnostic| diagnostic.is_error())
        .collect();
    assert!(errors.is_empty(), "{errors:?}\n{text}");
    checked.program.expect("no errors")
}
