//! The real logs in ../shared/data (skipped when the folder is absent, as on a
//! machine without it): every file reads to its end tag without an error or a
//! warning, with the sensor count its header states. Value-by-value equality
//! with dbdreader is tests/e2e/dbd/compare.py.

use std::path::{Path, PathBuf};

use gloc_dbd::open_path;

fn data() -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data");
    path.is_dir().then_some(path)
}

fn read_all(path: &Path, cache: &Path) -> (usize, u64, f64, f64) {
    let mut reader = open_path(path, Some(cache)).unwrap_or_else(|error| panic!("{error}"));
    let sensors = reader.sensors().len();
    let mut cycles = 0u64;
    let (mut first, mut last) = (f64::NAN, f64::NAN);
    while let Some(cycle) = reader
        .next_cycle()
        .unwrap_or_else(|error| panic!("{error}"))
    {
        cycles += 1;
        if first.is_nan() {
            first = cycle.time;
        }
        if !cycle.time.is_nan() {
            last = cycle.time;
        }
    }
    let warnings = reader.take_warnings();
    assert!(warnings.is_empty(), "{warnings:?}");
    (sensors, cycles, first, last)
}

#[test]
fn every_real_log_reads_to_its_end() {
    let Some(data) = data() else {
        eprintln!("../shared/data absent: skipped");
        return;
    };
    let comet = data.join("comet/from-glider");
    let cac = data.join("cac");
    let compressed = data.join("compressed");
    for (file, cache, sensors) in [
        (comet.join("comet-2019-222-02-154.dbd"), &cac, 2142),
        (comet.join("comet-2019-222-02-154.ebd"), &cac, 91),
        (comet.join("comet-2019-222-02-152.sbd"), &cac, 20),
        (comet.join("comet-2019-222-02-152.tbd"), &cac, 6),
        (comet.join("comet-2019-222-02-153.sbd"), &cac, 20),
        (comet.join("comet-2019-222-02-153.tbd"), &cac, 6),
        (compressed.join("01600000.dcd"), &compressed, 0),
        (compressed.join("01600000.ecd"), &compressed, 0),
    ] {
        let (count, cycles, first, last) = read_all(&file, cache);
        eprintln!(
            "{}: {count} sensors, {cycles} cycles, {first}..{last}",
            file.display()
        );
        if sensors > 0 {
            assert_eq!(count, sensors, "{}", file.display());
        }
        assert!(cycles > 0);
    }
}
