//! Reading speed and streaming memory of the glider-log reader.
//! Run with `cargo bench -p gloc-dbd --bench read` (reads the repository's data/
//! the clone; dbdreader from tests/e2e/.venv, made by tests/e2e/setup, or the
//! Python named by $DBDREADER_PYTHON).
//!
//! 1. comet-2019-222-02-154.dbd with its .ebd (2.5 MB) read into every sensor's
//!    (time, value) series, as dbdreader's `DBD.get(*all)` does, gloc and
//!    dbdreader's C extension side by side in this run: median wall time of 5.
//! 2. A 100 MB log (the real .dbd's cycles written again and again with
//!    `DbdWriter`, times shifted) streamed cycle by cycle in a child process
//!    under `/usr/bin/time -v`, and a 10 MB one the same way: peak RSS of both.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use gloc_dbd::{open_path, DbdWriter, ListSensor, LogIdentity, WrittenList};

const RUNS: usize = 5;

fn data() -> PathBuf {
    gloc_testsupport::data("")
}

/// Every sensor's (time, value) samples: the cycles that updated it, at the
/// time sensor's latest value (dbdreader's output).
fn read_series(path: &Path, cache: &Path) -> Vec<Vec<(f64, f64)>> {
    let mut source = open_path(path, Some(cache)).unwrap_or_else(|error| panic!("{error}"));
    let time = source.time_column().expect("a time sensor");
    let mut series: Vec<Vec<(f64, f64)>> = vec![Vec::new(); source.sensors().len()];
    let mut now = f64::NAN;
    while let Some(cycle) = source
        .next_cycle()
        .unwrap_or_else(|error| panic!("{error}"))
    {
        if let Some(value) = cycle.value(time) {
            now = value;
        }
        for (column, state) in cycle.states.iter().enumerate() {
            if state.is_updated() {
                series[column].push((now, cycle.values[column]));
            }
        }
    }
    series
}

fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn speed() {
    let data = data();
    let folder = data.join("comet/from-glider");
    let cache = data.join("cac");
    let mut samples = 0;
    let times: Vec<f64> = (0..RUNS)
        .map(|_| {
            let start = Instant::now();
            samples = 0;
            for name in ["comet-2019-222-02-154.dbd", "comet-2019-222-02-154.ebd"] {
                let series = read_series(&folder.join(name), &cache);
                samples += series.iter().map(Vec::len).sum::<usize>();
                std::hint::black_box(series);
            }
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    let gloc = median(times);
    println!("gloc-dbd:  {gloc:.2} ms for .dbd + .ebd, all sensors ({samples} samples; median of {RUNS})");
    let python = std::env::var("DBDREADER_PYTHON").unwrap_or_else(|_| {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/e2e/.venv/bin/python")
            .display()
            .to_string()
    });
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/read_dbdreader.py");
    match Command::new(&python)
        .arg(&script)
        .arg(&data)
        .arg(RUNS.to_string())
        .output()
    {
        Ok(output) if output.status.success() => {
            let text = String::from_utf8_lossy(&output.stdout);
            let mut fields = text.split_whitespace();
            let ms: f64 = fields
                .next()
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN);
            let theirs: usize = fields.next().and_then(|v| v.parse().ok()).unwrap_or(0);
            println!("dbdreader: {ms:.2} ms for the same ({theirs} samples; median of {RUNS})");
            println!("ratio:     gloc is {:.2}× dbdreader's speed", ms / gloc);
        }
        Ok(output) => println!(
            "dbdreader: failed: {}",
            String::from_utf8_lossy(&output.stderr).trim()
        ),
        Err(error) => println!("dbdreader: cannot run {python}: {error} (run tests/e2e/setup)"),
    }
}

/// Writes a log of at least `megabytes` MB from the real .dbd's cycles.
fn write_big(path: &Path, megabytes: u64) -> PathBuf {
    let data = data();
    let real = data.join("comet/from-glider/comet-2019-222-02-154.dbd");
    let cache = data.join("cac");
    let first = open_path(&real, Some(&cache)).unwrap_or_else(|error| panic!("{error}"));
    let sensors: Vec<ListSensor> = first
        .sensors()
        .iter()
        .map(|sensor| ListSensor {
            name: sensor.name.clone(),
            units: sensor.units.clone(),
            bytes: sensor.bytes,
            logged: true,
        })
        .collect();
    let time = first.time_column().expect("a time sensor");
    let list = WrittenList::new(&sensors);
    let folder = path.parent().expect("a folder");
    std::fs::write(folder.join(format!("{}.cac", list.crc)), &list.text).expect("cac");
    let identity = LogIdentity {
        full_filename: "bench-big".into(),
        the8x3_filename: "00000000".into(),
        filename_extension: "dbd".into(),
        mission_name: "BENCH.MI".into(),
        fileopen_time: "Wed_Aug_21_13:54:25_2019".into(),
    };
    let file = std::fs::File::create(path).expect("create");
    let mut writer =
        DbdWriter::new(std::io::BufWriter::new(file), &identity, &list).expect("header");
    let mut shift = 0.0;
    let mut values = Vec::new();
    'outer: loop {
        let mut source = open_path(&real, Some(&cache)).unwrap_or_else(|error| panic!("{error}"));
        let mut last = 0.0;
        while let Some(cycle) = source.next_cycle().expect("reads") {
            values.clear();
            values.extend(cycle.values.iter().copied());
            values[time] += shift;
            last = cycle.values[time];
            writer.write_cycle(&values).expect("write");
            if writer.cycles().is_multiple_of(1000)
                && std::fs::metadata(path).map(|m| m.len()).unwrap_or(0) >= megabytes << 20
            {
                break 'outer;
            }
        }
        shift += last - 1_566_395_646.0 + 4.0;
    }
    writer.finish().expect("finish");
    folder.to_path_buf()
}

