//! `gloc run`: with `--replay`, run a script on recorded sensor values
//! (`replay.rs`); otherwise fly it in the simulator.

use std::process::ExitCode;

pub fn main(args: crate::RunArgs) -> anyhow::Result<ExitCode> {
    // From here on a signal stops the run between cycles instead of killing it.
    crate::signals::interrupt_signals()?;
    if !args.replay.is_empty() {
        return crate::replay::main(args);
    }
    crate::simulate::main(args)
}
