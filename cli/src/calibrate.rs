//! `gloc calibrate`: fit the simulator's constants from a glider's own logs
//! (the fitting is `gloc_sim::calibrate`) and write them as a `[simulator]`
//! table, each value with what it was fitted from.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use clap::Args;
use gloc_sim::calibrate::{fit, yo_figures};
use gloc_sim::SimConfig;

use crate::data::SourceArgs;

#[derive(Args, Debug)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// Write the table here (a new file; see --force). Default: standard output.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Replace the output file if it exists (never one of the inputs).
    #[arg(long)]
    pub force: bool,
    /// The yo's climb target depth in m (its `c_target_depth`), for the turn latency.
    #[arg(long, value_name = "M", default_value_t = 3.0)]
    pub climb_target: f64,
}

pub fn main(args: CalibrateArgs) -> anyhow::Result<ExitCode> {
    if let Some(output) = &args.output {
        crate::data::check_output(output, &args.source.files)?;
        if output.exists() && !args.force {
            bail!(
                "{} exists; give --force to replace it, or -o another file (then copy the [simulator] table)",
                output.display()
            );
        }
    }
    let mut source = crate::data::open(&args.source)?;
    let track = gloc_project::logs::read_track(&mut source)?;
    for warning in gloc_dbd::CycleSource::take_warnings(&mut source) {
        eprintln!("warning: {warning}");
    }
    let fitted = fit(&track, args.climb_target, &SimConfig::default())
        .map_err(|problem| anyhow::anyhow!("cannot calibrate: {problem}"))?;
    let names: Vec<String> = args
        .source
        .files
        .iter()
        .map(|path| {
            path.file_name()
                .map(|name| name.to_string_lossy().into_owned())
                .unwrap_or_else(|| path.display().to_string())
        })
        .collect();
    let table = fitted.to_toml(&names.join(", "));
    if let Ok(figures) = yo_figures(&track, args.climb_target) {
        eprintln!(
            "measured      {} legs: dive {:.3} m/s, climb {:.3} m/s, pitch {:.3}/{:.3} rad, half-yo {:.0} s, overshoot {:.2}/{:.2} m, turn {:.1}/{:.1} s, turn latency {:.1} s, cycle {:.3} s, power {:.2} W",
            figures.legs,
            figures.dive_rate,
            figures.climb_rate,
            figures.dive_pitch,
            figures.climb_pitch,
            figures.half_yo_time,
            figures.bottom_overshoot,
            figures.top_overshoot,
            figures.bottom_turn_time,
            figures.top_turn_time,
            figures.turn_latency,
            figures.cycle_period,
            figures.power
        );
    }
    for (name, why) in &fitted.not_fitted {
        eprintln!("not fitted    {name}: {why}");
    }
    match &args.output {
        Some(output) => {
            // Written beside the output and renamed over it: a failure leaves the old file.
            crate::output::write_atomically(output, table.as_bytes())
                .map_err(|error| crate::output::write_error(error, "the table", output))?;
            eprintln!("wrote         {}", output.display());
        }
        None => out!("{table}"),
    }
    Ok(ExitCode::SUCCESS)
}
