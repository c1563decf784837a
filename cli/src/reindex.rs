//! `gloc reindex FILE.gloc --to LIST [--from LIST] -o OUT.gloc`: rewrites a GLOC
//! file's sensor indices from one sensor list to another by name, and states the
//! new list in its `# sensors:` line (`gloc_engine::gloc::identity::reindex`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context};
use gloc_engine::gloc::{self, identity};
use gloc_engine::sensors::{find_cac, SensorList, EMBEDDED_CRC};

use crate::render::{SourceFile, Tally};

pub fn main(args: crate::ReindexArgs) -> anyhow::Result<ExitCode> {
    if same_file(&args.file, &args.output) {
        bail!(
            "`{}` is the input: write the reindexed script to another file",
            args.output.display()
        );
    }
    let bytes = std::fs::read(&args.file)
        .with_context(|| format!("cannot read the GLOC file `{}`", args.file.display()))?;
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let display = args.file.display().to_string();
    let order = args.sensor_order.unwrap_or_default();
    let mut tally = Tally::default();
    let Some(to) = crate::check::load_sensors(&args.to, "--to", order, &mut tally)? else {
        return Ok(ExitCode::FAILURE);
    };
    let parsed = gloc::parse(&text);
    let from = match (&args.from, identity::stated_list(&parsed)) {
        (Some(path), _) => match crate::check::load_sensors(path, "--from", order, &mut tally)? {
            Some(list) => list,
            None => return Ok(ExitCode::FAILURE),
        },
        (None, Some(Ok(stated))) if stated.crc == EMBEDDED_CRC => SensorList::embedded(),
        (None, Some(Ok(stated))) => {
            let folders: Vec<PathBuf> = [args.file.parent(), args.to.parent()]
                .into_iter()
                .flatten()
                .map(|folder| {
                    if folder.as_os_str().is_empty() {
                        PathBuf::from(".")
                    } else {
                        folder.to_path_buf()
                    }
                })
                .collect();
            let Some(path) = find_cac(&stated.crc, &folders) else {
                bail!(
                    "{display} states `# sensors: {}`, and `{}.cac` is not beside it or beside \
                     the target list: give the list with --from",
                    stated.crc,
                    stated.crc
                );
            };
            match crate::check::load_sensors(&path, "--from", order, &mut tally)? {
                Some(list) => list,
                None => return Ok(ExitCode::FAILURE),
            }
        }
        (None, Some(Err(_))) => {
            bail!("{display}: its `# sensors:` line is not a CRC: give the list with --from")
        }
        (None, None) => {
            eprintln!(
                "{display}: no `# sensors:` line; its indices are taken as the embedded list's \
                 ({EMBEDDED_CRC}); --from LIST says otherwise"
            );
            SensorList::embedded()
        }
    };
    match identity::reindex(&text, &parsed, &from, &to) {
        Ok(rewritten) => {
            std::fs::write(&args.output, rewritten)
                .with_context(|| format!("cannot write `{}`", args.output.display()))?;
            eprintln!(
                "{display}: indices rewritten from {} to {} in {}",
                from.label(),
                to.label(),
                args.output.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Err(problems) => {
            let source = SourceFile::new(&display, &text);
            for problem in &problems {
                eprint!("{}", source.render(problem));
            }
            eprintln!("nothing written");
            Ok(ExitCode::FAILURE)
        }
    }
}

/// True when both paths name one file (so the output would overwrite the input).
fn same_file(input: &Path, output: &Path) -> bool {
    match (input.canonicalize(), output.canonicalize()) {
        (Ok(input), Ok(output)) => input == output,
        _ => input == output,
    }
}
