//! `gloc run`.

use std::process::ExitCode;

pub fn main(_args: crate::RunArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`gloc run` is not built yet")
}
