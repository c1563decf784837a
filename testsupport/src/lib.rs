//! What the tests of every crate share: the real glider files kept in the repository's
//! `data/` folder (found by one locator that fails loudly), paths in the repository, and
//! one seeded random-number generator for property tests.
//!
//! A test that needs a real file calls [`data`]; a missing file is a failure that names
//! the path, never a silent skip.

use std::path::{Path, PathBuf};

/// The repository's root folder (the workspace, one level above this crate).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")))
}

/// A path in the repository, `relative` to its root (not checked).
pub fn repo(relative: &str) -> PathBuf {
    repo_root().join(relative)
}

/// A real glider file or folder in the repository's `data/` (see `data/README.md` for
/// where each came from). Panics, naming the path, when it is missing: the files are part
/// of the repository, so a missing one is a broken checkout, not a reason to skip.
pub fn data(relative: &str) -> PathBuf {
    let path = repo_root().join("data").join(relative);
    if !path.exists() {
        panic!(
            "the real glider file {} is missing: it belongs to the repository (data/README.md); \
             restore it with `git checkout -- data`",
            path.display()
        );
    }
    path
}

/// [`data`] as a display string, for command lines.
pub fn data_arg(relative: &str) -> String {
    data(relative).display().to_string()
}

/// A small seeded generator (SplitMix64) for property tests: the same seed gives the same
/// sequence on every machine. Not for the simulator, whose noise has its own generator.
#[derive(Debug, Clone)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `0..bound` (`bound` > 0).
    pub fn below(&mut self, bound: u64) -> u64 {
        self.next_u64() % bound.max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_data_folder_is_found_and_a_missing_file_fails_loudly() {
        assert!(data("comet/missions/nsb3.mi").is_file());
        let missing = std::panic::catch_unwind(|| data("no/such/file.dbd"));
        assert!(missing.is_err());
    }

    #[test]
    fn splitmix64_matches_its_published_first_value() {
        // SplitMix64 seeded with 0: first output 0xE220A8397B1DCDAF (Vigna's reference).
        assert_eq!(Rng::new(0).next_u64(), 0xE220_A839_7B1D_CDAF);
    }
}
