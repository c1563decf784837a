//! The active sensor list of a project: the masterdata, `.cac` or `.ccc` file the
//! settings name, or the embedded 2008 list. One loader and one error format for the
//! CLI, the language server and the debugger.

use std::path::{Path, PathBuf};

use gloc_engine::sensors::{load_sensor_file, SensorList, SensorOrder};
use gloc_engine::Diagnostic;

use crate::error::{ErrorKind, ProjectError};
use crate::settings::{Settings, Sourced};

/// A sensor list as read: the list, and the file's text and diagnostics (warnings,
/// or errors that [`LoadedSensors::errors`] turns into one error).
#[derive(Clone, Debug)]
pub struct LoadedSensors {
    pub list: SensorList,
    /// The file, `None` for the embedded list.
    pub path: Option<PathBuf>,
    pub text: String,
    pub diagnostics: Vec<Diagnostic>,
}

impl LoadedSensors {
    /// The embedded 2008 list.
    pub fn embedded() -> LoadedSensors {
        LoadedSensors {
            list: SensorList::embedded(),
            path: None,
            text: String::new(),
            diagnostics: Vec::new(),
        }
    }

    /// Errors in the file, or a file that holds no sensors.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error) || self.is_empty_file()
    }

    fn is_empty_file(&self) -> bool {
        self.path.is_some() && self.list.is_empty()
    }

    /// The list's errors as one project error (`the sensor list `F` has errors:` and
    /// one `F:LINE:COL: error[CODE]: …` line each), or `None` when it has none.
    pub fn errors(&self) -> Option<ProjectError> {
        let path = self.path.as_deref().unwrap_or(Path::new("<embedded>"));
        let display = path.display().to_string();
        // One line index for every diagnostic (one each took 15 s for 40,000 bad lines).
        let source = gloc_engine::render::SourceFile::new(&display, &self.text);
        let mut lines: Vec<String> = self
            .diagnostics
            .iter()
            .filter(|diagnostic| diagnostic.is_error())
            .map(|diagnostic| source.headline(diagnostic))
            .collect();
        if lines.is_empty() && self.is_empty_file() {
            lines.push(format!("{}: it holds no sensors", path.display()));
        }
        (!lines.is_empty()).then(|| {
            ProjectError::new(
                ErrorKind::Invalid,
                None,
                format!(
                    "the sensor list `{}` has errors:\n{}",
                    path.display(),
                    lines.join("\n")
                ),
            )
        })
    }

    /// The list, or its errors as one project error.
    pub fn into_list(self) -> Result<SensorList, ProjectError> {
        match self.errors() {
            Some(error) => Err(error),
            None => Ok(self.list),
        }
    }
}

/// The active sensor list of `settings`. An unreadable file is an error naming where
/// the path came from (`gloc.toml:1:14: cannot read the sensor list `nosuch.mi`: …`);
/// a list with errors is returned with its diagnostics (see [`LoadedSensors::errors`]).
pub fn load_sensor_list(settings: &Settings) -> Result<LoadedSensors, ProjectError> {
    match &settings.masterdata {
        None => Ok(LoadedSensors::embedded()),
        Some(masterdata) => load_sensor_list_file(masterdata, settings.sensor_order),
    }
}

/// Reads one sensor list file (masterdata, `.cac`, `.ccc`).
pub fn load_sensor_list_file(
    masterdata: &Sourced<PathBuf>,
    order: SensorOrder,
) -> Result<LoadedSensors, ProjectError> {
    let path = &masterdata.value;
    let loaded = load_sensor_file(path, order).map_err(|error| {
        ProjectError::new(
            ErrorKind::Unreadable,
            Some(masterdata.origin.clone()),
            format!("cannot read the sensor list `{}`: {error}", path.display()),
        )
    })?;
    Ok(LoadedSensors {
        list: loaded.list,
        path: Some(path.clone()),
        text: loaded.text,
        diagnostics: loaded.diagnostics,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::{Origin, Overrides, Surface};

    #[test]
    fn an_unreadable_list_names_where_its_path_came_from() {
        let settings = crate::settings::test_settings("\nmasterdata = \"nosuch.mi\"\n");
        let error = load_sensor_list(&settings).expect_err("no such file");
        // Line 2, column 14 (`masterdata = ` is 13 characters).
        crate::error::assert_unreadable(
            &error,
            "/p/gloc.toml:2:14: cannot read the sensor list `/p/nosuch.mi`: ",
        );
        let mut overrides = Overrides::new(Surface::Editor);
        overrides.masterdata = Some(PathBuf::from("/nowhere/md"));
        let settings =
            Settings::from_config(crate::config::Config::default(), overrides).expect("ok");
        let error = load_sensor_list(&settings).expect_err("no such file");
        assert_eq!(error.origin, Some(Origin::EditorSetting("gloc.masterdata")));
    }

    #[test]
    fn a_list_with_errors_is_one_error_with_a_line_per_problem() {
        let folder = gloc_testsupport::scratch_dir("project-md");
        let path = folder.join("bad.cac");
        // A `.cac` line needs `s:` and five fields; this one has too few.
        std::fs::write(&path, "s: T 0 0 4 m_depth\ns: T\n").expect("write");
        let loaded = load_sensor_list_file(
            &Sourced {
                value: path.clone(),
                origin: Origin::Default,
            },
            SensorOrder::FileOrder,
        )
        .expect("readable");
        assert!(loaded.has_errors(), "{:?}", loaded.diagnostics);
        let error = loaded.into_list().expect_err("errors");
        assert_eq!(error.kind, ErrorKind::Invalid);
        let text = error.to_string();
        assert!(text.starts_with("the sensor list `"), "{text}");
        assert!(
            text.contains("bad.cac:2:"),
            "the error is on line 2: {text}"
        );
        std::fs::remove_dir_all(&folder).ok();
    }
}
