//! `gloc compile`.

use std::process::ExitCode;

pub fn main(_args: crate::CompileArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`gloc compile` is not built yet")
}
