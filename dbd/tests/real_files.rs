//! The real logs in the repository's data/: every file reads to its end tag without an error or a
//! warning, with the sensor count its header states. Value-by-value equality
//! with dbdreader is tests/e2e/dbd/compare.py.

use std::path::{Path, PathBuf};

use gloc_dbd::{open_path, CycleSource};

fn data() -> PathBuf {
    gloc_testsupport::data("")
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
    let data = data();
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

/// comet's .dbd merged with its .ebd: at every flight cycle, `sci_water_temp` is
/// the last value the .ebd read alone gives at or before the flight time (a
/// binary search over the science samples, a second route to the merge rule).
#[test]
fn merged_science_values_are_the_latest_at_or_before_each_flight_cycle() {
    let data = data();
    let comet = data.join("comet/from-glider");
    let cac = data.join("cac");
    let ebd = comet.join("comet-2019-222-02-154.ebd");
    let mut science = open_path(&ebd, Some(&cac)).expect("ebd");
    let temp = science
        .sensors()
        .iter()
        .position(|s| s.name == "sci_water_temp")
        .expect("sci_water_temp");
    let mut samples: Vec<(f64, f64)> = Vec::new();
    let mut now = f64::NAN;
    while let Some(cycle) = science.next_cycle().expect("reads") {
        if !cycle.time.is_nan() {
            now = cycle.time;
        }
        if let Some(value) = cycle.value(temp) {
            samples.push((now, value));
        }
    }
    let mut merged = gloc_dbd::Merged::new(
        open_path(&comet.join("comet-2019-222-02-154.dbd"), Some(&cac)).expect("dbd"),
        open_path(&ebd, Some(&cac)).expect("ebd"),
    );
    let column = merged
        .sensors()
        .iter()
        .position(|s| s.name == "sci_water_temp")
        .expect("merged column");
    let (mut checked, mut flight_time) = (0, f64::NAN);
    while let Some(cycle) = merged.next_cycle().expect("merges") {
        if !cycle.time.is_nan() {
            flight_time = cycle.time;
        }
        let at_or_before = samples.partition_point(|(t, _)| *t <= flight_time);
        let expected = at_or_before.checked_sub(1).map(|i| samples[i].1);
        let got = cycle.values[column];
        match expected {
            Some(value) => assert!(
                got == value || (got.is_nan() && value.is_nan()),
                "at {flight_time}: merged {got}, expected {value}"
            ),
            None => assert!(got.is_nan(), "before any science value: {got}"),
        }
        checked += 1;
    }
    assert!(checked > 2000, "{checked} flight cycles");
}

/// A deployment given out of order, with three sensor lists (the .dbd's 2,142,
/// the .sbd's 20, the science files' 91 and 6): paired by name, read in
/// `fileopen_time` order, the columns united by name.
#[test]
fn a_deployment_streams_in_time_order_across_sensor_lists() {
    let data = data();
    let comet = data.join("comet/from-glider");
    let files: Vec<PathBuf> = [
        "comet-2019-222-02-154.ebd",
        "comet-2019-222-02-153.sbd",
        "comet-2019-222-02-152.tbd",
        "comet-2019-222-02-154.dbd",
        "comet-2019-222-02-152.sbd",
        "comet-2019-222-02-153.tbd",
    ]
    .iter()
    .map(|name| comet.join(name))
    .collect();
    let mut deployment =
        gloc_dbd::Deployment::open(&files, Some(&data.join("cac"))).expect("opens");
    let order: Vec<String> = deployment
        .segments()
        .iter()
        .map(|segment| {
            let name = |path: Option<&PathBuf>| {
                path.and_then(|p| p.file_name())
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default()
            };
            format!(
                "{}+{}",
                name(segment.files.flight()),
                name(segment.files.science())
            )
        })
        .collect();
    assert_eq!(
        order,
        [
            "comet-2019-222-02-152.sbd+comet-2019-222-02-152.tbd",
            "comet-2019-222-02-153.sbd+comet-2019-222-02-153.tbd",
            "comet-2019-222-02-154.dbd+comet-2019-222-02-154.ebd",
        ]
    );
    // Every sensor of the .dbd and .ebd (2,142 + the .ebd's names the .dbd lacks).
    let names: std::collections::HashSet<&str> = deployment
        .sensors()
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(
        names.len(),
        deployment.sensors().len(),
        "one column per name"
    );
    assert!(names.contains("sci_water_temp") && names.contains("m_depth"));
    let (mut cycles, mut last) = (0u64, f64::NEG_INFINITY);
    while let Some(cycle) = deployment.next_cycle().expect("streams") {
        if !cycle.time.is_nan() {
            assert!(cycle.time >= last, "time goes back at cycle {cycles}");
            last = cycle.time;
        }
        cycles += 1;
    }
    // 304 + 8 + 2,244 flight cycles (the .sbd and .dbd counts read alone).
    assert_eq!(cycles, 304 + 8 + 2244);
}

/// `Cycle::updated` lists exactly the columns whose state says updated, each
/// once, in every cycle of every real log, of comet's flight log merged with its
/// science log, and of comet's whole deployment (6 files, 3 segments).
#[test]
fn updated_lists_exactly_the_updated_columns() {
    let data = data();
    let comet = data.join("comet/from-glider");
    let cac = data.join("cac");
    let check = |mut source: Box<dyn CycleSource>, what: &str| -> (u64, Vec<u64>) {
        let mut cycles = 0u64;
        let mut counts = vec![0u64; source.sensors().len()];
        while let Some(cycle) = source.next_cycle().expect("reads") {
            let mut listed = cycle.updated.clone();
            listed.sort_unstable();
            let dense: Vec<usize> = (0..cycle.states.len())
                .filter(|&column| cycle.states[column].is_updated())
                .collect();
            assert_eq!(listed, dense, "{what}, cycle {cycles}");
            for column in dense {
                counts[column] += 1;
            }
            cycles += 1;
        }
        (cycles, counts)
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&comet)
        .expect("comet")
        .map(|entry| entry.expect("entry").path())
        .collect();
    files.sort();
    for file in &files {
        check(
            open_path(file, Some(&cac)).expect("opens"),
            &file.display().to_string(),
        );
    }
    let compressed = data.join("compressed");
    for name in ["01600000.dcd", "01600000.ecd"] {
        check(
            open_path(&compressed.join(name), Some(&compressed)).expect("opens"),
            name,
        );
    }
    // The merge: a flight-owned sensor is updated in as many merged cycles as in
    // the flight log read alone (the merge keeps every flight cycle).
    let dbd = comet.join("comet-2019-222-02-154.dbd");
    let ebd = comet.join("comet-2019-222-02-154.ebd");
    let alone = check(open_path(&dbd, Some(&cac)).expect("dbd"), "154.dbd");
    let merged = gloc_dbd::Merged::new(
        open_path(&dbd, Some(&cac)).expect("dbd"),
        open_path(&ebd, Some(&cac)).expect("ebd"),
    );
    let science: std::collections::HashSet<String> = open_path(&ebd, Some(&cac))
        .expect("ebd")
        .sensors()
        .iter()
        .map(|sensor| sensor.name.clone())
        .collect();
    let names: Vec<String> = merged.sensors().iter().map(|s| s.name.clone()).collect();
    let together = check(Box::new(merged), "154 merged");
    assert_eq!(together.0, alone.0);
    for (column, name) in names.iter().enumerate().take(alone.1.len()) {
        if !science.contains(name) {
            assert_eq!(together.1[column], alone.1[column], "{name}");
        }
    }
    let deployment = gloc_dbd::Deployment::open(&files, Some(&cac)).expect("opens");
    let (cycles, _) = check(Box::new(deployment), "comet's deployment");
    assert!(cycles > alone.0, "{cycles}");
}
