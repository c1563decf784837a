//! Document links: the paths written in a `gloc.toml` (`masterdata`, `mission`,
//! `sensor_cache`), resolved against the file's folder as `gloc_engine::config`
//! resolves them, so a click opens the file the tools will read.

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

/// The keys of `gloc.toml` that hold paths (see `gloc_engine::config::Config`).
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_path_key_links_to_the_path_beside_the_file() {
        let text = "cycle_budget = 2000\nmasterdata = \"config/masterdata.mi\"   # list\nmission = 'missions/yo.mi'\n\n[simulator]\ndive_rate = 0.2\nsensor_cache = \"x\"\n";
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
