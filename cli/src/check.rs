//! `gloc check`.

use std::process::ExitCode;

pub fn main(_args: crate::CheckArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`gloc check` is not built yet")
}
