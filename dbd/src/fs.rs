//! The file system, in one place: a log's kind from its extension, opening a
//! path, and the sensor-list cache search (`<crc>.cac` / `<crc>.ccc`).

use std::path::{Path, PathBuf};

use crate::dba::DbaReader;
use crate::error::{DbdError, Location};
use crate::lists::{SensorListText, SensorLists};
use crate::lz4::decompress_all;
use crate::{CycleSource, DbdReader};

/// What a file is, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LogKind {
    /// `.dbd .ebd .sbd .tbd .mbd .nbd`, or compressed `.dcd .ecd .scd .tcd .mcd .ncd`.
    Binary {
        /// The letter of the plain extension: `d e s t m n`.
        letter: u8,
        compressed: bool,
    },
    /// `.dba`: dbd2asc's output, or gloc's own.
    Ascii,
}

impl LogKind {
    /// The extensions gloc reads, for messages.
    pub const EXTENSIONS: &'static str =
        ".dbd .ebd .sbd .tbd .mbd .nbd, compressed .dcd .ecd .scd .tcd .mcd .ncd, and .dba";

    pub fn from_path(path: &Path) -> Option<LogKind> {
        let extension = gloc_engine::files::extension(path)?;
        if extension == "dba" {
            return Some(LogKind::Ascii);
        }
        let bytes = extension.as_bytes();
        match bytes {
            [letter @ (b'd' | b'e' | b's' | b't' | b'm' | b'n'), middle @ (b'b' | b'c'), b'd'] => {
                Some(LogKind::Binary {
                    letter: *letter,
                    compressed: *middle == b'c',
                })
            }
            _ => None,
        }
    }

    /// A science computer's log (`.ebd .tbd .nbd` and compressed forms).
    pub fn is_science(self) -> bool {
        matches!(
            self,
            LogKind::Binary {
                letter: b'e' | b't' | b'n',
                ..
            }
        )
    }
}

/// Folders searched, in order, for a factored-out sensor list.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CacheFolders {
    pub folders: Vec<PathBuf>,
}

/// Largest sensor-list file read (a real `.cac` is about 100 KB).
const MAX_LIST_FILE: u64 = 16 * 1024 * 1024;

impl CacheFolders {
    /// The standard search for `file`: the configured folder (`--sensor-cache`
    /// or `sensor_cache` in gloc.toml) if any, then the file's own folder, then
    /// the per-user folder ([`CacheFolders::user_folder`]).
    pub fn standard(configured: Option<&Path>, file: &Path) -> CacheFolders {
        let mut folders = Vec::new();
        folders.extend(configured.map(Path::to_path_buf));
        let beside = match file.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        folders.push(beside);
        folders.extend(CacheFolders::user_folder());
        folders.dedup();
        CacheFolders { folders }
    }

    /// `$XDG_DATA_HOME/gloc/cac`, else `$HOME/.local/share/gloc/cac`.
    pub fn user_folder() -> Option<PathBuf> {
        let data = std::env::var_os("XDG_DATA_HOME")
            .filter(|value| !value.is_empty())
            .map(PathBuf::from)
            .or_else(|| {
                std::env::var_os("HOME")
                    .filter(|value| !value.is_empty())
                    .map(|home| PathBuf::from(home).join(".local").join("share"))
            })?;
        Some(data.join("gloc").join("cac"))
    }
}

impl SensorLists for CacheFolders {
    fn find(&self, crc: &str) -> Result<SensorListText, String> {
        let upper = crc.to_ascii_uppercase();
        for folder in &self.folders {
            for (name, compressed) in [
                (format!("{crc}.cac"), false),
                (format!("{upper}.CAC"), false),
                (format!("{crc}.ccc"), true),
                (format!("{upper}.CCC"), true),
            ] {
                let path = folder.join(&name);
                let Ok(metadata) = std::fs::metadata(&path) else {
                    continue;
                };
                let shown = path.display().to_string();
                if metadata.len() > MAX_LIST_FILE {
                    return Err(format!(
                        "{shown} is {} bytes: too large for a sensor list",
                        metadata.len()
                    ));
                }
                let bytes = gloc_engine::files::read(&path, gloc_engine::files::SENSOR_LIST)
                    .map_err(|error| format!("{shown}: {error}"))?;
                let bytes = if compressed {
                    decompress_all(&bytes, gloc_engine::files::SENSOR_LIST.bytes).map_err(
                        |problem| {
                            format!("{shown}: file byte {}: {}", problem.block, problem.message)
                        },
                    )?
                } else {
                    bytes
                };
                return Ok(SensorListText {
                    text: String::from_utf8_lossy(&bytes).into_owned(),
                    origin: shown,
                });
            }
        }
        let searched: Vec<String> = self
            .folders
            .iter()
            .map(|folder| folder.display().to_string())
            .collect();
        Err(format!(
            "looked for {crc}.cac and {crc}.ccc in {}",
            if searched.is_empty() {
                "no folder".to_string()
            } else {
                searched.join(", ")
            }
        ))
    }
}

/// Opens a log by its extension, with the standard cache search
/// ([`CacheFolders::standard`]) for its sensor list.
pub fn open_path(
    path: &Path,
    sensor_cache: Option<&Path>,
) -> Result<Box<dyn CycleSource>, DbdError> {
    open_path_with(path, &CacheFolders::standard(sensor_cache, path))
}

/// Opens a log by its extension, finding a factored-out sensor list in `lists`.
pub fn open_path_with(
    path: &Path,
    lists: &dyn SensorLists,
) -> Result<Box<dyn CycleSource>, DbdError> {
    let name = path.display().to_string();
    let kind = LogKind::from_path(path);
    let file = gloc_engine::files::open_regular(path).map_err(|error| {
        DbdError::unreadable(&name, Location::default(), format!("cannot open: {error}"))
    })?;
    match kind {
        Some(LogKind::Binary { compressed, .. }) => {
            Ok(Box::new(DbdReader::new(file, &name, compressed, lists)?))
        }
        Some(LogKind::Ascii) => Ok(Box::new(DbaReader::new(file, &name)?)),
        None => {
            let mut start = [0u8; 10];
            let got = crate::lz4::read_full(&mut &file, &mut start).unwrap_or(0);
            let looks = if &start[..got] == b"dbd_label:" {
                " It opens like a Slocum log: give it its glider extension (.dbd, .ebd, …, or .dba)."
            } else {
                ""
            };
            Err(DbdError::new(
                &name,
                Location::default(),
                format!(
                    "not a glider log by its extension; gloc reads {}.{looks}",
                    LogKind::EXTENSIONS
                ),
            ))
        }
    }
}

/// The header of a log (plain, compressed or `.dba`), without its sensor list.
pub fn read_file_header(path: &Path) -> Result<crate::Header, DbdError> {
    let name = path.display().to_string();
    let file = gloc_engine::files::open_regular(path).map_err(|error| {
        DbdError::unreadable(&name, Location::default(), format!("cannot open: {error}"))
    })?;
    let compressed = matches!(
        LogKind::from_path(path),
        Some(LogKind::Binary {
            compressed: true,
            ..
        })
    );
    let source: Box<dyn std::io::Read> = if compressed {
        Box::new(crate::lz4::Lz4Blocks::new(file))
    } else {
        Box::new(file)
    };
    let mut input = std::io::BufReader::new(source);
    let mut offset = 0;
    crate::header::read_header(&mut input, &mut offset, &name, |offset| Location {
        offset,
        block: None,
    })
}
