//! Simulator benchmark (`cargo bench -p gloc-sim`): control cycles per second
//! with the paper's Fig. 2 script, and the wall time of a 30-day mission
//! (648,000 cycles) logging the default sensor set to a `.dba` file.
//!
//! Prints figures; asserts nothing about time (a benchmark, not a test).

use std::io::BufWriter;
use std::sync::Arc;
use std::time::Instant;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::sensors::SensorList;
use gloc_sim::log::{default_columns, DbaHeader, LogFormat, LogWriter};
use gloc_sim::{Mission, SimConfig, Simulation};

const FIG2: &str = include_str!("../../examples/fig2.gloc");

/// The Fig. 2 mission with an endless yo and no overtime, so it flies for a month.
fn endless_mission() -> Mission {
    let text = gloc_sim::DEFAULT_MISSION
        .replace(
            "b_arg: overtime(s)             7200",
            "b_arg: overtime(s)               -1",
        )
        .replace(
            "b_arg: num_half_cycles_to_do(nodim) 6",
            "b_arg: num_half_cycles_to_do(nodim) -1",
        );
    Mission::parse("fig2-endless.mi", text)
}

fn new_sim(list: &Arc<SensorList>) -> Simulation {
    let checked = gloc::check(&gloc::parse(FIG2), list, &CheckOptions::default());
    let program = checked.program.expect("Fig. 2 checks");
    // The benchmark measures speed, not endurance: a battery that lasts the month.
    let mut config = SimConfig::default();
    config.set("battery_wh", 100_000.0);
    Simulation::new(&endless_mission(), list.clone(), Some(program), &config)
        .expect("mission starts")
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() {
    let cycles: u64 = std::env::var("GLOC_BENCH_CYCLES")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(648_000);
    let runs: usize = std::env::var("GLOC_BENCH_RUNS")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(5);
    let list = Arc::new(SensorList::embedded());

    // Cycles per second, no logging.
    let mut rates = Vec::new();
    for _ in 0..runs {
        let mut sim = new_sim(&list);
        let started = Instant::now();
        for _ in 0..cycles {
            sim.step_cycle();
        }
        let seconds = started.elapsed().as_secs_f64();
        assert!(
            sim.end().is_none(),
            "the endless mission ended: {:?}",
            sim.end()
        );
        rates.push(cycles as f64 / seconds);
    }
    let rate = median(rates);
    println!(
        "simulate, Fig. 2 script, no log: {:.0} cycles/s ({:.2} µs/cycle), median of {runs}",
        rate,
        1e6 / rate
    );

    // A 30-day mission logging the default set to a .dba file.
    let path = std::env::temp_dir().join(format!("gloc-bench-{}.dba", std::process::id()));
    let mut walls = Vec::new();
    for _ in 0..runs {
        let mut sim = new_sim(&list);
        let started = Instant::now();
        let file = std::fs::File::create(&path).expect("temp file");
        let header = DbaHeader {
            filename: "bench".to_string(),
            mission_name: "FIG2-ENDLESS.MI".to_string(),
            fileopen_time: "Mon_May_24_00:00:00_2010".to_string(),
        };
        let mut writer = LogWriter::new(
            BufWriter::with_capacity(1 << 16, file),
            LogFormat::Dba,
            default_columns(&list, &[]),
            &list,
            &header,
        )
        .expect("header");
        for _ in 0..cycles {
            sim.step_cycle();
            writer.write_row(sim.sensors()).expect("row");
        }
        writer.finish().expect("flush");
        walls.push(started.elapsed().as_secs_f64());
    }
    let size = std::fs::metadata(&path).map(|meta| meta.len()).unwrap_or(0);
    let _ = std::fs::remove_file(&path);
    let wall = median(walls);
    println!(
        "30-day mission ({cycles} cycles), Fig. 2 script, .dba log of the default set: {wall:.3} s wall \
         ({:.0} cycles/s, {:.0}× real time), log {:.1} MB, median of {runs}",
        cycles as f64 / wall,
        cycles as f64 * 4.0 / wall,
        size as f64 / 1e6
    );
}
