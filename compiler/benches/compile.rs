//! Compile-time figures: how long the compiler takes on the thermocline tracker and
//! on a large generated program, with and without `-O`, and the size figures.
//! Run with `cargo bench -p gloc-compiler`; it prints, it asserts nothing.

use std::time::Instant;

use gloc_compiler::{compile, CompileOptions, Optimization};
use gloc_engine::sensors::SensorList;

fn measure(name: &str, text: &str, sensors: &SensorList) {
    for optimization in [Optimization::Plain, Optimization::Optimized] {
        let options = CompileOptions { optimization };
        let runs = 20;
        let start = Instant::now();
        let mut stats = None;
        for _ in 0..runs {
            let compiled = compile(text, sensors, &options);
            assert!(!compiled.has_errors(), "{name}: {:?}", compiled.diagnostics);
            stats = compiled.code.map(|code| code.build.stats);
        }
        let each = start.elapsed() / runs;
        let stats = stats.unwrap_or_default();
        println!(
            "{name:<28} {:<4} {:>9.3} ms   {:>6} GLOC lines {:>6} instructions {:>5} registers {:>5} labels",
            if optimization.enabled() { "-O" } else { "" },
            each.as_secs_f64() * 1000.0,
            stats.lines,
            stats.instructions,
            stats.registers,
            stats.labels
        );
    }
}

fn main() {
    let sensors = SensorList::embedded();
    let tracker = include_str!("../../examples/thermocline.gbas");
    measure("thermocline.gbas", tracker, &sensors);
    // A long program: 400 copies of a block with an if, a for loop and arrays.
    let mut large =
        String::from("dim a(50) as float\ndim i as integer\ndim j as integer\ndim s as float\n");
    for copy in 0..400 {
        large.push_str(&format!(
            "label: block{copy}\nfor i = 0 to 49\n  a(i) = a(i) + m_depth * {copy}.5\n  if a(i) > 100.0 then\n    s = s + a(i)\n  elseif i mod 2 = 0 then\n    j = j + 1\n  endif\nnext\nyield\n"
        ));
    }
    large.push_str("print s, j\n");
    measure("generated (4,000 lines)", &large, &sensors);
}
