//! Where a mission's `.ma` files are, by the glider's file rules: the name an
//! `args_from_file` asks for, and the folders searched for it.
//!
//! The glider's file system ignores case, so `Mafiles/`, `MAFILES/` and `SURFAC10.MA`
//! are `mafiles/surfac10.ma` to it. gloc searches, in order: the folder the user named
//! (`--mafiles`, `gloc.toml`'s `mafiles`), the `mafiles` folder beside `missions/` (any
//! case), then the mission's own folder (where operators keep copies; a note says so).
//! A file found in the mission tree must be a regular file inside the tree: a link
//! out of it (to `/proc/self/environ`, say) is refused, so that a mission folder
//! cannot make gloc quote a private file. A folder the user named is trusted.

use std::collections::HashMap;
use std::io;
use std::path::{Path, PathBuf};

/// The `.ma` file an `args_from_file(enum) N` loads: the behavior's name cut to six
/// characters, then N written with at least two digits (`surface` 1 → `surfac01.ma`,
/// `goto_list` 10 → `goto_l10.ma`, `yo` 3 → `yo03.ma`). The masterdata documents
/// `mafiles/surfac<N>.ma`, `set_he<N>.ma`, `prepar<N>.ma`; TWR's training guide
/// writes `args_from_file(enum) 06 # read from mafiles/surfac06.ma`.
pub fn ma_file_name(behavior: &str, number: i64) -> String {
    let prefix: String = behavior.to_ascii_lowercase().chars().take(6).collect();
    format!("{prefix}{number:02}.ma")
}

/// How a mission reaches its files: the real disk ([`Disk`]) or anything that can
/// read a path (a closure; tests and the fuzzer serve files from memory).
pub trait MissionFiles {
    /// The text of a file (lossily decoded; regular files under the size cap).
    fn read(&mut self, path: &Path) -> io::Result<String>;

    /// The names in `folder`; `None` when this source cannot list folders (then
    /// only the exact names are tried). A folder that does not exist has no names.
    fn list(&mut self, _folder: &Path) -> Option<Vec<String>> {
        None
    }

    /// Why `path`, found inside the mission tree `tree`, must not be read: it is not
    /// a regular file, or it (or a link on the way) leads out of the tree.
    fn refuse(&mut self, _path: &Path, _tree: &Path) -> Option<String> {
        None
    }
}

impl<F: FnMut(&Path) -> io::Result<String>> MissionFiles for F {
    fn read(&mut self, path: &Path) -> io::Result<String> {
        self(path)
    }
}

/// The real file system, through `gloc_engine::files` (regular files, size capped).
#[derive(Clone, Copy, Debug, Default)]
pub struct Disk;

/// The most names read from one folder: a `mafiles` folder holds tens of files.
const MAX_FOLDER_NAMES: usize = 100_000;

impl MissionFiles for Disk {
    fn read(&mut self, path: &Path) -> io::Result<String> {
        gloc_engine::files::read_text(path, gloc_engine::files::MISSION)
    }

    fn list(&mut self, folder: &Path) -> Option<Vec<String>> {
        let Ok(entries) = std::fs::read_dir(folder) else {
            return Some(Vec::new());
        };
        Some(
            entries
                .take(MAX_FOLDER_NAMES)
                .filter_map(|entry| entry.ok()?.file_name().into_string().ok())
                .collect(),
        )
    }

    fn refuse(&mut self, path: &Path, tree: &Path) -> Option<String> {
        let real = match std::fs::canonicalize(path) {
            Ok(real) => real,
            Err(error) => return Some(error.to_string()),
        };
        let root = std::fs::canonicalize(tree).unwrap_or_else(|_| tree.to_path_buf());
        if !real.starts_with(&root) {
            return Some(format!(
                "it leads out of the mission's folders (to `{}`); gloc reads a `.ma` file \
                 found there only inside `{}`",
                real.display(),
                root.display()
            ));
        }
        match std::fs::metadata(&real) {
            Ok(metadata) if metadata.is_file() => None,
            Ok(_) => Some("it is not a regular file".to_string()),
            Err(error) => Some(error.to_string()),
        }
    }
}

