//! `gloc compile` and `.gbas` in `gloc check`, through the real binary.

use std::path::{Path, PathBuf};
use std::process::Command;

fn gloc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gloc"))
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gloc-compile-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn compile_fig3_writes_fig2_and_the_source_map() {
    let dir = scratch("fig3");
    let out = dir.join("fig3.gloc");
    let status = gloc()
        .arg("compile")
        .arg(root().join("examples/fig3.gbas"))
        .arg("-o")
        .arg(&out)
        .arg("--emit-map")
        .status()
        .expect("gloc runs");
    assert!(status.success());
    let written = std::fs::read_to_string(&out).expect("GLOC written");
    let fig2 = std::fs::read_to_string(root().join("tests/fixtures/gbasic/ok/fig3.gloc"))
        .expect("fixture");
    assert_eq!(written, fig2);
    let map = std::fs::read_to_string(dir.join("fig3.map.json")).expect("map written");
    // `loads 444,r0` (GLOC line 5) comes from `m_depth` on GBASIC line 2, column 4.
    assert!(map.contains("\"gloc_line\": 5,\n      \"is_label\": false,\n      \"start\": 17,\n      \"end\": 24,\n      \"line\": 2,\n      \"column\": 4"), "{map}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn compile_errors_are_rendered_and_no_gloc_is_written() {
    let dir = scratch("errors");
    let source = dir.join("bad.gbas");
    std::fs::write(&source, "dim depth as float\ndepth = m_dpth + 1.0\n").expect("write");
    let output = gloc()
        .arg("compile")
        .arg(&source)
        .output()
        .expect("gloc runs");
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("bad.gbas:2:9: error[E2101]: `m_dpth` is not declared and is not a sensor"),
        "{stderr}"
    );
    assert!(stderr.contains("did you mean `m_depth`?"), "{stderr}");
    assert!(!dir.join("bad.gloc").exists());
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn check_accepts_gbasic_and_reports_on_gbasic_lines() {
    let output = gloc()
        .arg("check")
        .arg(root().join("tests/fixtures/gbasic/err/read_only.gbas"))
        .output()
        .expect("gloc runs");
    assert_eq!(output.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("read_only.gbas:1:1: error[E2105]: the sensor `m_depth` is read-only"),
        "{stdout}"
    );

    let output = gloc()
        .arg("check")
        .arg(root().join("examples/fig3.gbas"))
        .output()
        .expect("gloc runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stdout)
    );
}

#[test]
fn a_missing_file_is_a_clear_error() {
    let output = gloc()
        .args(["compile", "no/such/file.gbas"])
        .output()
        .expect("gloc runs");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("cannot read the GBASIC file `no/such/file.gbas`"),
        "{stderr}"
    );
}

#[test]
fn compile_refuses_to_overwrite_its_source() {
    let dir = scratch("overwrite");
    let source = dir.join("prog.gbas");
    std::fs::write(&source, "yield\n").expect("write");
    let output = gloc()
        .arg("compile")
        .arg(&source)
        .arg("-o")
        .arg(&source)
        .output()
        .expect("gloc runs");
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("is the GBASIC source itself"));
    assert_eq!(
        std::fs::read_to_string(&source).expect("source kept"),
        "yield\n"
    );
    std::fs::remove_dir_all(dir).ok();
}
