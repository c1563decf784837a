//! Each line the script prints carries the pc of the instruction that printed it
//! (`Simulation::print_sites`), so a debugger can name the printing statement.

use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::program::{Pc, Program};
use gloc_engine::sensors::SensorList;
use gloc_sim::{default_mission, SimConfig, Simulation};

fn compile(text: &str, list: &SensorList) -> Arc<Program> {
    let checked = gloc::check(&gloc::parse(text), list, &CheckOptions::default());
    match checked.program {
        Some(program) => program,
        None => panic!("script does not check: {:?}", checked.diagnostics),
    }
}

#[test]
fn every_printed_line_has_the_pc_of_its_print() {
    // pcs by hand: 0 loadi, 1 print, 2 loadi, 3 prints, 4 print, 5 yield.
    let script = "nregs 1\nnblbs 0\nninstr 6\nloadi 7,r0\nprint r0\nloadi 8,r0\n\
                  prints \"eight\"\nprint r0\nyield\n";
    let list = SensorList::embedded();
    let program = compile(script, &list);
    let mut sim = Simulation::new(
        &default_mission(),
        Arc::new(list),
        Some(program),
        &SimConfig::default(),
    )
    .expect("starts");
    assert!(sim.step_cycle());
    assert_eq!(sim.printed_text(), "7\neight\n8\n");
    let ends = [2, 8, 10];
    let pcs = [Pc(1), Pc(3), Pc(4)];
    let sites: Vec<(usize, Pc)> = ends.into_iter().zip(pcs).collect();
    assert_eq!(sim.print_sites(), sites.as_slice());
}
