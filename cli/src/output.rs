//! Every file `gloc` writes goes through here: an output may never be one of the run's
//! inputs or another output (compared by device and inode, so a hard link or a symlink
//! is caught too), and is written to a temporary file in the same folder that replaces
//! the target only when complete, so a failure or a full disk leaves the old file.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::bail;

/// Set once standard output turned out to be a closed pipe: nothing more is written.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes a command's report to standard output (the `out!` and `outln!` macros).
/// A reader that stops early (`| head`) closes the pipe: the rest of the output is
/// dropped and the command ends as it would have, with no message; any other
/// error (a full disk behind a redirection) is reported once on stderr.
pub fn print(args: std::fmt::Arguments<'_>) {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return;
    }
    if let Err(error) = io::stdout().lock().write_fmt(args) {
        STDOUT_CLOSED.store(true, Ordering::Relaxed);
        if !is_closed_pipe(&error) {
            eprintln!("error: cannot write to standard output: {error}");
        }
    }
}

/// Whether a write failed because the reader closed the pipe (`| head`): not a
/// failure of the command, which stops writing there.
pub fn is_closed_pipe(error: &io::Error) -> bool {
    error.kind() == io::ErrorKind::BrokenPipe
}

/// One output the command will write, with its flag for messages.
pub struct Output<'a> {
    pub flag: &'a str,
    pub path: &'a Path,
}

/// [`check_outputs`] for a command that writes one file.
pub fn check_output(inputs: &[&Path], flag: &str, path: &Path) -> anyhow::Result<()> {
    check_outputs(inputs, &[Output { flag, path }])
}

/// Refuses an output that is an input or another output. `inputs` are files already
/// read (or about to be); paths that do not exist are skipped.
pub fn check_outputs(inputs: &[&Path], outputs: &[Output<'_>]) -> anyhow::Result<()> {
    for (index, output) in outputs.iter().enumerate() {
        if let Some(output_id) = file_id(output.path) {
            for input in inputs {
                if file_id(input) == Some(output_id) {
                    bail!(
                        "{} `{}` is the input `{}`: writing it would destroy the input; \
                         choose another output path",
                        output.flag,
                        output.path.display(),
                        input.display()
                    );
                }
            }
        }
        for other in &outputs[..index] {
            if same_target(output.path, other.path) {
                bail!(
                    "{} `{}` is also the file of {}: choose two different paths",
                    output.flag,
                    output.path.display(),
                    other.flag
                );
            }
        }
    }
    Ok(())
}

/// Has `write` write a file under a temporary name beside `target` (same extension, so a
/// writer that picks its format by extension still sees it), then renames it over the
/// target; on a failure the temporary file is removed and the target is untouched. For
/// writers that take a path (the plotter's PNG encoder), where [`AtomicFile`] cannot go.
pub fn write_through_temporary(
    target: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> anyhow::Result<()> {
    let folder = match target.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    };
    let name = target
        .file_name()
        .ok_or_else(|| anyhow::anyhow!("`{}` is not a file name", target.display()))?;
    let mut temporary_name = std::ffi::OsString::from(".");
    temporary_name.push(name);
    temporary_name.push(format!(".gloc-{}.tmp", std::process::id()));
    if let Some(extension) = target.extension() {
        temporary_name.push(".");
        temporary_name.push(extension);
    }
    let temporary = folder.join(temporary_name);
    refuse_special(target).map_err(|error| write_error(error, "the file", target))?;
    // The writer's own failure is the output's too (exit code 4).
    let result = write(&temporary)
        .map_err(|message| anyhow::Error::new(crate::exit::Unwritable(message)))
        .and_then(|()| {
            std::fs::rename(&temporary, target)
                .map_err(|error| write_error(error, "the file", target))
        });
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Writes `bytes` to `path` atomically (see [`AtomicFile`]).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes)?;
    file.commit()
}

/// A file written beside its target under a temporary name; [`AtomicFile::commit`]
/// flushes it to disk and renames it over the target. Dropped without a commit, it
/// removes the temporary file and the target is untouched.
pub struct AtomicFile {
    temporary: PathBuf,
    target: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl AtomicFile {
    pub fn create(target: &Path) -> io::Result<AtomicFile> {
        let folder = match target.parent() {
            Some(folder) if !folder.as_os_str().is_empty() => folder,
            _ => Path::new("."),
        };
        let name = target
            .file_name()
            .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?;
        let mut temporary_name = std::ffi::OsString::from(".");
        temporary_name.push(name);
        temporary_name.push(format!(".gloc-{}.tmp", std::process::id()));
        let temporary = folder.join(temporary_name);
        refuse_special(target)?;
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(&temporary)?;
        Ok(AtomicFile {
            temporary,
            target: target.to_path_buf(),
            writer: Some(BufWriter::with_capacity(1 << 16, file)),
        })
    }

    /// Flushes, syncs (so a full disk shows here, not later) and renames over the target.
    pub fn commit(mut self) -> io::Result<()> {
        let writer = self
            .writer
            .take()
            .expect("the writer is only taken here, once");
        let result = (|| {
            let file = writer
                .into_inner()
                .map_err(io::IntoInnerError::into_error)?;
            if let Ok(old) = std::fs::metadata(&self.target) {
                // The new file keeps the old one's permissions.
                file.set_permissions(old.permissions())?;
            }
            file.sync_all()?;
            drop(file);
            std::fs::rename(&self.temporary, &self.target)
        })();
        if result.is_err() {
            // The last bytes did not fit (a full disk): no temporary file is left.
            let _ = std::fs::remove_file(&self.temporary);
        }
        result
    }
}

impl Write for AtomicFile {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.writer_mut()?.write(bytes)
    }

    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.writer_mut()?.write_all(bytes)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.writer_mut()?.flush()
    }
}

