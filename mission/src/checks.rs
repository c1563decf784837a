//! Checks no manufacturer tool makes: a mission's values against each other, the
//! behavior table's limits and the waypoint format. Each is a warning on the line
//! involved, naming the other lines (with a label when they are in the same file).
//!
//! Values are those flown: as written (a `.ma` value over a `.mi` one), else the
//! behavior table's default. A value of 1,000,000 or more names a `u_mission_param`
//! sensor, set at run time, and is not checked.

use gloc_engine::Diagnostic;

use crate::behaviors::BehaviorKind;
use crate::mission::{BehaviorSpec, Location, Mission, MissionDiagnostic, Waypoint};

/// Every check below, in the order of the lines they name.
pub fn check(mission: &Mission) -> Vec<MissionDiagnostic> {
    let mut found = Vec::new();
    limits(mission, &mut found);
    waypoints(mission, &mut found);
    depths(mission, &mut found);
    surface_intervals(mission, &mut found);
    waypoint_counts(mission, &mut found);
    found
}

/// A value the glider flies, and where it comes from.
#[derive(Clone, Copy)]
struct Value {
    value: f64,
    /// The `b_arg:` line, or the `behavior:` line when it is the table's default.
    at: Location,
    written: bool,
}

fn value(spec: &BehaviorSpec, name: &str) -> Option<Value> {
    let written = spec
        .args
        .iter()
        .rev()
        .filter(|arg| arg.at.file != 0)
        .find(|arg| arg.name.eq_ignore_ascii_case(name))
        .or_else(|| {
            spec.args
                .iter()
                .rev()
                .find(|arg| arg.name.eq_ignore_ascii_case(name))
        });
    let found = match written {
        Some(arg) => Value {
            value: arg.value,
            at: arg.at,
            written: true,
        },
        None => Value {
            value: spec.default(name)?,
            at: spec.at,
            written: false,
        },
    };
    (found.value < 1_000_000.0).then_some(found)
}

/// `yo10.ma:4` or `line 4` (in the file of `here`).
fn place(mission: &Mission, at: Location, here: usize) -> String {
    let (path, line, _) = mission.line_col(at.file, at.span);
    if at.file == here {
        format!("line {line}")
    } else {
        let name = path
            .file_name()
            .map_or_else(String::new, |name| name.to_string_lossy().into_owned());
        format!("{name}:{line}")
    }
}

fn describe(mission: &Mission, name: &str, found: Value, here: usize) -> String {
    if found.written {
        format!(
            "`{name}` {} ({})",
            found.value,
            place(mission, found.at, here)
        )
    } else {
        format!("`{name}` {} (the default)", found.value)
    }
}

fn warn(
    found: &mut Vec<MissionDiagnostic>,
    code: &'static str,
    at: Location,
    message: String,
    help: &str,
    others: &[(Location, &str)],
) {
    let mut diagnostic = Diagnostic::warning(code, at.span, message).with_help(help);
    for (other, label) in others {
        if other.file == at.file && other.span != at.span {
            diagnostic = diagnostic.with_label(other.span, *label);
        }
    }
    found.push(MissionDiagnostic {
        file: at.file,
        diagnostic,
    });
}

/// S0120: written values outside the table's `#!` range.
fn limits(mission: &Mission, found: &mut Vec<MissionDiagnostic>) {
    let table = mission.table();
    for spec in mission.behaviors.iter().filter(|spec| spec.defined) {
        let Some(info) = table.behavior(&spec.name) else {
            continue;
        };
        for arg in &spec.args {
            let Some(def) = info.arg(&arg.name) else {
                continue;
            };
            if arg.value >= 1_000_000.0 {
                continue;
            }
            if let Some(choices) = def
                .choices
                .as_ref()
                .filter(|choices| !choices.contains(&arg.value))
            {
                let listed = choices
                    .iter()
                    .map(|choice| choice.to_string())
                    .collect::<Vec<_>>()
                    .join(", ");
                warn(
                    found,
                    gloc_engine::codes::mission::VALUE_NOT_A_CHOICE,
                    arg.at,
                    format!(
                        "`{}` is {}, not one of the values {} allows for `{}` here: {listed}",
                        arg.name,
                        arg.value,
                        table.source_name(),
                        spec.name
                    ),
                    "Control Center refuses this value; pick one of the listed codes",
                    &[],
                );
                continue;
            }
            if !def.range.excludes(arg.value) {
                continue;
            }
            let Some(range) = def.range.text() else {
                continue;
            };
            warn(
                found,
                gloc_engine::codes::mission::VALUE_OUT_OF_RANGE,
                arg.at,
                format!(
                    "`{}` is {}, outside its range in {}: {range}",
                    arg.name,
                    arg.value,
                    table.source_name()
                ),
                "Control Center refuses this value; check the units and the number",
                &[],
            );
        }
    }
}

