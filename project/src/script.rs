//! A script of either language loaded into program and source map (through
//! `gloc_compiler::loader`), with the settings' budget and the sensor list a GLOC
//! file's `# sensors:` line names; and the hint when a file is in the other language.

use std::path::{Path, PathBuf};

use gloc_compiler::loader::load_script_written_for;
use gloc_compiler::{Language, LoadOptions, LoadedScript, Optimization};
use gloc_engine::sensors::SensorList;

use crate::error::{ErrorKind, ProjectError};
use crate::settings::Settings;

/// A loaded script: its text and what the loader made of it.
#[derive(Clone, Debug)]
pub struct Script {
    /// The file, `None` for a script given as text (the embedded Fig. 2 script).
    pub path: Option<PathBuf>,
    /// How to name the script in messages.
    pub display: String,
    pub text: String,
    pub language: Language,
    pub loaded: LoadedScript,
    /// When the script has errors and reads as the other language: what to do.
    pub hint: Option<String>,
    /// The file holds nothing but blanks and comments: it loads (as GBASIC) but does
    /// nothing, which is worth a warning, never a silent pass.
    pub empty: bool,
}

/// Reads a script file; an unreadable file is an error of kind `Unreadable`, and
/// a file of another kind given as the script (a glider log, a mission, a sensor
/// list, binary data) one of kind `Setting`, naming the option it belongs to,
/// before any of it is parsed (a `.dbd` read as GLOC gave 5,010 errors).
pub fn read_script(path: &Path) -> Result<String, ProjectError> {
    if let Some(hint) = not_a_script(path) {
        return Err(ProjectError::new(
            ErrorKind::Setting,
            None,
            format!("`{}` is {hint}", path.display()),
        ));
    }
    let bytes = gloc_engine::files::read(path, gloc_engine::files::SCRIPT).map_err(|error| {
        ProjectError::new(
            ErrorKind::Unreadable,
            None,
            format!("cannot read the script `{}`: {error}", path.display()),
        )
    })?;
    // A NUL byte near the start is binary data (git's and grep's test); text in a
    // legacy encoding is read, its stray bytes as U+FFFD.
    if bytes.iter().take(8192).any(|&byte| byte == 0) {
        return Err(ProjectError::new(
            ErrorKind::Setting,
            None,
            format!(
                "`{}` is binary data, not a script: a script is a text file (`.gloc` or `.gbas`)",
                path.display()
            ),
        ));
    }
    Ok(match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(error) => String::from_utf8_lossy(error.as_bytes()).into_owned(),
    })
}

/// What a file given as the script is instead, by its extension, and where it goes.
fn not_a_script(path: &Path) -> Option<String> {
    if gloc_dbd::LogKind::from_path(path).is_some() {
        return Some(
            "a glider log, not a script: replay a script over it with \
             `gloc run SCRIPT --replay LOG…` (or read it with `gloc data info`)"
                .to_string(),
        );
    }
    let extension = gloc_engine::files::extension(path)?;
    let hint = match extension.as_str() {
        "mi" => {
            "a mission file, not a script: fly a script in it with \
                 `gloc run SCRIPT --mission FILE.mi`"
        }
        "ma" => {
            "a mission argument file, not a script: a mission (`--mission FILE.mi`) \
                 loads it from `../mafiles/`"
        }
        "cac" | "ccc" => "a sensor list, not a script: give it with `--masterdata`",
        "csv" => {
            "a CSV file, not a script: replay a script over recorded values with \
                  `gloc run SCRIPT --replay FILE.csv`"
        }
        "toml" => {
            "a settings file, not a script: gloc reads the nearest `gloc.toml` \
                   above the script by itself"
        }
        _ => return None,
    };
    Some(hint.to_string())
}

/// Reads and loads a `.gloc` or `.gbas` script (by extension), with the settings'
/// cycle budget (so every surface warns W2302 alike).
pub fn load_script(
    path: &Path,
    sensors: &SensorList,
    settings: &Settings,
    optimization: Optimization,
) -> Result<Script, ProjectError> {
    let text = read_script(path)?;
    Ok(load_text(
        Some(path),
        path.display().to_string(),
        text,
        Language::of_path(path),
        sensors,
        settings,
        optimization,
    ))
}

/// Loads a script's text in `language`.
pub fn load_text(
    path: Option<&Path>,
    display: String,
    text: String,
    language: Language,
    sensors: &SensorList,
    settings: &Settings,
    optimization: Optimization,
) -> Script {
    let written_for = path.and_then(|path| {
        gloc_engine::gloc::identity::find_written_for(
            &text,
            sensors,
            &settings.list_folders(Some(path)),
        )
    });
    let loaded = load_script_written_for(
        &text,
        language,
        sensors,
        &load_options(settings, optimization),
        written_for,
    );
    let hint = language_hint(&text, language, &loaded, sensors);
    let empty = words(&text).next().is_none();
    Script {
        path: path.map(Path::to_path_buf),
        display,
        text,
        language,
        loaded,
        hint,
        empty,
    }
}

