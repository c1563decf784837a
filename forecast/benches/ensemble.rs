//! The ensemble's speed: N members × H hours of comet's mission (nsb3.mi)
//! from the end of comet's deployment, on 1 thread, 2 threads and (with more)
//! every core, side by side: wall and CPU time, the load average before and
//! after, and a check that every thread count gives the same members.
//! `cargo bench -p gloc-forecast --bench ensemble [-- MEMBERS HOURS]` (default
//! 1,000 × 12). Speed is printed, never asserted.

use std::sync::Arc;
use std::time::Instant;

use gloc_engine::sensors::SensorList;
use gloc_forecast::ensemble::{run_ensemble, spread_from_history, EnsembleInput, EnsembleOptions};
use gloc_forecast::fly::{prepare_mission, Flight, Start, Truth};
use gloc_forecast::logs::read_history;
use gloc_sim::{Mission, SimConfig};

/// The process's user + system CPU time (s), from /proc/self/stat (Linux,
/// 100 ticks a second); `None` elsewhere. Wall time on a shared machine
/// counts other processes; CPU time says what the ensemble itself cost.
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let after_name = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = after_name.split_whitespace().collect();
    // Fields 14 and 15 of the line (utime, stime) are 12 and 13 after the name.
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn main() {
    let arguments: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let members: usize = arguments
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(1000);
    let hours: f64 = arguments
        .get(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(12.0);
    let files: Vec<_> = [
        "comet/from-glider/comet-2019-222-02-152.sbd",
        "comet/from-glider/comet-2019-222-02-153.sbd",
        "comet/from-glider/comet-2019-222-02-154.dbd",
    ]
    .iter()
    .map(|file| gloc_testsupport::data(file))
    .collect();
    let cache = gloc_testsupport::data("cac");
    let mut source = gloc_dbd::Deployment::open(&files, Some(&cache)).expect("comet's logs");
    let history = read_history(&mut source).expect("comet's logs");
    let mission = Mission::load(&gloc_testsupport::data("comet/missions/nsb3.mi"));
    let start = Start::from_history(&history).expect("a fix");
    let prepared = prepare_mission(&mission, &start);
    let sensors = Arc::new(SensorList::embedded());
    let config = SimConfig::default();
    let truth = Truth::Uniform(start.believed);
    let input = EnsembleInput {
        flight: Flight {
            mission: &prepared,
            sensors: &sensors,
            config: &config,
            start: &start,
            truth: &truth,
            bathymetry: None,
        },
        hours,
    };
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    // 1 and 2 threads side by side, and every core when there are more.
    let mut counts = vec![1, 2];
    if cores > 2 {
        counts.push(cores);
    }
    println!(
        "{cores} core(s); load average before: {}",
        load_average().unwrap_or_else(|| "?".to_string())
    );
    let mut first = None;
    let mut reference = None;
    for threads in counts {
        let options = EnsembleOptions {
            members,
            seed: 1,
            spread: spread_from_history(&history),
            threads,
        };
        let cpu_before = process_cpu_seconds();
        let began = Instant::now();
        let ensemble = run_ensemble(&input, &options).expect("flies");
        let seconds = began.elapsed().as_secs_f64();
        let cpu = process_cpu_seconds()
            .zip(cpu_before)
            .map(|(after, before)| after - before);
        let single = *first.get_or_insert(seconds);
        println!(
            "ensemble {members} members × {hours} h, {threads} thread(s): {seconds:.2} s wall, \
             {} CPU ({:.0} µs of wall per member-hour, speed-up {:.2}× over 1 thread), {} hourly regions",
            cpu.map_or("?".to_string(), |cpu| format!("{cpu:.2} s")),
            seconds / (members as f64 * hours) * 1e6,
            single / seconds,
            ensemble.regions.len()
        );
        // The same seed gives the same members on any number of threads.
        match &reference {
            None => reference = Some(ensemble),
            Some(reference) => assert_eq!(reference, &ensemble, "{threads} threads differ"),
        }
    }
    println!(
        "load average after: {}",
        load_average().unwrap_or_else(|| "?".to_string())
    );
}

/// The 1, 5 and 15 minute load averages (Linux); `None` elsewhere. Other
/// processes on the machine take cores from the threads.
fn load_average() -> Option<String> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    Some(
        text.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" "),
    )
}