impl AtomicFile {
    fn writer_mut(&mut self) -> io::Result<&mut BufWriter<File>> {
        // Only `commit`, which consumes the file, takes the writer.
        self.writer
            .as_mut()
            .ok_or_else(|| io::Error::other("the file was already committed"))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.is_some() {
            // Not committed: a failure or an early exit leaves the old target alone.
            self.writer = None;
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

/// Refuses a target that exists and is not a regular file (a FIFO, a device, a
/// folder): the rename would replace it, and a FIFO written directly blocks until a
/// reader comes, for ever in a script or CI.
fn refuse_special(target: &Path) -> io::Result<()> {
    match std::fs::metadata(target) {
        Ok(metadata) if !metadata.is_file() => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "it is not a regular file (a FIFO, a device or a folder): gloc writes regular files only; choose another path",
        )),
        _ => Ok(()),
    }
}

/// Device and inode of the file at `path` (following symlinks), if it exists.
fn file_id(path: &Path) -> Option<(u64, u64)> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let metadata = std::fs::metadata(path).ok()?;
        Some((metadata.dev(), metadata.ino()))
    }
    #[cfg(not(unix))]
    {
        std::fs::canonicalize(path).ok().map(|_| (0, 0))
    }
}

/// Whether two output paths name the same file: the same inode when both exist, else
/// the same name in the same (canonical) folder.
fn same_target(a: &Path, b: &Path) -> bool {
    if let (Some(a), Some(b)) = (file_id(a), file_id(b)) {
        return a == b;
    }
    let place = |path: &Path| {
        let folder = match path.parent() {
            Some(folder) if !folder.as_os_str().is_empty() => folder,
            _ => Path::new("."),
        };
        Some((
            std::fs::canonicalize(folder).ok()?,
            path.file_name()?.to_owned(),
        ))
    };
    matches!((place(a), place(b)), (Some(a), Some(b)) if a == b)
}

/// `context` for an output's errors: "cannot write the log `x`", with a full disk named.
pub fn write_error(error: io::Error, what: &str, path: &Path) -> anyhow::Error {
    let hint = if error.kind() == io::ErrorKind::StorageFull {
        " (the disk is full; the previous file, if any, is left as it was)"
    } else {
        ""
    };
    // Exit code 4 (`crate::exit`): the cause is the output, whatever the I/O error.
    anyhow::Error::new(crate::exit::Unwritable(format!(
        "cannot write {what} `{}`{hint}: {error}",
        path.display()
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        gloc_testsupport::scratch_dir(&format!("output-{name}"))
    }

    #[test]
    fn an_uncommitted_file_leaves_the_target_and_no_temporary() {
        let dir = folder("drop");
        let target = dir.join("out.csv");
        std::fs::write(&target, "old\n").expect("write");
        let mut file = AtomicFile::create(&target).expect("create");
        file.write_all(b"new, but never committed\n")
            .expect("write");
        drop(file);
        assert_eq!(std::fs::read_to_string(&target).expect("read"), "old\n");
        assert_eq!(gloc_testsupport::file_names(&dir), ["out.csv"]);
        std::fs::remove_dir_all(dir).ok();
    }

    #[cfg(unix)]
    #[test]
    fn a_commit_replaces_the_target_and_keeps_its_permissions() {
        use std::os::unix::fs::PermissionsExt as _;
        let dir = folder("commit");
        let target = dir.join("out.csv");
        std::fs::write(&target, "old\n").expect("write");
        std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o640)).expect("chmod");
        write_atomically(&target, b"new\n").expect("write");
        assert_eq!(std::fs::read_to_string(&target).expect("read"), "new\n");
        let mode = std::fs::metadata(&target)
            .expect("stat")
            .permissions()
            .mode();
        assert_eq!(mode & 0o777, 0o640);
        assert_eq!(gloc_testsupport::file_names(&dir), ["out.csv"]);
        std::fs::remove_dir_all(dir).ok();
    }

    #[test]
    fn two_outputs_with_one_name_collide_before_either_exists() {
        let dir = folder("names");
        let outputs = [
            Output {
                flag: "--log",
                path: &dir.join("x.csv"),
            },
            Output {
                flag: "--plot",
                path: &dir.join(".").join("x.csv"),
            },
        ];
        let error = check_outputs(&[], &outputs).expect_err("the same file");
        assert!(
            error.to_string().contains("is also the file of --log"),
            "{error}"
        );
        std::fs::remove_dir_all(dir).ok();
    }
}