/// What is wrong with a `lon lat` pair in NMEA `dddmm.mmm`, if anything.
fn waypoint_problem(lon: f64, lat: f64) -> Option<String> {
    let minutes = |value: f64| value.abs() % 100.0;
    if lat.abs() > 9000.0 && lon.abs() <= 9000.0 {
        return Some(format!(
            "latitude {lat} is beyond ±90° (9000.0) while longitude {lon} would be a latitude: \
             longitude and latitude look swapped (the line is `LON LAT`)"
        ));
    }
    if lat.abs() > 9000.0 {
        return Some(format!(
            "latitude {lat} is beyond ±90° (9000.0 in ddmm.mmm)"
        ));
    }
    if lon.abs() > 18000.0 {
        return Some(format!(
            "longitude {lon} is beyond ±180° (18000.0 in dddmm.mmm)"
        ));
    }
    if lon.abs() <= 180.0 && lat.abs() <= 90.0 && (lon.fract() != 0.0 || lat.fract() != 0.0) {
        return Some(format!(
            "{lon} {lat} reads as within 2° of 0°N 0°E in `dddmm.mmm`: it looks like \
             decimal degrees"
        ));
    }
    if minutes(lon) >= 60.0 || minutes(lat) >= 60.0 {
        let which = if minutes(lon) >= 60.0 { lon } else { lat };
        return Some(format!(
            "{which} has {:.3} minutes: `dddmm.mmm` allows 0 to 59.999",
            minutes(which)
        ));
    }
    None
}

/// Degrees from NMEA `dddmm.mmm`.
fn degrees(nmea: f64) -> f64 {
    let whole = (nmea.abs() / 100.0).trunc();
    (whole + (nmea.abs() - whole * 100.0) / 60.0).copysign(nmea)
}

/// The median of some values (for the centre of a waypoint list).
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// Within a list of three or more waypoints, one far (over 5°) from the list's
/// centre that would lie near it with longitude and latitude exchanged: swapped.
fn swapped_in_list(list: &[&Waypoint], waypoint: &Waypoint) -> bool {
    if list.len() < 3 {
        return false;
    }
    let lon = median(list.iter().map(|other| degrees(other.lon)).collect());
    let lat = median(list.iter().map(|other| degrees(other.lat)).collect());
    let far = |x: f64, y: f64| (x - lon).abs() > 5.0 || (y - lat).abs() > 5.0;
    far(degrees(waypoint.lon), degrees(waypoint.lat))
        && !far(degrees(waypoint.lat), degrees(waypoint.lon))
}

