//! The simulator allocates nothing per control cycle in steady state, with a
//! script running and a log being written (a counting global allocator).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::sensors::SensorList;
use gloc_sim::log::{default_columns, DbaHeader, LogFormat, LogWriter};
use gloc_sim::{default_mission, SimConfig, Simulation};

struct Counting;

// Counted per thread: the test harness's own threads allocate now and then (a global
// counter saw them: the test failed about one run in seven with 4 allocations).
thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

fn allocations() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

// SAFETY: every call is forwarded to the system allocator unchanged; the counter is a
// thread-local `Cell` with const initialisation, which does not allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: the caller's contract for `alloc`, passed on unchanged.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract for `dealloc`, passed on unchanged.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: the caller's contract for `realloc`, passed on unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Prints a line and stores a sensor every cycle: the busiest steady state.
const BUSY: &str = "nregs 2\nnblbs 1\nninstr 8\nlabel 0\nloads 444,r0\nwrite r0\nprints \"m deep\"\nloadi 0,r1\nstores r1,1387\nyield\njumpi 0\n";

#[test]
fn no_allocation_per_cycle() {
    let list = Arc::new(SensorList::embedded());
    for script in [include_str!("../../examples/fig2.gloc"), BUSY] {
        let checked = gloc::check(&gloc::parse(script), &list, &CheckOptions::default());
        let program = checked.program.expect("script checks");
        let mut sim = Simulation::new(
            &default_mission(),
            list.clone(),
            Some(program),
            &SimConfig::default(),
        )
        .expect("starts");
        let header = DbaHeader {
            filename: "alloc".to_string(),
            mission_name: "FIG2.MI".to_string(),
            fileopen_time: "now".to_string(),
        };
        let mut writer = LogWriter::new(
            std::io::sink(),
            LogFormat::Dba,
            default_columns(&list, &[]),
            &list,
            &header,
        )
        .expect("header");
        // Warm up: buffers reach their working size.
        for _ in 0..40 {
            sim.step_cycle();
            writer.write_row(sim.sensors()).expect("row");
        }
        let before = allocations();
        for _ in 0..200 {
            assert!(sim.step_cycle(), "the mission is still flying");
            writer.write_row(sim.sensors()).expect("row");
        }
        let after = allocations();
        assert_eq!(after - before, 0, "allocations in 200 cycles");
        assert!(sim.printed().count() <= 1);
    }
}
