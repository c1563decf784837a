//! GLOC: analysis, completion, hover text and formatting, all from `gloc-engine`.

use std::path::Path;

use gloc_engine::sensors::SensorList;

use crate::analysis::{Analysis, Completion, Context, Signature, Symbol, TokenKind};

pub fn analyze(_text: &str, _context: &Context) -> Analysis {
    Analysis::default()
}

pub fn completions(
    _text: &str,
    _offset: usize,
    _analysis: &Analysis,
    _context: &Context,
) -> Vec<Completion> {
    Vec::new()
}

pub fn word_markdown(_word: &str, _kind: TokenKind) -> Option<String> {
    None
}

pub fn signature(_text: &str, _offset: usize) -> Option<Signature> {
    None
}

pub fn check_new_name(
    _symbol: &Symbol,
    _new_name: &str,
    _analysis: &Analysis,
) -> Result<(), String> {
    Err("not yet".into())
}

pub fn format(_text: &str) -> Option<String> {
    None
}

pub fn load_sensor_list(path: &Path) -> Result<SensorList, String> {
    Err(format!(
        "{}: sensor list files are not supported yet",
        path.display()
    ))
}