/// A folder searched for `.ma` files, and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    /// The folder the user named (`--mafiles`, `gloc.toml`): trusted.
    Named,
    /// `mafiles/` beside `missions/`, as on the glider.
    Mafiles,
    /// The mission's own folder (not where the glider looks).
    BesideMission,
}

/// A `.ma` file found.
#[derive(Clone, Debug)]
pub struct Found {
    pub path: PathBuf,
    pub place: Place,
    pub text: String,
}

/// Why no `.ma` file was loaded: the folders searched, or the file found but refused
/// or unreadable.
#[derive(Clone, Debug)]
pub enum NotLoaded {
    Missing { searched: Vec<PathBuf> },
    Unreadable { path: PathBuf, reason: String },
}

/// Finds and reads `.ma` files for one mission load, reading each path once (a
/// mission that loads `surfac01.ma` from three surface behaviors reads it once).
pub struct Lookup<'a> {
    files: &'a mut dyn MissionFiles,
    /// The mission's folder (`…/missions`).
    mission_folder: PathBuf,
    /// The mission tree: the folder holding `missions/` and `mafiles/`.
    tree: PathBuf,
    named: Option<PathBuf>,
    cache: HashMap<PathBuf, Result<String, (io::ErrorKind, String)>>,
    /// Folder listings, also once per load.
    listings: HashMap<PathBuf, Option<Vec<String>>>,
}

impl<'a> Lookup<'a> {
    pub fn new(
        files: &'a mut dyn MissionFiles,
        mission: &Path,
        named: Option<&Path>,
    ) -> Lookup<'a> {
        // `./missions/x.mi` is `missions/x.mi`: paths in messages read as the user
        // would write them, and a file reached from a mission is the same path as
        // the one named on the command line.
        let folder: PathBuf = mission
            .parent()
            .map(|folder| {
                folder
                    .components()
                    .filter(|part| *part != std::path::Component::CurDir)
                    .collect()
            })
            .unwrap_or_default();
        let mission_folder = if folder.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            folder
        };
        // `missions/x.mi` → the tree `.` (so `mafiles/yo10.ma`); `x.mi` → `..`;
        // `../x.mi` → `../..`.
        let tree = if mission_folder == Path::new(".") {
            PathBuf::from("..")
        } else {
            match mission_folder.components().next_back() {
                Some(std::path::Component::Normal(_)) => match mission_folder.parent() {
                    Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
                    _ => PathBuf::from("."),
                },
                _ => mission_folder.join(".."),
            }
        };
        Lookup {
            files,
            mission_folder,
            tree,
            named: named.map(Path::to_path_buf),
            cache: HashMap::new(),
            listings: HashMap::new(),
        }
    }

    /// Reads `path` through the files, once per path.
    pub fn read(&mut self, path: &Path) -> io::Result<String> {
        if let Some(cached) = self.cache.get(path) {
            return cached
                .clone()
                .map_err(|(kind, message)| io::Error::new(kind, message));
        }
        let read = self.files.read(path);
        self.cache.insert(
            path.to_path_buf(),
            read.as_ref()
                .map(String::clone)
                .map_err(|error| (error.kind(), error.to_string())),
        );
        read
    }

    /// The names in `folder`, listed once per load.
    fn list(&mut self, folder: &Path) -> Option<Vec<String>> {
        if let Some(listed) = self.listings.get(folder) {
            return listed.clone();
        }
        let listed = self.files.list(folder);
        self.listings.insert(folder.to_path_buf(), listed.clone());
        listed
    }

    /// The `.ma` file `name` by the glider's rules (see the module's doc).
    pub fn find(&mut self, name: &str) -> Result<Found, NotLoaded> {
        let mut searched = Vec::new();
        let mut folders: Vec<(PathBuf, Place)> = Vec::new();
        if let Some(named) = &self.named {
            folders.push((named.clone(), Place::Named));
        }
        let tree = self.tree.clone();
        match self.list(&tree) {
            Some(mut names) => {
                names.sort();
                // `mafiles` itself first, then other spellings in a stable order.
                names.sort_by_key(|folder| folder != "mafiles");
                folders.extend(
                    names
                        .into_iter()
                        .filter(|folder| folder.eq_ignore_ascii_case("mafiles"))
                        .map(|folder| (join(&self.tree, &folder), Place::Mafiles)),
                );
            }
            None => folders.push((join(&self.tree, "mafiles"), Place::Mafiles)),
        }
        if !folders.iter().any(|(_, place)| *place == Place::Mafiles) {
            // Nothing of that name: the message still names where the glider looks.
            searched.push(join(&self.tree, "mafiles"));
        }
        folders.push((self.mission_folder.clone(), Place::BesideMission));
        for (folder, place) in folders {
            searched.push(folder.clone());
            let candidates = match self.list(&folder) {
                Some(mut names) => {
                    names.sort();
                    names.sort_by_key(|file| file != name);
                    names
                        .into_iter()
                        .filter(|file| file.eq_ignore_ascii_case(name))
                        .map(|file| join(&folder, &file))
                        .collect()
                }
                None => vec![join(&folder, name)],
            };
            for path in candidates {
                if place != Place::Named {
                    if let Some(reason) = self.files.refuse(&path, &self.tree) {
                        return Err(NotLoaded::Unreadable { path, reason });
                    }
                }
                match self.read(&path) {
                    Ok(text) => return Ok(Found { path, place, text }),
                    Err(error) if error.kind() == io::ErrorKind::NotFound => continue,
                    Err(error) => {
                        return Err(NotLoaded::Unreadable {
                            path,
                            reason: error.to_string(),
                        })
                    }
                }
            }
        }
        searched.dedup();
        Err(NotLoaded::Missing { searched })
    }
}

