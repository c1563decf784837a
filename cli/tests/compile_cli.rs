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
    let dir = gloc_testsupport::scratch_dir(&format!("compile-cli-{name}"));
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
fn check_and_compile_agree_on_which_language_a_file_is() {
    // `.bas` and `.gbasic` are GBASIC for `gloc compile`; `gloc check` read them as
    // GLOC (27 "expected" errors for Fig. 3) before both used the compiler's one table.
    let dir = scratch("extensions");
    let fig3 = std::fs::read_to_string(root().join("examples/fig3.gbas")).expect("fig3");
    for name in ["fig3.bas", "fig3.GBASIC"] {
        let path = dir.join(name);
        std::fs::write(&path, &fig3).expect("write");
        for command in ["check", "compile"] {
            let mut gloc = gloc();
            gloc.arg(command).arg(&path);
            if command == "compile" {
                gloc.arg("-o").arg(dir.join("out.gloc"));
            }
            let output = gloc.output().expect("gloc runs");
            assert!(
                output.status.success(),
                "gloc {command} {name}: {}{}",
                String::from_utf8_lossy(&output.stdout),
                String::from_utf8_lossy(&output.stderr)
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_file_is_a_clear_error() {
    let output = gloc()
        .args(["compile", "no/such/file.gbas"])
        .output()
        .expect("gloc runs");
    // Exit code 3, as in every subcommand: an input cannot be read.
    assert_eq!(output.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("cannot read the script `no/such/file.gbas`"),
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
    assert!(String::from_utf8_lossy(&output.stderr).contains("is the input"));
    assert_eq!(
        std::fs::read_to_string(&source).expect("source kept"),
        "yield\n"
    );
    std::fs::remove_dir_all(dir).ok();
}

/// `(instructions, registers)` of a written GLOC file, counted from its text: the
/// `nregs` header, and the lines after the header that are not labels.
fn counts_in_gloc(text: &str) -> (u32, u32) {
    let mut registers = None;
    let mut instructions = 0;
    for line in text.lines() {
        let first = line.split_whitespace().next().unwrap_or("");
        match first {
            "nregs" => {
                registers = line
                    .split_whitespace()
                    .nth(1)
                    .and_then(|value| value.parse().ok())
            }
            "nblbs" | "ninstr" | "nmem" | "label" | "" => {}
            _ => instructions += 1,
        }
    }
    (instructions, registers.expect("an nregs header"))
}

/// The four numbers of `…: -O: A → B instructions, C → D registers (…)`.
fn optimizer_counts(stderr: &str) -> Option<[u32; 4]> {
    let line = stderr.lines().find(|line| line.contains(": -O: "))?;
    let numbers: Vec<u32> = line
        .split(": -O: ")
        .nth(1)?
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|word| word.parse().ok())
        .collect();
    numbers.try_into().ok()
}

#[test]
fn compile_dash_o_reports_before_and_after_counts_and_writes_gloc_that_checks() {
    let dir = scratch("optimize");
    let source = root().join("examples/thermocline.gbas");
    let plain_out = dir.join("plain.gloc");
    let optimized_out = dir.join("optimized.gloc");
    let plain = gloc()
        .arg("compile")
        .arg(&source)
        .arg("-o")
        .arg(&plain_out)
        .output()
        .expect("gloc runs");
    assert!(
        plain.status.success(),
        "{}",
        String::from_utf8_lossy(&plain.stderr)
    );
    // Without -O there is no before → after line.
    assert_eq!(
        optimizer_counts(&String::from_utf8_lossy(&plain.stderr)),
        None
    );

    let optimized = gloc()
        .arg("compile")
        .arg(&source)
        .arg("-O")
        .arg("-o")
        .arg(&optimized_out)
        .output()
        .expect("gloc runs");
    let stderr = String::from_utf8_lossy(&optimized.stderr);
    assert!(optimized.status.success(), "{stderr}");
    let [instructions_before, instructions_after, registers_before, registers_after] =
        optimizer_counts(&stderr).unwrap_or_else(|| panic!("no -O counts line in {stderr}"));
    assert!(instructions_before >= instructions_after, "{stderr}");
    assert!(registers_before >= registers_after, "{stderr}");
    // The figures are the two builds' own: counted independently from the GLOC files.
    let plain_text = std::fs::read_to_string(&plain_out).expect("plain GLOC written");
    let optimized_text = std::fs::read_to_string(&optimized_out).expect("-O GLOC written");
    assert_eq!(
        counts_in_gloc(&plain_text),
        (instructions_before, registers_before),
        "{stderr}"
    );
    assert_eq!(
        counts_in_gloc(&optimized_text),
        (instructions_after, registers_after),
        "{stderr}"
    );
    // Unoptimized, every value takes a fresh register, so reuse must save some.
    assert!(registers_after < registers_before, "{stderr}");

    // The optimized GLOC is a valid script on its own.
    let check = gloc()
        .arg("check")
        .arg(&optimized_out)
        .output()
        .expect("gloc runs");
    assert!(
        check.status.success(),
        "{}{}",
        String::from_utf8_lossy(&check.stdout),
        String::from_utf8_lossy(&check.stderr)
    );
    // And it flies the mission as the unoptimized GLOC does: the same lines printed.
    let fly = |gloc_file: &Path| {
        let output = gloc()
            .arg("run")
            .arg(gloc_file)
            .arg("--mission")
            .arg(root().join("examples/thermocline.mi"))
            .args(["--duration", "2h"])
            .output()
            .expect("gloc runs");
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        String::from_utf8_lossy(&output.stdout).into_owned()
    };
    let plain_printed = fly(&plain_out);
    assert!(
        plain_printed.contains("thermocline from"),
        "{plain_printed}"
    );
    assert_eq!(fly(&optimized_out), plain_printed);
    std::fs::remove_dir_all(dir).ok();
}