/// S0121: waypoint lists, and `.mi` waypoints given in latitude/longitude (`wpt_units` 2).
fn waypoints(mission: &Mission, found: &mut Vec<MissionDiagnostic>) {
    let help = "write waypoints as NMEA `dddmm.mmm`, longitude first: 70°32.064'W 41°38.106'N is `-7032.064 4138.106`";
    for waypoint in &mission.waypoints {
        let list: Vec<&Waypoint> = mission
            .waypoints
            .iter()
            .filter(|other| {
                other.behavior == waypoint.behavior && other.at.file == waypoint.at.file
            })
            .collect();
        let problem = waypoint_problem(waypoint.lon, waypoint.lat).or_else(|| {
            swapped_in_list(&list, waypoint).then(|| {
                format!(
                    "{} {} is far from the list's other waypoints, and beside them with \
                     longitude and latitude exchanged: they look swapped (the line is `LON LAT`)",
                    waypoint.lon, waypoint.lat
                )
            })
        });
        if let Some(problem) = problem {
            warn(
                found,
                gloc_engine::codes::mission::WAYPOINT_NOT_NMEA,
                waypoint.at,
                format!("waypoint {problem}"),
                help,
                &[],
            );
        }
    }
    for spec in &mission.behaviors {
        let pairs: Vec<(String, String, String)> = match spec.kind {
            BehaviorKind::GotoWpt => vec![("wpt_units".into(), "wpt_x".into(), "wpt_y".into())],
            BehaviorKind::GotoList => (0..8)
                .map(|index| {
                    (
                        format!("wpt_units_{index}"),
                        format!("wpt_x_{index}"),
                        format!("wpt_y_{index}"),
                    )
                })
                .collect(),
            _ => continue,
        };
        for (units, x, y) in pairs {
            let lat_lon = spec.arg(&units).is_some_and(|units| units == 2.0);
            let (Some(lon), Some(lat)) = (spec.arg(&x), spec.arg(&y)) else {
                continue;
            };
            if !lat_lon {
                continue;
            }
            let Some(problem) = waypoint_problem(lon, lat) else {
                continue;
            };
            let at = spec
                .args
                .iter()
                .rev()
                .find(|arg| arg.name.eq_ignore_ascii_case(&y))
                .map_or(spec.at, |arg| arg.at);
            warn(
                found,
                gloc_engine::codes::mission::WAYPOINT_NOT_NMEA,
                at,
                format!("`{x}` `{y}`: waypoint {problem}"),
                help,
                &[],
            );
        }
    }
}

/// S0122 and S0123: dive targets against abend's overdepth and the water depth, and
/// climb targets against dive targets.
fn depths(mission: &Mission, found: &mut Vec<MissionDiagnostic>) {
    let overdepth = mission
        .known_behaviors()
        .find(|spec| spec.kind == BehaviorKind::Abend)
        .and_then(|abend| value(abend, "overdepth"))
        .filter(|overdepth| overdepth.value > 0.0);
    let water = mission
        .sensor_settings
        .iter()
        .rev()
        .find(|setting| setting.name.eq_ignore_ascii_case("s_water_depth_avg"))
        .filter(|setting| setting.value > 0.0);
    for spec in mission.known_behaviors() {
        let (dive, climb) = match spec.kind {
            BehaviorKind::Yo => ("d_target_depth", Some("c_target_depth")),
            BehaviorKind::DiveTo => ("target_depth", None),
            _ => continue,
        };
        let Some(target) = value(spec, dive) else {
            continue;
        };
        // Each limit the dive target passes: what it is (after "deeper than"), what
        // to do, and where the limit was set.
        let here = target.at.file;
        let limits = [
            overdepth
                .filter(|limit| target.value > limit.value)
                .map(|limit| {
                    (
                        format!(
                            "abend's {}: the mission aborts on the dive",
                            describe(mission, "overdepth", limit, here)
                        ),
                        "make the dive target shallower than overdepth, or overdepth deeper",
                        (limit.at, "abend's overdepth"),
                    )
                }),
            water
                .filter(|water| target.value > water.value)
                .map(|water| {
                    (
                        format!(
                            "the water, `s_water_depth_avg` {} ({}): the glider turns on the \
                             altimeter or the bottom",
                            water.value,
                            place(mission, water.at, here)
                        ),
                        "set the dive target above the bottom, or rely on d_target_altitude",
                        (water.at, "the water depth"),
                    )
                }),
        ];
        for (limit, help, other) in limits.into_iter().flatten() {
            warn(
                found,
                gloc_engine::codes::mission::TARGET_TOO_DEEP,
                target.at,
                format!(
                    "{}'s {} is deeper than {limit}",
                    spec.name,
                    describe(mission, dive, target, here)
                ),
                help,
                &[other],
            );
        }
        let Some(climb) = climb.and_then(|name| Some((name, value(spec, name)?))) else {
            continue;
        };
        let (climb_name, climb) = climb;
        if climb.value > target.value {
            let here = climb.at.file;
            warn(
                found,
                gloc_engine::codes::mission::CLIMB_BELOW_DIVE,
                climb.at,
                format!(
                    "{}'s {} is deeper than its {}: it would climb to below where it dives to",
                    spec.name,
                    describe(mission, climb_name, climb, here),
                    describe(mission, dive, target, here)
                ),
                "the climb target is the shallow turn: make it smaller than the dive target",
                &[(target.at, "the dive target")],
            );
        }
    }
}

