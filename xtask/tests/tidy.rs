//! Each tidy check over the real workspace: a problem fails the test that found it.

use xtask::tidy;

fn assert_clean(check: &str, problems: Vec<String>) {
    assert!(problems.is_empty(), "{check}:\n  {}", problems.join("\n  "));
}

#[test]
fn every_module_opens_with_a_doc_line() {
    let root = tidy::workspace_root();
    assert!(tidy::members(&root).len() >= 12);
    assert_clean("module docs", tidy::module_docs(&root));
}

#[test]
fn every_crate_takes_the_workspace_lints() {
    assert_clean("lints", tidy::workspace_lints(&tidy::workspace_root()));
}

#[test]
fn only_the_engine_may_use_unsafe() {
    assert_clean(
        "unsafe",
        tidy::unsafe_outside_the_engine(&tidy::workspace_root()),
    );
}

#[test]
fn every_diagnostic_code_in_the_sources_is_registered() {
    let (problems, seen) = tidy::unregistered_codes(&tidy::workspace_root());
    // The registry's own table is the one place codes are written as literals.
    assert!(
        seen >= 90,
        "only {seen} code literals found: is the registry still scanned?"
    );
    assert_clean("codes", problems);
}

#[test]
fn no_function_outside_tests_is_over_150_lines_but_the_listed_ones() {
    assert_clean(
        "long functions",
        tidy::long_functions(&tidy::workspace_root()),
    );
}

#[test]
fn no_new_import_circle_in_cli_or_dap() {
    assert_clean(
        "import circles",
        tidy::import_circles(&tidy::workspace_root()),
    );
}

#[test]
fn each_crate_depends_on_what_architecture_md_draws() {
    let root = tidy::workspace_root();
    let architecture = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("readable");
    // The picture names every member (a broken picture would make the check vacuous).
    assert_eq!(
        tidy::drawn_layers(&architecture).len(),
        tidy::members(&root).len()
    );
    assert_clean("layers", tidy::layers(&root));
}