/// `folder/name`, without a leading `./` (`mafiles/yo10.ma`, not `./mafiles/yo10.ma`).
fn join(folder: &Path, name: &str) -> PathBuf {
    if folder == Path::new(".") {
        PathBuf::from(name)
    } else {
        folder.join(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The folders `find` searches for a mission at `mission`, as it names them.
    fn searched(mission: &str) -> Vec<PathBuf> {
        let mut nothing = |_: &Path| -> io::Result<String> { Err(io::ErrorKind::NotFound.into()) };
        match Lookup::new(&mut nothing, Path::new(mission), None).find("yo10.ma") {
            Err(NotLoaded::Missing { searched }) => searched,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn folders_are_named_as_a_user_writes_them() {
        // `mafiles` beside `missions`, then the mission's folder.
        for (mission, folders) in [
            ("missions/x.mi", ["mafiles", "missions"]),
            ("./missions/x.mi", ["mafiles", "missions"]),
            ("x.mi", ["../mafiles", "."]),
            ("./x.mi", ["../mafiles", "."]),
            (
                "/g/comet/missions/x.mi",
                ["/g/comet/mafiles", "/g/comet/missions"],
            ),
            ("../x.mi", ["../../mafiles", ".."]),
        ] {
            assert_eq!(searched(mission), folders.map(PathBuf::from), "{mission}");
        }
    }

    #[test]
    fn names_are_six_characters_and_two_digits() {
        // Hand-worked from the masterdata's `mafiles/surfac<N>.ma` and TWR's
        // `args_from_file(enum) 06 # read from mafiles/surfac06.ma`.
        assert_eq!(ma_file_name("surface", 1), "surfac01.ma");
        assert_eq!(ma_file_name("surface", 6), "surfac06.ma");
        assert_eq!(ma_file_name("goto_list", 10), "goto_l10.ma");
        assert_eq!(ma_file_name("yo", 10), "yo10.ma");
        assert_eq!(ma_file_name("yo", 3), "yo03.ma");
        assert_eq!(ma_file_name("Set_Heading", 5), "set_he05.ma");
        assert_eq!(ma_file_name("drift_at_depth", 10), "drift_10.ma");
        assert_eq!(ma_file_name("prepare_to_dive", 0), "prepar00.ma");
        assert_eq!(ma_file_name("sample", 123), "sample123.ma");
    }
}