/// S0124: a timed surface behavior whose first surfacing comes after abend's overtime.
fn surface_intervals(mission: &Mission, found: &mut Vec<MissionDiagnostic>) {
    let Some(overtime) = mission
        .known_behaviors()
        .find(|spec| spec.kind == BehaviorKind::Abend)
        .and_then(|abend| value(abend, "overtime"))
        .filter(|overtime| overtime.value > 0.0)
    else {
        return;
    };
    for spec in mission
        .known_behaviors()
        .filter(|spec| spec.kind == BehaviorKind::Surface)
    {
        // start_when 6, 9, 10 and 12 wait when_secs (after an end, a start, or since comms).
        let timed = value(spec, "start_when")
            .is_some_and(|start| matches!(start.value as i64, 6 | 9 | 10 | 12));
        let Some(interval) = value(spec, "when_secs").filter(|_| timed) else {
            continue;
        };
        if interval.value <= overtime.value {
            continue;
        }
        let at = if interval.written {
            interval.at
        } else {
            spec.at
        };
        let here = at.file;
        warn(
            found,
            gloc_engine::codes::mission::SURFACE_AFTER_OVERTIME,
            at,
            format!(
                "this surface behavior waits {} s, longer than abend's {}: the mission \
                 aborts before it surfaces",
                interval.value,
                describe(mission, "overtime", overtime, here)
            ),
            "shorten when_secs or lengthen overtime",
            &[(overtime.at, "abend's overtime")],
        );
    }
}

/// S0125: `num_waypoints` against the waypoints listed in the `.ma` file (the glider
/// counts the list: the masterdata says `num_waypoints` is ignored with args from file).
fn waypoint_counts(mission: &Mission, found: &mut Vec<MissionDiagnostic>) {
    for (index, spec) in mission.behaviors.iter().enumerate() {
        if spec.kind != BehaviorKind::GotoList {
            continue;
        }
        let listed: Vec<&Waypoint> = mission
            .waypoints
            .iter()
            .filter(|waypoint| waypoint.behavior == index)
            .collect();
        let Some(count) = spec
            .args
            .iter()
            .rev()
            .find(|arg| arg.name.eq_ignore_ascii_case("num_waypoints"))
        else {
            continue;
        };
        let in_mi = (0..64)
            .filter(|n| spec.arg(&format!("wpt_x_{n}")).is_some())
            .count();
        let (have, what) = if listed.is_empty() {
            (in_mi, "`wpt_x_N` arguments")
        } else {
            (listed.len(), "waypoints in the list")
        };
        // No waypoints anywhere (a list the glider gets later): nothing to compare.
        if have == 0 {
            continue;
        }
        if count.value as usize == have && count.value >= 0.0 {
            continue;
        }
        let others: Vec<(Location, &str)> = listed
            .iter()
            .take(1)
            .map(|waypoint| (waypoint.at, "the list starts here"))
            .collect();
        warn(
            found,
            gloc_engine::codes::mission::NUM_WAYPOINTS_MISMATCH,
            count.at,
            format!(
                "`num_waypoints` is {}, but there are {have} {what}{}",
                count.value,
                if listed.is_empty() {
                    String::new()
                } else {
                    format!(
                        " ({}): the glider flies the list",
                        place(mission, listed[0].at, count.at.file)
                    )
                }
            ),
            "make num_waypoints the number of waypoints",
            &others,
        );
    }
}
