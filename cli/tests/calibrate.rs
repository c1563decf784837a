//! `gloc calibrate` on comet's log (data/): the
//! table has a comment per value and lists what was not fitted; an existing
//! output is refused without --force, an input always; `gloc run --plot`
//! writes PNG by the extension and refuses other extensions.

mod support;
use support::{gloc_in as gloc, temp_folder, text};

#[test]
fn calibrate_writes_a_commented_table_and_never_overwrites() {
    let data = gloc_testsupport::data("");
    let folder = temp_folder("calibrate");
    let log = data.join("comet/from-glider/comet-2019-222-02-154.dbd");
    let (log, cache) = (log.to_string_lossy(), data.join("cac"));
    let cache = cache.to_string_lossy();
    let args = [
        "calibrate",
        &log,
        "--sensor-cache",
        &cache,
        "-o",
        "gloc.toml",
    ];
    let output = gloc(&args, &folder);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let table = std::fs::read_to_string(folder.join("gloc.toml")).expect("written");
    assert!(table.contains("[simulator]"), "{table}");
    // comet's drag and hull volume as gliderflight's glidertrim fits them on the
    // same log (domain notes §7): Cd0 0.209, Vg 71.549 L.
    let value = |name: &str| -> (f64, String) {
        let line = table
            .lines()
            .find_map(|line| line.strip_prefix(&format!("{name} = ")))
            .unwrap_or_else(|| panic!("{name} fitted: {table}"));
        let number = line.split_whitespace().next().unwrap_or("").parse();
        (number.expect("number"), line.to_string())
    };
    let (cd0, line) = value("drag_cd0");
    assert!((0.19..0.23).contains(&cd0), "{line}");
    assert!(line.contains("# least squares"), "{line}");
    let (volume, line) = value("hull_volume");
    assert!((71.45..71.65).contains(&volume), "{line}");
    assert!(
        table.contains("#   pitch_t2: m_battpos stays within"),
        "{table}"
    );
    assert!(table.contains("#   battery_wh: "), "{table}");
    // The table is a gloc.toml gloc run accepts.
    let run = gloc(&["run", "--cycles", "10"], &folder);
    assert!(run.status.success(), "{}", text(&run.stderr));
    // An existing output is refused without --force; an input always.
    let again = gloc(&args, &folder);
    assert_eq!(again.status.code(), Some(2));
    assert!(
        text(&again.stderr).contains("--force"),
        "{}",
        text(&again.stderr)
    );
    let mut forced = args.to_vec();
    forced.push("--force");
    assert!(gloc(&forced, &folder).status.success());
    let onto_input = gloc(
        &[
            "calibrate",
            &log,
            "--sensor-cache",
            &cache,
            "-o",
            &log,
            "--force",
        ],
        &folder,
    );
    assert_eq!(onto_input.status.code(), Some(2));
    assert!(text(&onto_input.stderr).contains("writing it would destroy the input"));
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn plots_are_png_or_svg_by_extension() {
    let folder = temp_folder("plot-formats");
    let output = gloc(&["run", "--cycles", "50", "--plot", "run.png"], &folder);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let png = std::fs::read(folder.join("run.png")).expect("png written");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let output = gloc(&["run", "--cycles", "50", "--plot", "run.jpg"], &folder);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains(".svg or .png"),
        "{}",
        text(&output.stderr)
    );
    assert!(!folder.join("run.jpg").exists());
    // A chosen sensor gets its own panel; an unknown one is refused.
    let output = gloc(
        &[
            "run",
            "--cycles",
            "50",
            "--plot",
            "run.svg",
            "--plot-panels",
            "battery,m_pitch",
        ],
        &folder,
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let svg = std::fs::read_to_string(folder.join("run.svg")).expect("svg written");
    assert!(
        svg.contains("\nbattery (V)\n") && svg.contains("\nm_pitch\n"),
        "panels missing"
    );
    let output = gloc(
        &[
            "run",
            "--cycles",
            "5",
            "--plot",
            "x.svg",
            "--plot-panels",
            "m_nosuch",
        ],
        &folder,
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("no sensor `m_nosuch`"));
    let _ = std::fs::remove_dir_all(&folder);
}
