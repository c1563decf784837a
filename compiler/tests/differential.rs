//! Differential test of the optimizer: every fixture and example runs on the GLOC
//! machine with and without `-O` against the same scripted host (a recorded-style
//! depth ramp and a temperature profile), and must make the same sensor writes in
//! the same cycles, print the same lines in the same cycles and end the same way.
//! Also: the `run/` programs print exactly the `.out` beside them (written by hand).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_compiler::{load_script, Language, LoadOptions, LoadedScript, Optimization};
use gloc_engine::program::Program;
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};

/// A host that plays a depth ramp (a 0–30 m triangle at 0.6 m per cycle) and a
/// temperature profile over depth, and records what the script does.
struct ScriptedHost {
    cycle: u64,
    depth_sensor: u32,
    temperature_sensor: u32,
    time_sensor: u32,
    stored: HashMap<u32, f64>,
    writes: Vec<(u64, u32, u64)>,
    lines: Vec<(u64, String)>,
}

impl ScriptedHost {
    fn new(sensors: &SensorList) -> ScriptedHost {
        let id = |name: &str| sensors.lookup(name).expect("embedded sensor").0;
        ScriptedHost {
            cycle: 0,
            depth_sensor: id("m_depth"),
            temperature_sensor: id("sci_water_temp"),
            time_sensor: id("m_present_time"),
            stored: HashMap::new(),
            writes: Vec::new(),
            lines: Vec::new(),
        }
    }

    fn depth(&self) -> f64 {
        let travelled = self.cycle as f64 * 0.6;
        let phase = travelled % 60.0;
        if phase <= 30.0 {
            phase
        } else {
            60.0 - phase
        }
    }
}

impl Host for ScriptedHost {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        let depth = self.depth();
        if sensor.0 == self.depth_sensor {
            depth
        } else if sensor.0 == self.temperature_sensor {
            // Warm surface over a thermocline between about 8 and 16 m.
            10.0 + 12.0 * 0.5 * (1.0 - ((depth - 12.0) / 3.0).tanh())
        } else if sensor.0 == self.time_sensor {
            self.cycle as f64 * 4.0
        } else {
            self.stored.get(&sensor.0).copied().unwrap_or(0.0)
        }
    }

    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        self.stored.insert(sensor.0, value);
        self.writes.push((self.cycle, sensor.0, value.to_bits()));
    }

    fn print_line(&mut self, line: &str) {
        self.lines.push((self.cycle, line.to_string()));
    }
}

#[derive(Debug, PartialEq)]
struct Run {
    writes: Vec<(u64, u32, u64)>,
    lines: Vec<(u64, String)>,
    /// How it ended: halted, trapped (kind and GBASIC line), or still running.
    end: String,
    cycles: u64,
}

const CYCLES: u64 = 2000;

fn run(loaded: &LoadedScript, sensors: &SensorList) -> Run {
    let program: Arc<Program> = loaded.program.clone().expect("program");
    let mut machine = Machine::new(
        program,
        MachineConfig {
            cycle_budget: 1_000_000,
        },
    );
    let mut host = ScriptedHost::new(sensors);
    let mut end = String::from("running");
    while host.cycle < CYCLES {
        match machine.run_cycle(&mut host) {
            CycleEnd::Yielded => host.cycle += 1,
            CycleEnd::Halted => {
                end = "halted".to_string();
                break;
            }
            CycleEnd::Trapped(trap) => {
                let line = loaded
                    .line_of_pc(trap.pc)
                    .map_or_else(|| "?".to_string(), |line| line.to_string());
                end = format!(
                    "trap {} at GBASIC line {line}",
                    loaded.trap_message(&trap.kind)
                );
                break;
            }
        }
    }
    Run {
        writes: host.writes,
        lines: host.lines,
        end,
        cycles: host.cycle,
    }
}

fn programs() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in [
        "tests/fixtures/gbasic/ok",
        "tests/fixtures/gbasic/run",
        "examples",
    ] {
        // These folders are part of the repository: a missing one is a broken
        // checkout, not a folder to skip.
        let entries = std::fs::read_dir(root.join(dir))
            .unwrap_or_else(|error| panic!("cannot read {dir}: {error}"));
        for entry in entries {
            let path = entry.expect("readable entry").path();
            if path
                .extension()
                .is_some_and(|extension| extension == "gbas")
            {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn load(text: &str, sensors: &SensorList, optimization: Optimization) -> LoadedScript {
    load_script(
        text,
        Language::Gbasic,
        sensors,
        &LoadOptions::from(optimization),
    )
}

#[test]
fn optimized_and_unoptimized_builds_behave_identically() {
    let sensors = SensorList::embedded();
    let files = programs();
    assert!(
        files.len() >= 8,
        "expected the fixtures and examples, found {files:?}"
    );
    let mut report = String::new();
    for path in files {
        let text = std::fs::read_to_string(&path).expect("readable program");
        let plain = load(&text, &sensors, Optimization::Plain);
        let optimized = load(&text, &sensors, Optimization::Optimized);
        assert!(
            plain.program.is_some(),
            "{}: {:?}",
            path.display(),
            plain.diagnostics
        );
        assert!(
            optimized.program.is_some(),
            "{} -O: {:?}",
            path.display(),
            optimized.diagnostics
        );
        let plain_run = run(&plain, &sensors);
        let optimized_run = run(&optimized, &sensors);
        assert_eq!(
            plain_run,
            optimized_run,
            "{} behaves differently with -O",
            path.display()
        );
        let (before, after) = (
            plain.gbasic.as_ref().expect("stats").stats,
            optimized.gbasic.as_ref().expect("stats").stats,
        );
        assert!(
            after.instructions <= before.instructions,
            "{}: -O grew the code",
            path.display()
        );
        assert!(
            after.registers <= before.registers,
            "{}: -O used more registers",
            path.display()
        );
        report.push_str(&format!(
            "{:<28} instructions {:>4} -> {:>4}   registers {:>4} -> {:>4}   ({} writes, {} lines, {})\n",
            path.file_name().and_then(|name| name.to_str()).unwrap_or(""),
            before.instructions,
            after.instructions,
            before.registers,
            after.registers,
            plain_run.writes.len(),
            plain_run.lines.len(),
            plain_run.end,
        ));
    }
    println!("{report}");
}

#[test]
fn run_programs_print_what_was_worked_out_by_hand() {
    let sensors = SensorList::embedded();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/gbasic/run");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("run fixtures") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|extension| extension != "gbas") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("readable");
        let expected =
            std::fs::read_to_string(path.with_extension("out")).expect(".out beside the program");
        for optimization in [Optimization::Plain, Optimization::Optimized] {
            let loaded = load(&text, &sensors, optimization);
            assert!(
                loaded.program.is_some(),
                "{}: {:?}",
                path.display(),
                loaded.diagnostics
            );
            let result = run(&loaded, &sensors);
            let mut printed: String = result
                .lines
                .iter()
                .map(|(_, line)| format!("{line}\n"))
                .collect();
            printed.push_str(&format!("-- {}\n", result.end));
            assert_eq!(
                printed,
                expected,
                "{} (optimization {optimization:?})",
                path.display()
            );
        }
        checked += 1;
    }
    assert!(checked >= 3, "expected run fixtures in {}", dir.display());
}