/// The loader's options for these settings: the budget always applies (the default
/// one too), so `W2302` is decided the same way everywhere.
pub fn load_options(settings: &Settings, optimization: Optimization) -> LoadOptions {
    LoadOptions {
        optimization,
        cycle_budget: Some(settings.cycle_budget.value.get()),
    }
}

/// The other language.
fn other(language: Language) -> Language {
    match language {
        Language::Gloc => Language::Gbasic,
        Language::Gbasic => Language::Gloc,
    }
}

/// The first word of each line that has one, outside comments (`#` GLOC, `'` GBASIC).
/// An iterator, not a list: a script has up to a million lines (a list of their
/// words took 450 MB of 8 million).
fn words(text: &str) -> impl Iterator<Item = &str> {
    text.lines().filter_map(|line| {
        line.split(['#', '\''])
            .next()
            .unwrap_or("")
            .split_whitespace()
            .next()
    })
}

/// By content: the script has errors as `language`, and reads as the other language
/// (it loads there without errors, or opens with GLOC's header / GBASIC's `dim`).
pub fn language_hint(
    text: &str,
    language: Language,
    loaded: &LoadedScript,
    sensors: &SensorList,
) -> Option<String> {
    // An empty file reads as nothing in either language: its own error says so. A
    // script over the size limits is over them in either language.
    let too_large = |diagnostic: &gloc_engine::Diagnostic| {
        diagnostic.code == gloc_engine::gloc::SOURCE_TOO_LARGE
    };
    if !loaded.has_errors()
        || words(text).next().is_none()
        || loaded.diagnostics.iter().any(too_large)
    {
        return None;
    }
    let looks_like = match other(language) {
        Language::Gloc => words(text)
            .next()
            .is_some_and(|word| word.eq_ignore_ascii_case("nregs")),
        Language::Gbasic => words(text).any(|word| word.eq_ignore_ascii_case("dim")),
    };
    let looks_like = looks_like || {
        let as_other = load_script_written_for(
            text,
            other(language),
            sensors,
            &LoadOptions::default(),
            None,
        );
        !as_other.has_errors()
    };
    looks_like.then(|| match other(language) {
        Language::Gbasic => "this looks like GBASIC, but it was read as GLOC: only `.gbas` and `.bas` files are read as GBASIC; rename it to end in `.gbas`".to_string(),
        Language::Gloc => "this looks like GLOC, but it was read as GBASIC (`gloc compile`, `.gbas` and `.bas` files are GBASIC); a GLOC file needs no compiling: name it `.gloc`, and `gloc check` and `gloc run` take it as it is".to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hint(text: &str, language: Language) -> Option<String> {
        let sensors = SensorList::embedded();
        let loaded =
            load_script_written_for(text, language, &sensors, &LoadOptions::default(), None);
        language_hint(text, language, &loaded, &sensors)
    }

    #[test]
    fn gloc_read_as_gbasic_gets_a_hint_and_so_does_gbasic_read_as_gloc() {
        let gloc = "nregs 1\nnblbs 0\nninstr 2\nloadi 1,r0\nyield\n";
        let hint_text = hint(gloc, Language::Gbasic).expect("a hint");
        assert!(
            hint_text.starts_with("this looks like GLOC, but it was read as GBASIC"),
            "{hint_text}"
        );
        let gbasic = "dim x as integer\nx = 1\nprint x\nyield\n";
        let hint_text = hint(gbasic, Language::Gloc).expect("a hint");
        assert!(
            hint_text.starts_with("this looks like GBASIC, but it was read as GLOC"),
            "{hint_text}"
        );
        // GBASIC without `dim` still compiles as GBASIC.
        assert!(hint("print 1\nyield\n", Language::Gloc).is_some());
    }

    #[test]
    fn an_empty_file_gets_no_hint_and_is_marked_empty() {
        // E0010 says a GLOC file is empty; "looks like GBASIC" would be false.
        assert_eq!(hint("", Language::Gloc), None);
        assert_eq!(hint("\n  \n# only a comment\n", Language::Gloc), None);
        assert!(words("' a comment\n\n").next().is_none());
        assert!(words("yield\n").next().is_some());
    }

    #[test]
    fn a_script_in_its_own_language_gets_no_hint() {
        assert_eq!(
            hint("dim x as integer\nx = 1\nyield\n", Language::Gbasic),
            None
        );
        // Errors in the right language, not valid in the other: no hint.
        assert_eq!(hint("dim x as integer\nx = \n", Language::Gbasic), None);
    }
}
