//! `gloc reindex FILE.gloc --to LIST [--from LIST] -o OUT.gloc`: rewrites a GLOC
//! file's sensor indices from one sensor list to another by name, and states the
//! new list in its `# sensors:` line (`gloc_engine::gloc::identity::reindex`).

use std::path::Path;
use std::process::ExitCode;

use anyhow::{bail, Context};
use gloc_engine::gloc::{self, identity};
use gloc_engine::sensors::{find_cac, SensorList, EMBEDDED_CRC};

use crate::render::{SourceFile, Tally};

pub fn main(args: crate::ReindexArgs) -> anyhow::Result<ExitCode> {
    // The output may be none of the inputs: the script, the target list, the source list.
    let inputs: Vec<&Path> = [
        Some(args.file.as_path()),
        Some(args.to.as_path()),
        args.from.as_deref(),
    ]
    .into_iter()
    .flatten()
    .collect();
    crate::output::check_output(&inputs, "-o", &args.output)?;
    let text = gloc_engine::files::read_text(&args.file, gloc_engine::files::SCRIPT)
        .with_context(|| format!("cannot read the GLOC file `{}`", args.file.display()))?;
    let display = args.file.display().to_string();
    let order = args.sensor_order.unwrap_or_default();
    let mut tally = Tally::default();
    let Some(to) = crate::loading::load_sensors(&args.to, "--to", order, &mut tally)? else {
        return Ok(ExitCode::FAILURE);
    };
    let parsed = gloc::parse(&text);
    let from = match (&args.from, identity::stated_list(&parsed)) {
        (Some(path), _) => match crate::loading::load_sensors(path, "--from", order, &mut tally)? {
            Some(list) => list,
            None => return Ok(ExitCode::FAILURE),
        },
        (None, Some(Ok(stated))) if stated.crc == EMBEDDED_CRC => SensorList::embedded(),
        (None, Some(Ok(stated))) => {
            // Beside the script, then beside the target list (as `gloc check` looks).
            let folders = identity::list_folders(Some(&args.file), Some(&args.to), None);
            let Some(path) = find_cac(&stated.crc, &folders) else {
                bail!(
                    "{display} states `# sensors: {}`, and `{}.cac` is not beside it or beside \
                     the target list: give the list with --from",
                    stated.crc,
                    stated.crc
                );
            };
            match crate::loading::load_sensors(&path, "--from", order, &mut tally)? {
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
            crate::output::write_atomically(&args.output, rewritten.as_bytes()).map_err(
                |error| crate::output::write_error(error, "the reindexed script", &args.output),
            )?;
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
