//! `gloc explain [CODE]`: a diagnostic code's entry in the one registry
//! (`gloc_engine::codes`), or every entry when no code is given.

use std::process::ExitCode;

use clap::Args;
use gloc_engine::codes::{self, CodeInfo};

#[derive(Args, Debug)]
pub struct ExplainArgs {
    /// The code to explain (`E0101`, `w2302`, `S0107`); without one, every code.
    pub code: Option<String>,
}

fn area_name(area: &str) -> &'static str {
    match area {
        "gloc" => "GLOC",
        "sensors" => "sensor lists",
        "gbasic" => "GBASIC",
        "mission" => "missions",
        "settings" => "project settings",
        _ => "gloc",
    }
}

/// `E0101 error (GLOC): register out of range (`>= nregs`)`.
fn line(info: &CodeInfo) -> String {
    format!(
        "{} {} ({}): {}",
        info.code,
        info.severity,
        area_name(info.area),
        info.doc.replace("\\|", "|")
    )
}

pub fn main(args: ExplainArgs) -> anyhow::Result<ExitCode> {
    let Some(code) = args.code else {
        let all: Vec<String> = codes::ALL.iter().map(line).collect();
        outln!("{}", all.join("\n"));
        return Ok(ExitCode::SUCCESS);
    };
    match codes::lookup(code.trim()) {
        Some(info) => {
            outln!("{}", line(info));
            Ok(ExitCode::SUCCESS)
        }
        None => anyhow::bail!(
            "`{code}` is not a gloc diagnostic code; codes look like E0101, W2302 or S0107 \
             (`gloc explain` lists them all, as does docs/diagnostics.md)"
        ),
    }
}
