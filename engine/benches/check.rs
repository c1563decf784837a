//! Parse + check benchmark: a 6.5 MB straight-line script (500,000 lines: within the
//! 2^19-line cap; 800,000 lines before it) and 2,000 copies of
//! Fig. 2's body (about 20,000 lines, what a large compiled GBASIC program
//! gives). Prints the median wall time of each stage.
//! Run with `cargo bench -p gloc-engine --bench check`.

use std::time::Instant;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::sensors::SensorList;

fn median_ms(mut run: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..5)
        .map(|_| {
            let start = Instant::now();
            run();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[2]
}

fn measure(name: &str, text: &str) {
    let sensors = SensorList::embedded();
    let parse_ms = median_ms(|| {
        std::hint::black_box(gloc::parse(text));
    });
    let parsed = gloc::parse(text);
    let check_ms = median_ms(|| {
        std::hint::black_box(gloc::check(&parsed, &sensors, &CheckOptions::default()));
    });
    let checked = gloc::check(&parsed, &sensors, &CheckOptions::default());
    assert!(
        checked.program.is_some(),
        "{:?}",
        checked.diagnostics.first()
    );
    println!(
        "{name}: {} lines, {:.1} MB: parse {parse_ms:.1} ms, check {check_ms:.1} ms (median of 5)",
        text.lines().count(),
        text.len() as f64 / 1e6
    );
}

fn main() {
    let body_lines = 500_000;
    let mut big = format!("nregs 3\nnblbs 1\nninstr {}\nlabel 0\n", body_lines + 3);
    for _ in 0..body_lines {
        big.push_str("add r0,r1,r2\n");
    }
    big.push_str("yield\njumpi 0\n");
    measure("straight line", &big);

    // Fig. 2's state machine repeated with fresh registers and labels.
    let copies = 1_000;
    let mut body = String::new();
    for copy in 0..copies {
        let (label, register) = (copy * 7, copy * 8);
        let next = if copy + 1 == copies { 0 } else { label + 7 };
        let lines = [
            format!("label {label}"),
            format!("loads 444,r{register}"),
            format!("loadd 15.0,r{}", register + 1),
            format!("cmpgt r{register},r{},r{}", register + 1, register + 2),
            format!("cbr r{},{},{}", register + 2, label + 3, label + 4),
            format!("label {}", label + 3),
            format!("loadi 128,r{}", register + 3),
            format!("stores r{},1387", register + 3),
            format!("jumpi {}", label + 1),
            format!("label {}", label + 4),
            "yield".to_string(),
            format!("jumpi {label}"),
            format!("label {}", label + 1),
            format!("loads 444,r{}", register + 4),
            format!("loadd 5.0,r{}", register + 5),
            format!(
                "cmplt r{},r{},r{}",
                register + 4,
                register + 5,
                register + 6
            ),
            format!("cbr r{},{},{}", register + 6, label + 5, label + 6),
            format!("label {}", label + 5),
            format!("loadi 0,r{}", register + 7),
            format!("stores r{},1387", register + 7),
            format!("jumpi {}", label + 2),
            format!("label {}", label + 6),
            "yield".to_string(),
            format!("jumpi {}", label + 1),
            format!("label {}", label + 2),
            "yield".to_string(),
            format!("jumpi {next}"),
        ];
        for line in lines {
            body.push_str(&line);
            body.push('\n');
        }
    }
    let state_machines = format!(
        "nregs {}\nnblbs {}\nninstr {}\n{body}",
        copies * 8,
        copies * 7,
        copies * 27
    );
    measure("fig2 x1000", &state_machines);
}
