//! Code actions: the quick fixes carried by the diagnostics that touch a range.

use gloc_engine::Span;

use crate::analysis::{Analysis, TextEdit};

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct QuickFix {
    pub title: String,
    pub edit: TextEdit,
    /// Index into `Analysis::diagnostics` of the diagnostic it fixes.
    pub diagnostic: usize,
    /// The diagnostic's only fix.
    pub preferred: bool,
}

/// The fixes of every diagnostic whose span touches `wanted` (ends included).
pub fn quick_fixes(analysis: &Analysis, wanted: Span) -> Vec<QuickFix> {
    let mut fixes = Vec::new();
    for (index, diagnostic) in analysis.diagnostics.iter().enumerate() {
        let touches = diagnostic.span.start <= wanted.end && wanted.start <= diagnostic.span.end;
        if !touches {
            continue;
        }
        for fix in &diagnostic.fixes {
            fixes.push(QuickFix {
                title: fix.title.clone(),
                edit: TextEdit {
                    span: fix.span,
                    new_text: fix.replacement.clone(),
                },
                diagnostic: index,
                preferred: diagnostic.fixes.len() == 1,
            });
        }
    }
    fixes
}

/// The GLOC of a document for `gloc.compiledGloc`: a GLOC document is its own
/// GLOC; a GBASIC one's is its compilation, or why there is none.
pub fn compiled_gloc(
    language: crate::Language,
    text: &str,
    analysis: &Analysis,
) -> Result<String, String> {
    match language {
        crate::Language::Gbasic => {}
        crate::Language::Gloc => return Ok(text.to_string()),
        crate::Language::Config => {
            return Err("`gloc.compiledGloc` takes a GBASIC document, not gloc.toml".to_string())
        }
        crate::Language::Mission | crate::Language::MissionArgs => {
            return Err("`gloc.compiledGloc` takes a GBASIC document, not a mission".to_string())
        }
    }
    if let Some(gloc) = &analysis.compiled {
        return Ok(gloc.clone());
    }
    let errors = analysis
        .diagnostics
        .iter()
        .filter(|diagnostic| diagnostic.is_error())
        .count();
    Err(format!(
        "the program has {errors} error{}; fix {} to see its GLOC",
        if errors == 1 { "" } else { "s" },
        if errors == 1 { "it" } else { "them" }
    ))
}
