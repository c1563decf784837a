//! Deep expressions (hardening, issue 19): a chain `1 + 1 + …` is a left-deep tree that
//! every pass follows recursively, so its depth is capped at 256 operators (E2009) and a
//! million-term line gets one located diagnostic, not a stack overflow; at the cap the
//! program compiles, with and without `-O`, and computes the right value.

use gloc_compiler::{load_script, Language, LoadOptions, LoadedScript, Optimization};
use gloc_engine::sensors::SensorId;
use gloc_engine::sensors::SensorList;
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};

fn load(text: &str, optimization: Optimization) -> LoadedScript {
    load_script(
        text,
        Language::Gbasic,
        &SensorList::embedded(),
        &LoadOptions::from(optimization),
    )
}

/// `dim x as integer` and `x = 1 OP 1 OP …` with `terms` terms, then `print x`.
fn chain(operator: &str, terms: usize) -> String {
    let separator = format!(" {operator} ");
    format!(
        "dim x as integer\nx = {}\nprint x\n",
        vec!["1"; terms].join(&separator)
    )
}

#[derive(Default)]
struct Printed(Vec<String>);

impl Host for Printed {
    fn load_sensor(&mut self, _sensor: SensorId) -> f64 {
        0.0
    }
    fn store_sensor(&mut self, _sensor: SensorId, _value: f64) {}
    fn print_line(&mut self, line: &str) {
        self.0.push(line.to_string());
    }
}

fn first_line_printed(loaded: &LoadedScript) -> String {
    let program = loaded.program.clone().expect("a program");
    let mut machine = Machine::new(program, MachineConfig::default());
    let mut host = Printed::default();
    let end = machine.run_cycle(&mut host);
    assert!(!matches!(end, CycleEnd::Trapped(_)), "{end:?}");
    host.0.first().cloned().expect("a printed line")
}

#[test]
fn a_long_chain_is_one_located_error_for_every_operator() {
    // The 257th operator's byte offset in line 2, worked by hand: "x = " is 4 bytes,
    // each "1 OP " before it 3 + len(OP), then "1 ". 150,000 terms: deep, and within
    // GBASIC's 1 MB even with `and` and `mod` (6 bytes a term).
    for operator in ["+", "-", "*", "/", "\\", "or", "and", "mod", "=", "<"] {
        let text = chain(operator, 150_000);
        let loaded = load(&text, Optimization::Plain);
        let errors: Vec<_> = loaded
            .diagnostics
            .iter()
            .filter(|diagnostic| diagnostic.code == "E2009")
            .collect();
        assert_eq!(errors.len(), 1, "{operator}: {:?}", loaded.diagnostics);
        let step = 3 + operator.len();
        let in_line = 4 + 256 * step + 2;
        let offset = text.find('\n').expect("two lines") + 1 + in_line;
        assert_eq!(errors[0].span.start as usize, offset, "{operator}");
        assert_eq!(&text[offset..offset + operator.len()], operator);
        assert!(loaded.program.is_none());
    }
}

#[test]
fn a_chain_of_256_operators_compiles_and_adds_up() {
    for optimization in [Optimization::Plain, Optimization::Optimized] {
        let loaded = load(&chain("+", 257), optimization);
        assert!(!loaded.has_errors(), "{:?}", loaded.diagnostics);
        assert_eq!(first_line_printed(&loaded), "257");
    }
}

#[test]
fn a_mixed_chain_at_the_cap_with_conversions_runs_in_a_small_stack() {
    // Integer and float terms alternate, so the typer adds a conversion at every level;
    // the whole load runs on a 1 MB thread (the test harness gives 2 MB).
    let terms: Vec<&str> = (0..257)
        .map(|i| if i % 2 == 0 { "1" } else { "0.5" })
        .collect();
    let text = format!("dim y as float\ny = {}\nprint y\n", terms.join(" + "));
    let worker = std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || {
            let mut printed = Vec::new();
            for optimization in [Optimization::Plain, Optimization::Optimized] {
                let loaded = load(&text, optimization);
                assert!(!loaded.has_errors(), "{:?}", loaded.diagnostics);
                printed.push(first_line_printed(&loaded));
            }
            printed
        })
        .expect("a thread");
    // 129 ones and 128 halves.
    assert_eq!(worker.join().expect("no overflow"), ["193.0", "193.0"]);
}

#[test]
fn deep_parentheses_and_prefix_operators_are_refused_with_e2008() {
    for (open, close) in [("(", ")"), ("-", ""), ("not ", "")] {
        let text = format!(
            "dim x as integer\nx = {}1{}\n",
            open.repeat(200_000),
            close.repeat(200_000)
        );
        let loaded = load(&text, Optimization::Plain);
        let codes: Vec<&str> = loaded.diagnostics.iter().map(|d| d.code).collect();
        assert!(codes.contains(&"E2008"), "{open}: {codes:?}");
        assert!(loaded.program.is_none());
    }
}
