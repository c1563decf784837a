//! `# sensors: CRC` through the binary: `gloc check` against another list, the
//! compiler's line, and `gloc reindex`. Names and indices were read by hand from
//! `data/cac/1f35be3b.cac` (comet: 444 `m_certainly_at_surface`, 459
//! `m_depth`, 1387 `sci_whfctd_ref_lo`, 2,142 sensors, so the hook sensors are
//! appended at 2142–2144) and the paper's Fig. 2.

mod support;

use std::path::PathBuf;

use support::{gloc, real_file, repo, text};

fn comet_cac() -> String {
    real_file("cac/1f35be3b.cac")
}

fn scratch(name: &str) -> PathBuf {
    let dir = gloc_testsupport::scratch_dir("identity");
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// The `path:line:col: severity[CODE]` header lines of a report.
fn headers(report: &str) -> Vec<String> {
    report
        .lines()
        .filter(|line| line.contains("error[") || line.contains("warning["))
        .map(str::to_string)
        .collect()
}

#[test]
fn fig2_without_a_line_against_comets_list_warns_once_and_passes() {
    let fig2 = repo("examples/fig2.gloc");
    let output = gloc(&["check", &fig2, "--masterdata", &comet_cac()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert_eq!(
        headers(&stdout),
        [format!(
            "{fig2}:5:7: warning[W0114]: the sensor indices were not verified by name: this file \
             does not say which sensor list they were written for, and 1f35be3b is not the \
             embedded list (813b137d)"
        )]
    );
}

#[test]
fn a_stated_list_makes_every_differing_index_an_error() {
    let script = scratch("stated.gloc");
    let fig2 = std::fs::read_to_string(repo("examples/fig2.gloc")).expect("fig2");
    std::fs::write(&script, format!("# sensors: 813b137d\n{fig2}")).expect("write");
    let shown = script.display().to_string();
    let output = gloc(&["check", &shown, "--masterdata", &comet_cac()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    let depth =
        "error[E0113]: index 444 is `m_depth` in 813b137d but `m_certainly_at_surface` in 1f35be3b";
    let behs = "error[E0113]: index 1387 is `sci_ruhp_behs` in 813b137d but `sci_whfctd_ref_lo` in 1f35be3b";
    assert_eq!(
        headers(&stdout),
        [
            format!("{shown}:6:7: {depth}"),
            format!("{shown}:12:11: {behs}"),
            format!("{shown}:18:7: {depth}"),
            format!("{shown}:24:11: {behs}"),
        ]
    );
    assert!(
        stdout.contains("help: in 1f35be3b `m_depth` is index 459"),
        "{stdout}"
    );
    // A run refuses it too: it would store into `sci_whfctd_ref_lo`.
    let csv = scratch("depths.csv");
    std::fs::write(&csv, "m_depth\n3\n").expect("write");
    let output = gloc(&[
        "run",
        &shown,
        "--masterdata",
        &comet_cac(),
        "--replay",
        &csv.display().to_string(),
    ]);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
}

#[test]
fn a_third_list_beside_the_script_is_found_and_compared() {
    let folder = scratch("third");
    std::fs::create_dir_all(&folder).expect("dir");
    std::fs::copy(comet_cac(), folder.join("1f35be3b.cac")).expect("copy");
    let script = folder.join("comet.gloc");
    let fig2 = std::fs::read_to_string(repo("examples/fig2.gloc")).expect("fig2");
    std::fs::write(
        &script,
        format!("# sensors: 1f35be3b\n{}", fig2.replace("444,", "459,")),
    )
    .expect("write");
    // Checked against the embedded list (1387 is the same there: sci_whfctd_ref_lo in
    // comet's list, sci_ruhp_behs here, so it differs too).
    let output = gloc(&["check", &script.display().to_string()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    let found = headers(&stdout);
    assert_eq!(found.len(), 4, "{stdout}");
    assert!(found[0].ends_with(
        ":6:7: error[E0113]: index 459 is `m_depth` in 1f35be3b but `f_ocean_pressure_max` in 813b137d"
    ));
    assert!(found[1].ends_with(
        ":12:11: error[E0113]: index 1387 is `sci_whfctd_ref_lo` in 1f35be3b but `sci_ruhp_behs` in 813b137d"
    ));
    // Without the list beside it: one W0115, and the file still passes.
    std::fs::remove_file(folder.join("1f35be3b.cac")).expect("remove");
    let output = gloc(&["check", &script.display().to_string()]);
    let stdout = text(&output.stdout);
    assert_eq!(headers(&stdout).len(), 1, "{stdout}");
    assert!(
        headers(&stdout)[0].contains(":1:12: warning[W0115]"),
        "{stdout}"
    );
}

#[test]
fn the_compiler_states_a_non_default_list_and_its_output_checks_by_name() {
    let out = scratch("thermocline.gloc");
    let shown = out.display().to_string();
    let output = gloc(&[
        "compile",
        &repo("examples/thermocline.gbas"),
        "--masterdata",
        &comet_cac(),
        "-o",
        &shown,
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let compiled = std::fs::read_to_string(&out).expect("written");
    assert_eq!(compiled.lines().next(), Some("# sensors: 1f35be3b"));
    let output = gloc(&["check", &shown, "--masterdata", &comet_cac()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    // (Its two `for` loops without their bounds are W0111 warnings in plain GLOC.)
    assert!(
        !stdout.contains("E0113") && !stdout.contains("W0114") && !stdout.contains("W0115"),
        "{stdout}"
    );
    // Against the embedded list, with comet's list nowhere near: W0115 only.
    let output = gloc(&["check", &shown]);
    let stdout = text(&output.stdout);
    assert!(stdout.contains(":1:12: warning[W0115]"), "{stdout}");
    assert!(!stdout.contains("E0113"), "{stdout}");
    // With it beside the script, the first index that differs is `m_depth` (459).
    std::fs::copy(comet_cac(), out.with_file_name("1f35be3b.cac")).expect("copy");
    let output = gloc(&["check", &shown]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stdout.contains("error[E0113]: index 459 is `m_depth` in 1f35be3b but `f_ocean_pressure_max` in 813b137d"),
        "{stdout}"
    );
    // With the embedded list the compiler writes no line: Fig. 3 → Fig. 2 byte for byte.
    let fig2 = scratch("fig2.gloc");
    let output = gloc(&[
        "compile",
        &repo("examples/fig3.gbas"),
        "-o",
        &fig2.display().to_string(),
    ]);
    assert!(output.status.success());
    assert_eq!(
        std::fs::read_to_string(&fig2).expect("written"),
        std::fs::read_to_string(repo("examples/fig2.gloc")).expect("fig2")
    );
}

#[test]
fn reindex_rewrites_fig2_for_comet_and_refuses_what_it_cannot_map() {
    let out = scratch("fig2-comet.gloc");
    let shown = out.display().to_string();
    let output = gloc(&[
        "reindex",
        &repo("examples/fig2.gloc"),
        "--to",
        &comet_cac(),
        "-o",
        &shown,
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let fig2 = std::fs::read_to_string(repo("examples/fig2.gloc")).expect("fig2");
    assert_eq!(
        std::fs::read_to_string(&out).expect("written"),
        format!(
            "# sensors: 1f35be3b\n{}",
            fig2.replace("444,", "459,").replace(",1387", ",2144")
        )
    );
    let output = gloc(&["check", &shown, "--masterdata", &comet_cac()]);
    assert_eq!(text(&output.stdout), "");
    // The output may not be the input.
    let output = gloc(&["reindex", &shown, "--to", &comet_cac(), "-o", &shown]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains("is the input"),
        "{}",
        text(&output.stderr)
    );
    // Nor the target list: a copy of comet's list named as the output stays as it was.
    let list = scratch("target.cac");
    std::fs::copy(comet_cac(), &list).expect("copy the list");
    let before = std::fs::read(&list).expect("the list");
    let list_path = list.display().to_string();
    let output = gloc(&["reindex", &shown, "--to", &list_path, "-o", &list_path]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output.stderr));
    assert!(
        text(&output.stderr).contains("is the input"),
        "{}",
        text(&output.stderr)
    );
    assert_eq!(std::fs::read(&list).expect("the list"), before);
    // A list without `m_depth`: refused with the place, and nothing written.
    let tiny = scratch("tiny.cac");
    std::fs::write(&tiny, "s: T    0    0 4 c_pitch rad\n").expect("write");
    let refused = scratch("refused.gloc");
    let output = gloc(&[
        "reindex",
        &repo("examples/fig2.gloc"),
        "--to",
        &tiny.display().to_string(),
        "-o",
        &refused.display().to_string(),
    ]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let fig2_path = repo("examples/fig2.gloc");
    assert_eq!(
        headers(&stderr),
        [
            format!("{fig2_path}:5:7: error[E0116]: index 444 is `m_depth` in 813b137d, and the active sensor list has no sensor `m_depth`"),
            format!("{fig2_path}:17:7: error[E0116]: index 444 is `m_depth` in 813b137d, and the active sensor list has no sensor `m_depth`"),
        ]
    );
    assert!(!refused.exists());
}

#[test]
fn the_sensor_cache_of_gloc_toml_is_searched_too() {
    let folder = scratch("cached");
    std::fs::create_dir_all(&folder).expect("dir");
    std::fs::write(
        folder.join("gloc.toml"),
        format!("sensor_cache = \"{}\"\n", real_file("cac")),
    )
    .expect("write");
    let script = folder.join("comet.gloc");
    let fig2 = std::fs::read_to_string(repo("examples/fig2.gloc")).expect("fig2");
    std::fs::write(&script, format!("# sensors: 1f35be3b\n{fig2}")).expect("write");
    // Against the embedded list, comet's list found in the cache: 444 and 1387 differ.
    let output = gloc(&["check", &script.display().to_string()]);
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains(":6:7: error[E0113]: index 444 is `m_certainly_at_surface` in 1f35be3b but `m_depth` in 813b137d"),
        "{stdout}"
    );
}
