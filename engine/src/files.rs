//! The one way gloc reads an input file (script, masterdata, mission, profile, replay,
//! `gloc.toml`): only a regular file, its size checked against a cap before a byte is
//! read, so `/dev/zero` or a FIFO is a clear error, not a hang or exhausted memory.

use std::fs::{File, Metadata};
use std::io::{self, Read};
use std::path::Path;

/// A file's extension in lower case (`None` without one, or when it is not UTF-8): the
/// one way gloc tells how to read or write a file by its name, in any case, as the
/// glider's own names come (`01340000.DBD`, `LAYER.MI`).
pub fn extension(path: &Path) -> Option<String> {
    Some(path.extension()?.to_str()?.to_ascii_lowercase())
}

/// What a file is read as, and the most bytes it may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limit {
    /// For messages: "a script", "a masterdata file", …
    pub what: &'static str,
    pub bytes: u64,
}

impl Limit {
    /// Reading as `what`, at most `bytes` bytes.
    pub const fn new(what: &'static str, bytes: u64) -> Limit {
        Limit { what, bytes }
    }
}

/// A GLOC or GBASIC script: the same 16 MB as E0013 (`gloc::MAX_SOURCE_BYTES`).
pub const SCRIPT: Limit = Limit::new("a script", crate::gloc::MAX_SOURCE_BYTES as u64);
/// A masterdata or `.cac` sensor list (a real one is under 1 MB).
pub const SENSOR_LIST: Limit = Limit::new("a sensor list", 16 << 20);
/// A mission `.mi` or `.ma` file (a real one is a few KB).
pub const MISSION: Limit = Limit::new("a mission file", 16 << 20);
/// A temperature profile CSV.
pub const PROFILE: Limit = Limit::new("a temperature profile", 16 << 20);
/// A recorded-sensor CSV for `gloc run --replay` (a month of 4 s rows with 20 columns
/// is about 150 MB).
pub const REPLAY: Limit = Limit::new("a replay CSV", 256 << 20);
/// `gloc.toml`.
pub const CONFIG: Limit = Limit::new("gloc.toml", 1 << 20);

/// Reads the whole of a regular file of at most `limit.bytes` bytes. A directory, FIFO,
/// socket or device is refused before it is opened, and the size is checked before
/// reading; the error (kind `InvalidInput` or `FileTooLarge`) says why without the path,
/// for the caller's "cannot read X `path`: …".
pub fn read(path: &Path, limit: Limit) -> io::Result<Vec<u8>> {
    check(&std::fs::metadata(path)?, limit)?;
    let file = open(path)?;
    // The path may have been replaced since the first look: check what was opened.
    let metadata = file.metadata()?;
    check(&metadata, limit)?;
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(limit.bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit.bytes {
        return Err(too_large(bytes.len() as u64, limit));
    }
    Ok(bytes)
}

/// Opens a regular file for streaming (a glider log read cycle by cycle, in memory that
/// does not grow with its length), so no size cap; a directory, FIFO, socket or device
/// is refused as [`read`] refuses it.
pub fn open_regular(path: &Path) -> io::Result<File> {
    let unlimited = Limit::new("a file", u64::MAX);
    check(&std::fs::metadata(path)?, unlimited)?;
    let file = open(path)?;
    check(&file.metadata()?, unlimited)?;
    Ok(file)
}

/// [`read`], decoded as UTF-8 with invalid sequences replaced (U+FFFD).
pub fn read_text(path: &Path, limit: Limit) -> io::Result<String> {
    let bytes = read(path, limit)?;
    Ok(match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(error) => String::from_utf8_lossy(error.as_bytes()).into_owned(),
    })
}

fn check(metadata: &Metadata, limit: Limit) -> io::Result<()> {
    if !metadata.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "it is {}, not a regular file (gloc reads only regular files)",
                kind_of(metadata)
            ),
        ));
    }
    if metadata.len() > limit.bytes {
        return Err(too_large(metadata.len(), limit));
    }
    Ok(())
}

fn too_large(size: u64, limit: Limit) -> io::Error {
    io::Error::new(
        io::ErrorKind::FileTooLarge,
        format!(
            "it is {size} bytes, over the limit of {} for {} (not read)",
            in_words(limit.bytes),
            limit.what
        ),
    )
}

/// `16 MB` for a whole number of megabytes, else `N bytes`.
fn in_words(bytes: u64) -> String {
    if bytes >= 1 << 20 && bytes.is_multiple_of(1 << 20) {
        format!("{} MB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

#[cfg(unix)]
fn open(path: &Path) -> io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt as _;
    // Non-blocking, so that a FIFO put in the file's place after the first look
    // cannot block the open (the check after it then refuses it).
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open(path: &Path) -> io::Result<File> {
    File::open(path)
}

fn kind_of(metadata: &Metadata) -> &'static str {
    let file_type = metadata.file_type();
    if file_type.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "not a plain file"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_extension_is_read_in_any_case() {
        assert_eq!(
            extension(Path::new("logs/01340000.DBD")).as_deref(),
            Some("dbd")
        );
        assert_eq!(extension(Path::new("LAYER.Mi")).as_deref(), Some("mi"));
        assert_eq!(extension(Path::new("folder.d/masterdata")), None);
        assert_eq!(extension(Path::new(".hidden")), None);
    }

    #[test]
    fn devices_and_fifos_are_refused_unread_and_sizes_are_capped() {
        let error = read(Path::new("/dev/zero"), SCRIPT).expect_err("a device");
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        assert!(error.to_string().contains("a character device"), "{error}");
        let folder = std::env::temp_dir().join(format!("gloc-files-{}", std::process::id()));
        std::fs::create_dir_all(&folder).expect("a folder");
        let error = read(&folder, SCRIPT).expect_err("a directory");
        assert!(error.to_string().contains("a directory"), "{error}");
        let small = Limit::new("a test file", 4);
        let path = folder.join("five");
        std::fs::write(&path, "12345").expect("write");
        let error = read(&path, small).expect_err("too large");
        assert_eq!(error.kind(), io::ErrorKind::FileTooLarge);
        assert_eq!(
            error.to_string(),
            "it is 5 bytes, over the limit of 4 bytes for a test file (not read)"
        );
        std::fs::write(&path, "1234").expect("write");
        assert_eq!(read(&path, small).expect("four bytes"), b"1234");
        std::fs::remove_dir_all(&folder).expect("clean up");
    }
}
