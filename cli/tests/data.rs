//! `gloc data` through the real binary: a real log converted to `.dba` reads back
//! to the same CSV as the log itself (the ASCII reader against the binary one),
//! gloc's own `.dba` run log reads, and outputs never overwrite inputs.

use std::path::PathBuf;

mod support;
use support::{gloc_in as gloc, temp_folder, text};

fn shared_data() -> PathBuf {
    gloc_testsupport::data("")
}

#[test]
fn a_real_log_through_dba_gives_the_same_csv() {
    let data = shared_data();
    let folder = temp_folder("dba");
    let cache = data.join("cac").display().to_string();
    for name in ["comet-2019-222-02-152.sbd", "comet-2019-222-02-154.ebd"] {
        let log = data
            .join("comet/from-glider")
            .join(name)
            .display()
            .to_string();
        for (input, output) in [(log.as_str(), "direct.csv"), (log.as_str(), "x.dba")] {
            let run = gloc(
                &[
                    "data",
                    "convert",
                    input,
                    "--sensor-cache",
                    &cache,
                    "-o",
                    output,
                ],
                &folder,
            );
            assert!(run.status.success(), "{}", text(&run.stderr));
        }
        let run = gloc(&["data", "convert", "x.dba", "-o", "via-dba.csv"], &folder);
        assert!(run.status.success(), "{}", text(&run.stderr));
        let direct = std::fs::read_to_string(folder.join("direct.csv")).expect("csv");
        let via = std::fs::read_to_string(folder.join("via-dba.csv")).expect("csv");
        // `.dba` writes NaN for "not updated", so a NaN value reads back as not updated.
        let direct = direct.replace(",NaN", ",").replace("NaN,", ",");
        assert_eq!(direct.lines().count(), via.lines().count(), "{name}");
        for (at, (a, b)) in direct.lines().zip(via.lines()).enumerate() {
            assert_eq!(a, b, "{name} line {}", at + 1);
        }
    }
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn gloc_s_own_dba_log_reads() {
    let folder = temp_folder("own");
    let run = gloc(&["run", "--duration", "10m", "--log", "run.dba"], &folder);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let rows = std::fs::read_to_string(folder.join("run.dba"))
        .expect("log")
        .lines()
        .skip(17)
        .count();
    let info = gloc(&["data", "info", "run.dba"], &folder);
    let stdout = text(&info.stdout);
    assert!(info.status.success(), "{}", text(&info.stderr));
    assert!(
        stdout.contains(&format!("cycles: {rows}\n")),
        "{rows} rows: {stdout}"
    );
    assert!(stdout.contains("time sensor: m_present_time"), "{stdout}");
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn convert_refuses_to_overwrite_an_input_and_names_bad_outputs() {
    let folder = temp_folder("refuse");
    let run = gloc(&["run", "--duration", "2m", "--log", "run.dba"], &folder);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let before = std::fs::read(folder.join("run.dba")).expect("log");
    let output = gloc(&["data", "convert", "run.dba", "-o", "run.dba"], &folder);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains("writing it would destroy the input"),
        "{}",
        text(&output.stderr)
    );
    assert_eq!(std::fs::read(folder.join("run.dba")).expect("log"), before);
    let output = gloc(&["data", "convert", "run.dba", "-o", "out.txt"], &folder);
    assert!(
        text(&output.stderr).contains("must end in .csv or .dba"),
        "{}",
        text(&output.stderr)
    );
    let output = gloc(
        &[
            "data",
            "convert",
            "run.dba",
            "-o",
            "o.csv",
            "--sensors",
            "m_depth,nope",
        ],
        &folder,
    );
    assert!(
        text(&output.stderr).contains("`nope` is not a sensor"),
        "{}",
        text(&output.stderr)
    );
    let _ = std::fs::remove_dir_all(&folder);
}

/// `gloc run --log run.dbd` read back by `gloc data convert` (run.dbd merged with
/// run.ebd) carries forward to the CSV log of the same run, every value rounded
/// to the float32 the binary log stores (times are doubles). The independent
/// check, dbdreader reading the same files, is tests/e2e/dbd/roundtrip.py.
#[test]
fn a_binary_run_log_reads_back_as_the_csv_log() {
    let folder = temp_folder("binary");
    let sensors =
        "m_present_time,m_depth,m_pitch,c_pitch,sci_m_present_time,sci_water_temp,sci_ruhp_behs";
    for log in ["run.csv", "run.dbd"] {
        let run = gloc(
            &[
                "run",
                "--duration",
                "20m",
                "--seed",
                "3",
                "--log",
                log,
                "--log-sensors",
                sensors,
            ],
            &folder,
        );
        assert!(run.status.success(), "{}", text(&run.stderr));
    }
    assert!(folder.join("run.ebd").is_file(), "the science part");
    let cac = std::fs::read_dir(&folder)
        .expect("folder")
        .filter(|entry| {
            entry
                .as_ref()
                .is_ok_and(|e| e.path().extension().is_some_and(|x| x == "cac"))
        })
        .count();
    assert_eq!(cac, 2, "one sensor list per file");
    let run = gloc(
        &[
            "data",
            "convert",
            "run.dbd",
            "run.ebd",
            "-o",
            "back.csv",
            "--sensors",
            sensors,
        ],
        &folder,
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let csv = std::fs::read_to_string(folder.join("run.csv")).expect("csv");
    let back = std::fs::read_to_string(folder.join("back.csv")).expect("csv");
    let (mut csv, mut back) = (csv.lines(), back.lines());
    assert_eq!(csv.next(), back.next(), "the same header");
    let mut carried: Vec<Option<f64>> = vec![None; sensors.split(',').count()];
    let mut rows = 0;
    for (expected, got) in csv.zip(back) {
        for (column, (e, g)) in expected.split(',').zip(got.split(',')).enumerate() {
            // Times (columns 0 and 4) are doubles; the rest float32, printed
            // as the shortest text that reads back as that float32.
            let double = column == 0 || column == 4;
            let number = |text: &str| -> f64 {
                if double {
                    text.parse().expect("a number")
                } else {
                    f64::from(text.parse::<f32>().expect("a number"))
                }
            };
            if !g.is_empty() {
                carried[column] = Some(number(g));
            }
            assert_eq!(
                carried[column],
                Some(number(e)),
                "row {rows} column {column}"
            );
        }
        rows += 1;
    }
    assert!(rows > 100, "{rows} rows");
    let _ = std::fs::remove_dir_all(&folder);
}

/// A log cut before its first complete cycle: `info` says it has no time span (it
/// printed `- .. - (NaN s)`) and warns at the byte where the damage starts.
#[test]
fn info_on_a_log_without_a_complete_cycle_has_no_time_span() {
    let shared = shared_data();
    let folder = temp_folder("cut");
    let real = std::fs::read(shared.join("comet/from-glider/comet-2019-222-02-154.dbd"))
        .expect("comet's log");
    std::fs::write(folder.join("cut.dbd"), &real[..3000]).expect("write");
    let cache = shared.join("cac");
    let output = gloc(
        &[
            "data",
            "info",
            "cut.dbd",
            "--sensor-cache",
            cache.to_str().expect("UTF-8 path"),
        ],
        &folder,
    );
    let stdout = text(&output.stdout);
    let stderr = text(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stdout.contains("  cycles: 0\n"), "{stdout}");
    assert!(
        stdout.contains("  time span: none (no cycle with a time)"),
        "{stdout}"
    );
    assert!(!stdout.contains("NaN"), "{stdout}");
    assert!(stderr.contains("cut.dbd: byte"), "{stderr}");
    std::fs::remove_dir_all(&folder).expect("clean up");
}
