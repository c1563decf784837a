//! Signature help: the built-in function or instruction whose arguments the
//! cursor is in, and which argument.

use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::analysis::Signature;
use crate::{gbasic_lang, gloc_lang, Language};

pub fn signature_help(language: Language, text: &str, offset: usize) -> Option<Signature> {
    catch_unwind(AssertUnwindSafe(|| match language {
        Language::Gloc => gloc_lang::signature(text, offset),
        Language::Gbasic => gbasic_lang::signature(text, offset),
        Language::Config | Language::Mission | Language::MissionArgs => None,
    }))
    .ok()
    .flatten()
}
