//! The glider's file rules on real folders: the `args_from_file` name, case-insensitive
//! `mafiles/`, a `.ma` beside the `.mi`, `--mafiles`, links out of the tree refused, each
//! `.ma` read once per load, and a `.ma` value flown over the `.mi`'s.

use std::collections::HashMap;
use std::io;
use std::path::{Path, PathBuf};

use gloc_mission::{Disk, LoadOptions, Mission, MissionFiles};

/// A fresh folder `<temp>/gloc-mission-<name>-<pid>` holding `files`.
fn tree(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let root = std::env::temp_dir().join(format!("gloc-mission-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    for (path, text) in files {
        let path = root.join(path);
        std::fs::create_dir_all(path.parent().expect("a parent")).expect("mkdir");
        std::fs::write(&path, text).expect("write");
    }
    root
}

const SURFACE_MA: &str =
    "behavior_name=surface\n<start:b_arg>\n  b_arg: gps_wait_time(s) 123\n<end:b_arg>\n";

#[test]
fn args_from_file_01_reads_surfac01() {
    // `surface` cut to six characters is `surfac`, and 01 is two digits: the glider
    // opens `surfac01.ma`. A `surface1.ma` beside it must not be read.
    let root = tree(
        "surfac01",
        &[
            (
                "missions/m.mi",
                "behavior: surface\n  b_arg: args_from_file(enum) 01\n",
            ),
            ("mafiles/surfac01.ma", SURFACE_MA),
            ("mafiles/surface1.ma", "not read\n"),
        ],
    );
    let mission = Mission::load(&root.join("missions/m.mi"));
    assert_eq!(mission.rendered(), Vec::<String>::new());
    assert!(mission.sources[1].path.ends_with("mafiles/surfac01.ma"));
    assert_eq!(mission.behaviors[0].arg("gps_wait_time"), Some(123.0));
}

#[test]
fn mafiles_folder_and_file_names_ignore_case() {
    let root = tree(
        "case",
        &[
            (
                "missions/m.mi",
                "behavior: surface\n  b_arg: args_from_file(enum) 10\n",
            ),
            ("Mafiles/SURFAC10.MA", SURFACE_MA),
        ],
    );
    let mission = Mission::load(&root.join("missions/m.mi"));
    assert_eq!(mission.rendered(), Vec::<String>::new());
    assert!(mission.sources[1].path.ends_with("Mafiles/SURFAC10.MA"));
    assert_eq!(mission.behaviors[0].arg("gps_wait_time"), Some(123.0));
}

#[test]
fn a_ma_beside_the_mission_is_read_with_a_note() {
    let root = tree(
        "beside",
        &[
            (
                "missions/m.mi",
                "behavior: surface\n  b_arg: args_from_file(enum) 10\n",
            ),
            ("missions/surfac10.ma", SURFACE_MA),
        ],
    );
    let mission = Mission::load(&root.join("missions/m.mi"));
    let messages = mission.rendered();
    assert_eq!(messages.len(), 1, "{messages:?}");
    // The note sits on `b_arg: args_from_file(enum) 10`: line 2, column 3.
    assert!(
        messages[0].contains("m.mi:2:3: note[S0108]")
            && messages[0].contains("missions/surfac10.ma"),
        "{}",
        messages[0]
    );
    assert!(!mission.has_errors());
    assert_eq!(mission.behaviors[0].arg("gps_wait_time"), Some(123.0));
}

#[test]
fn mafiles_beats_the_mission_folder_and_a_named_folder_beats_both() {
    let other = tree(
        "named-elsewhere",
        &[(
            "args/surfac10.ma",
            "behavior_name=surface\n<start:b_arg>\n b_arg: gps_wait_time(s) 7\n<end:b_arg>\n",
        )],
    );
    let root = tree(
        "order",
        &[
            (
                "missions/m.mi",
                "behavior: surface\n  b_arg: args_from_file(enum) 10\n",
            ),
            ("mafiles/surfac10.ma", SURFACE_MA),
            (
                "missions/surfac10.ma",
                "behavior_name=surface\n<start:b_arg>\n b_arg: gps_wait_time(s) 1\n<end:b_arg>\n",
            ),
        ],
    );
    let mission = Mission::load(&root.join("missions/m.mi"));
    assert_eq!(mission.rendered(), Vec::<String>::new());
    assert_eq!(mission.behaviors[0].arg("gps_wait_time"), Some(123.0));
    let named = Mission::load_with_options(
        &root.join("missions/m.mi"),
        &LoadOptions {
            mafiles: Some(other.join("args")),
            ..LoadOptions::default()
        },
        &mut Disk,
    );
    assert_eq!(named.rendered(), Vec::<String>::new());
    assert_eq!(named.behaviors[0].arg("gps_wait_time"), Some(7.0));
}

#[test]
fn a_missing_ma_names_the_folders_searched() {
    let root = tree(
        "missing",
        &[(
            "missions/m.mi",
            "behavior: yo\n  b_arg: args_from_file(enum) 4\n",
        )],
    );
    let mission = Mission::load(&root.join("missions/m.mi"));
    let messages = mission.rendered();
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!(
        messages[0].contains("m.mi:2:3: error[S0004]: cannot find mission argument file `yo04.ma`"),
        "{}",
        messages[0]
    );
    assert!(messages[0].contains("mafiles"), "{}", messages[0]);
}

#[cfg(unix)]
#[test]
fn a_link_out_of_the_tree_is_refused_unless_the_folder_was_named() {
    let secret = tree("secret", &[("private.txt", "SECRET=1\n")]);
    let root = tree(
        "link",
        &[(
            "missions/m.mi",
            "behavior: surface\n  b_arg: args_from_file(enum) 10\n",
        )],
    );
    std::fs::create_dir_all(root.join("mafiles")).expect("mkdir");
    std::os::unix::fs::symlink(secret.join("private.txt"), root.join("mafiles/surfac10.ma"))
        .expect("symlink");
    let mission = Mission::load(&root.join("missions/m.mi"));
    let messages = mission.rendered().join("\n");
    assert!(messages.contains("error[S0004]"), "{messages}");
    assert!(
        messages.contains("leads out of the mission's folders"),
        "{messages}"
    );
    assert!(!messages.contains("SECRET"), "{messages}");
    assert_eq!(mission.sources.len(), 1, "nothing else was read");

    // `/proc/self/environ` through a link: refused the same way.
    let proc_root = tree(
        "proc",
        &[(
            "missions/m.mi",
            "behavior: surface\n  b_arg: args_from_file(enum) 10\n",
        )],
    );
    std::fs::create_dir_all(proc_root.join("mafiles")).expect("mkdir");
    std::os::unix::fs::symlink("/proc/self/environ", proc_root.join("mafiles/surfac10.ma"))
        .expect("symlink");
    let mission = Mission::load(&proc_root.join("missions/m.mi"));
    assert!(mission.has_errors());
    assert_eq!(mission.sources.len(), 1, "nothing else was read");

    // The user named the folder: it is trusted.
    let named = Mission::load_with_options(
        &root.join("missions/m.mi"),
        &LoadOptions {
            mafiles: Some(root.join("mafiles")),
            ..LoadOptions::default()
        },
        &mut Disk,
    );
    assert_eq!(named.sources.len(), 2);
}

/// The disk, counting reads per path.
#[derive(Default)]
struct Counting {
    reads: HashMap<PathBuf, usize>,
}

impl MissionFiles for Counting {
    fn read(&mut self, path: &Path) -> io::Result<String> {
        *self.reads.entry(path.to_path_buf()).or_default() += 1;
        Disk.read(path)
    }
    fn list(&mut self, folder: &Path) -> Option<Vec<String>> {
        Disk.list(folder)
    }
    fn refuse(&mut self, path: &Path, tree: &Path) -> Option<String> {
        Disk.refuse(path, tree)
    }
}

#[test]
fn each_ma_is_read_once_per_load() {
    let mission_text = "behavior: surface\n  b_arg: args_from_file(enum) 1\n\
                        behavior: surface\n  b_arg: args_from_file(enum) 1\n\
                        behavior: surface\n  b_arg: args_from_file(enum) 1\n";
    let root = tree(
        "once",
        &[
            ("missions/m.mi", mission_text),
            ("mafiles/surfac01.ma", SURFACE_MA),
        ],
    );
    let mut files = Counting::default();
    let mission = Mission::load_with_options(
        &root.join("missions/m.mi"),
        &LoadOptions::default(),
        &mut files,
    );
    assert_eq!(mission.rendered(), Vec::<String>::new());
    assert_eq!(mission.behaviors.len(), 3);
    assert!(mission
        .behaviors
        .iter()
        .all(|spec| spec.arg("gps_wait_time") == Some(123.0)));
    let ma_reads: Vec<usize> = files
        .reads
        .iter()
        .filter(|(path, _)| path.ends_with("surfac01.ma"))
        .map(|(_, count)| *count)
        .collect();
    assert_eq!(ma_reads, vec![1]);
}

#[test]
fn a_ma_value_is_flown_over_the_mi_value_with_a_warning() {
    // The `.mi` sets gps_wait_time 60 after args_from_file; the `.ma` sets 123.
    let root = tree(
        "override",
        &[
            (
                "missions/m.mi",
                "behavior: surface\n  b_arg: args_from_file(enum) 10\n  b_arg: gps_wait_time(s) 60\n",
            ),
            ("mafiles/surfac10.ma", SURFACE_MA),
        ],
    );
    let mission = Mission::load(&root.join("missions/m.mi"));
    let messages = mission.rendered();
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!(
        messages[0].contains("m.mi:3:3: warning[S0109]")
            && messages[0].contains("`surfac10.ma` (line 3)")
            && messages[0].contains("the `.ma` value 123, not 60"),
        "{}",
        messages[0]
    );
    assert_eq!(mission.behaviors[0].arg("gps_wait_time"), Some(123.0));
}
