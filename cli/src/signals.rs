//! Signals during a run: SIGINT, SIGTERM and SIGHUP stop `run`, `replay` and `batch`
//! between cycles instead of ending the process.

use std::sync::atomic::{AtomicBool, AtomicUsize};
use std::sync::Arc;

use anyhow::Context;

/// SIGINT, SIGTERM and SIGHUP set the returned number (the signal) instead of ending
/// the process, so the run stops between cycles, keeps its log and prints its summary;
/// a second one while the first is handled ends the process at once. Installed once,
/// by the first call (`gloc run` calls it before loading anything); later calls return
/// the same flag.
pub fn interrupt_signals() -> anyhow::Result<Arc<AtomicUsize>> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    static RECEIVED: std::sync::OnceLock<Arc<AtomicUsize>> = std::sync::OnceLock::new();
    if let Some(received) = RECEIVED.get() {
        return Ok(Arc::clone(received));
    }
    let received = Arc::new(AtomicUsize::new(0));
    let seen = Arc::new(AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM, SIGHUP] {
        signal_hook::flag::register_conditional_shutdown(signal, 128 + signal, Arc::clone(&seen))
            .context("cannot install a signal handler")?;
        signal_hook::flag::register(signal, Arc::clone(&seen))
            .context("cannot install a signal handler")?;
        signal_hook::flag::register_usize(signal, Arc::clone(&received), signal as usize)
            .context("cannot install a signal handler")?;
    }
    Ok(Arc::clone(RECEIVED.get_or_init(|| received)))
}

pub fn signal_name(signal: usize) -> &'static str {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    match signal as i32 {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    }
}