/// The child: streams the file, touching every value.
fn stream(path: &Path) {
    let cache = path.parent().expect("a folder");
    let mut source = open_path(path, Some(cache)).unwrap_or_else(|error| panic!("{error}"));
    let (mut cycles, mut sum) = (0u64, 0.0f64);
    while let Some(cycle) = source
        .next_cycle()
        .unwrap_or_else(|error| panic!("{error}"))
    {
        cycles += 1;
        sum += cycle.values.iter().filter(|v| v.is_finite()).sum::<f64>();
    }
    println!("{cycles} cycles, checksum {sum:e}");
}

fn memory() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/bench-dbd");
    std::fs::create_dir_all(&folder).expect("folder");
    for megabytes in [10u64, 100] {
        let path = folder.join(format!("big-{megabytes}.dbd"));
        write_big(&path, megabytes);
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        let me = std::env::current_exe().expect("the bench binary");
        let output = Command::new("/usr/bin/time")
            .arg("-v")
            .arg(me)
            .env("GLOC_DBD_STREAM", &path)
            .output()
            .expect("/usr/bin/time -v");
        let report = String::from_utf8_lossy(&output.stderr);
        let field = |name: &str| {
            report
                .lines()
                .find_map(|line| line.trim().strip_prefix(name))
                .map(|value| value.trim().to_string())
                .unwrap_or_else(|| "?".into())
        };
        println!(
            "stream {:.1} MB: {} ; wall {} ; peak RSS {} kB",
            size as f64 / (1 << 20) as f64,
            String::from_utf8_lossy(&output.stdout).trim(),
            field("Elapsed (wall clock) time (h:mm:ss or m:ss):"),
            field("Maximum resident set size (kbytes):"),
        );
        std::fs::remove_file(&path).ok();
    }
}

fn main() {
    if let Some(path) = std::env::var_os("GLOC_DBD_STREAM") {
        stream(Path::new(&path));
        return;
    }
    speed();
    memory();
}
