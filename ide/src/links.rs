//! Document links: the paths written in a `gloc.toml` (`masterdata`, `mission`,
//! `sensor_cache`), resolved against the file's folder as `gloc_project::config`
//! resolves them, and in a mission each `args_from_file` line to the `.ma` file
//! the simulator's parser loads for it, so a click opens the file the tools read.

use std::path::{Path, PathBuf};

use gloc_engine::Span;
use serde::Deserialize;
use toml::Spanned;

/// A link: where it is written (the text between the quotes) and what it opens.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Link {
    pub span: Span,
    pub target: PathBuf,
    /// What the path is, for the tooltip (`masterdata`, …).
    pub key: &'static str,
}

/// The keys of `gloc.toml` that hold paths (see `gloc_project::config::Config`).
#[derive(Deserialize)]
struct PathKeys {
    masterdata: Option<Spanned<String>>,
    mission: Option<Spanned<String>>,
    sensor_cache: Option<Spanned<String>>,
}

/// The path links of a `gloc.toml` in `folder`; none when the file does not
/// parse (its diagnostics say why).
pub fn config_links(text: &str, folder: &Path) -> Vec<Link> {
    let Ok(keys) = toml::from_str::<PathKeys>(text) else {
        return Vec::new();
    };
    let mut links = Vec::new();
    for (key, value) in [
        ("masterdata", keys.masterdata),
        ("mission", keys.mission),
        ("sensor_cache", keys.sensor_cache),
    ] {
        let Some(value) = value else { continue };
        let span = value.span();
        // The span covers the quotes; the link covers the path between them.
        let written = text.get(span.clone()).unwrap_or_default();
        let quoted = written.len() >= 2
            && (written.starts_with('"') || written.starts_with('\''))
            && written.ends_with(&written[..1]);
        let span = if quoted {
            Span::new(span.start + 1, span.end - 1)
        } else {
            Span::new(span.start, span.end)
        };
        let value = value.into_inner();
        if value.trim().is_empty() {
            continue;
        }
        links.push(Link {
            span,
            target: folder.join(value),
            key,
        });
    }
    links.sort_by_key(|link| link.span.start);
    links
}

/// The `args_from_file` lines of a mission at `path`, each to the `.ma` file it
/// loads (`gloc_mission::mission` decides which, as `gloc run` does, with the
/// context's `mafiles` and sensor list; a file it could not load has a diagnostic
/// instead of a link).
pub fn mission_links(text: &str, path: &Path, context: &crate::analysis::Context) -> Vec<Link> {
    crate::mission::links(text, path, context)
        .into_iter()
        .map(|(span, target)| Link {
            span,
            target,
            key: "args_from_file",
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use gloc_engine::sensors::SensorList;

    use super::*;
    use crate::analysis::Context;

    #[test]
    fn each_loaded_args_from_file_line_links_to_its_ma_file() {
        let root = gloc_testsupport::scratch_dir("ide-links");
        std::fs::create_dir_all(root.join("missions")).expect("folder");
        std::fs::create_dir_all(root.join("mafiles")).expect("folder");
        // `surface` cut to six characters and 10 in two digits is `surfac10`;
        // `yo` 99 is not there, so it gets a diagnostic (S0110) and no link.
        std::fs::write(
            root.join("mafiles/surfac10.ma"),
            "behavior_name=surface\n<start:b_arg>\n<end:b_arg>\n",
        )
        .expect("ma");
        let text = "behavior: surface\n  b_arg: args_from_file(enum) 10\nbehavior: yo\n  b_arg: args_from_file(enum) 99\n";
        let path = root.join("missions/m.mi");
        let embedded = Context::new(Arc::new(SensorList::embedded()));
        // The `index`th link: on the line loading `number`, to `ma` under the folder.
        let link_goes = |links: &[Link], index: usize, number: &str, ma: &str| {
            let link = &links[index];
            let loads = format!("args_from_file(enum) {number}");
            assert!(text[link.span.range()].contains(&loads), "{link:?}");
            let target = std::fs::canonicalize(root.join(ma)).expect("exists");
            assert_eq!(link.target, target);
        };
        let links = mission_links(text, &path, &embedded);
        assert_eq!(links.len(), 1, "{links:?}");
        link_goes(&links, 0, "10", "mafiles/surfac10.ma");
        // With gloc.toml's `mafiles` naming a folder that holds `yo99.ma` (`yo` and
        // 99), that line links there too, as `gloc run` would load it.
        std::fs::create_dir_all(root.join("elsewhere")).expect("folder");
        std::fs::write(
            root.join("elsewhere/yo99.ma"),
            "behavior_name=yo\n<start:b_arg>\n<end:b_arg>\n",
        )
        .expect("ma");
        let project = Context {
            mafiles: Some(root.join("elsewhere")),
            ..embedded
        };
        let links = mission_links(text, &path, &project);
        assert_eq!(links.len(), 2, "{links:?}");
        link_goes(&links, 1, "99", "elsewhere/yo99.ma");
        std::fs::remove_dir_all(&root).expect("clean up");
    }

    #[test]
    fn every_path_key_links_to_the_path_beside_the_file() {
        let text = "cycle_budget = 2000\nmasterdata = \"config/masterdata.mi\"   # list\nmission = 'missions/yo.mi'\n\n[simulator]\ndrag_cd0 = 0.2\nsensor_cache = \"x\"\n";
        let links = config_links(text, Path::new("/project"));
        // `sensor_cache` under [simulator] is not the top-level key.
        assert_eq!(links.len(), 2, "{links:?}");
        assert_eq!(&text[links[0].span.range()], "config/masterdata.mi");
        assert_eq!(links[0].target, Path::new("/project/config/masterdata.mi"));
        assert_eq!(links[0].key, "masterdata");
        assert_eq!(&text[links[1].span.range()], "missions/yo.mi");
        assert_eq!(links[1].target, Path::new("/project/missions/yo.mi"));
    }

    #[test]
    fn a_broken_file_has_no_links() {
        assert!(config_links("masterdata = \"unterminated\n", Path::new("/p")).is_empty());
        assert!(config_links("", Path::new("/p")).is_empty());
    }
}
