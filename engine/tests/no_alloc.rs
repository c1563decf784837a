//! Proves the interpreter allocates nothing per cycle in steady state: a
//! counting global allocator (per thread, so parallel tests do not disturb
//! it) around many cycles of Fig. 2 and of a script that prints every cycle.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::sensors::{SensorId, SensorList};
use gloc_engine::vm::{CycleEnd, Host, Machine, MachineConfig};

struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: every call is forwarded to the system allocator unchanged; the
// counter is a thread-local `Cell` with const initialisation, which does not
// allocate.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: the caller's contract for `alloc`, passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, pointer: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract for `dealloc`, passed on unchanged.
        unsafe { System.dealloc(pointer, layout) }
    }
    unsafe fn realloc(&self, pointer: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: the caller's contract for `realloc`, passed on unchanged.
        unsafe { System.realloc(pointer, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

/// A host that keeps a fixed sensor array and counts printed bytes.
struct ArrayHost {
    values: Vec<f64>,
    printed_bytes: usize,
}

impl Host for ArrayHost {
    fn load_sensor(&mut self, sensor: SensorId) -> f64 {
        self.values[sensor.index()]
    }
    fn store_sensor(&mut self, sensor: SensorId, value: f64) {
        self.values[sensor.index()] = value;
    }
    fn print_line(&mut self, line: &str) {
        self.printed_bytes += line.len();
    }
}

fn steady_state_allocations(text: &str) -> u64 {
    let sensors = SensorList::embedded();
    let checked = gloc::check(&gloc::parse(text), &sensors, &CheckOptions::default());
    let program = checked.program.expect("checks clean");
    let mut machine = Machine::new(program, MachineConfig::default());
    let mut host = ArrayHost {
        values: sensors.initial_values(),
        printed_bytes: 0,
    };
    let depth = sensors.lookup("m_depth").expect("m_depth exists").index();
    let run = |machine: &mut Machine, host: &mut ArrayHost, cycles: u32| {
        for cycle in 0..cycles {
            // A depth ramp 0 → 20 → 0 m, over and over.
            let phase = f64::from(cycle % 40);
            host.values[depth] = if phase <= 20.0 { phase } else { 40.0 - phase };
            assert_eq!(machine.run_cycle(host), CycleEnd::Yielded);
        }
    };
    // Warm up: the output buffer reaches its working size.
    run(&mut machine, &mut host, 100);
    let before = allocations();
    run(&mut machine, &mut host, 10_000);
    let after = allocations();
    assert!(host.printed_bytes > 0 || !text.contains("print"));
    after - before
}

#[test]
fn no_heap_allocation_per_cycle() {
    let fig2 = include_str!("../../examples/fig2.gloc");
    assert_eq!(steady_state_allocations(fig2), 0);

    let printing = r#"nregs 3
nblbs 1
ninstr 12
label 0
writes "depth"
loads 444,r0
write r0
loadd 0.1,r1
mul r0,r1,r2
write r2
loadi 42,r1
print r1
prints "done"
yield
jumpi 0
"#;
    assert_eq!(steady_state_allocations(printing), 0);

    // The counter works: building a machine allocates.
    let before = allocations();
    let _list = SensorList::embedded();
    assert!(allocations() > before);
}
