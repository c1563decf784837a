//! The simulator's navigation against comet's own log (comet-2019-222-02-154.dbd
//! in data/): the firmware's steering and surfacing current estimate, computed by
//! the simulator's functions from the log's inputs, equal what the glider logged;
//! and the simulator, started where comet dove with comet's belief and the current
//! it found, surfaces near comet's first fix.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_sim::calibrate::fit;
use gloc_sim::navigation::{
    angle_difference, final_water_velocity, initial_water_velocity, steer,
    time_adjusted_postfix_drift, Lmc, Xy,
};
use gloc_sim::{Mission, SimConfig, Simulation};

/// The sensors the tests read, in this order.
const SENSORS: &[&str] = &[
    "m_present_time",
    "x_dr_state",
    "m_x_lmc",
    "m_y_lmc",
    "c_wpt_x_lmc",
    "c_wpt_y_lmc",
    "m_water_vx",
    "m_water_vy",
    "m_avg_speed",
    "c_heading",
    "m_gps_lat",
    "m_gps_lon",
    "m_gps_fix_x_lmc",
    "m_gps_fix_y_lmc",
    "m_dr_surf_x_lmc",
    "m_dr_surf_y_lmc",
    "m_dr_time",
    "x_prior_seg_water_vx",
    "x_prior_seg_water_vy",
    "m_initial_water_vx",
    "m_initial_water_vy",
    "m_final_water_vx",
    "m_final_water_vy",
    "m_gps_postfix_x_lmc",
    "m_gps_postfix_y_lmc",
    "m_dr_fix_time",
    "m_dr_postfix_time",
    "c_wpt_lat",
    "c_wpt_lon",
    "m_depth",
];

#[derive(Clone, Copy, PartialEq, Eq)]
enum S {
    Time,
    DrState,
    X,
    Y,
    WptX,
    WptY,
    WaterVx,
    WaterVy,
    AvgSpeed,
    CHeading,
    GpsLat,
    GpsLon,
    FixX,
    FixY,
    SurfX,
    SurfY,
    DrTime,
    PriorVx,
    PriorVy,
    InitialVx,
    InitialVy,
    FinalVx,
    FinalVy,
    PostfixX,
    PostfixY,
    FixTime,
    PostfixTime,
    _WptLat,
    _WptLon,
    Depth,
}

/// One cycle: each sensor's value when the cycle updated it, and its latest value.
struct Row {
    updated: Vec<Option<f64>>,
    latest: Vec<f64>,
}

impl Row {
    fn updated(&self, sensor: S) -> Option<f64> {
        self.updated[sensor as usize]
    }
    fn get(&self, sensor: S) -> f64 {
        self.latest[sensor as usize]
    }
}

fn data() -> PathBuf {
    gloc_testsupport::data("")
}

fn comet_rows(data: &Path) -> Vec<Row> {
    let log = data.join("comet/from-glider/comet-2019-222-02-154.dbd");
    let mut source =
        gloc_dbd::open_path(&log, Some(&data.join("cac"))).unwrap_or_else(|e| panic!("{e}"));
    let columns: Vec<usize> = SENSORS
        .iter()
        .map(|name| {
            source
                .sensors()
                .iter()
                .position(|sensor| sensor.name == *name)
                .unwrap_or_else(|| panic!("comet's log has no {name}"))
        })
        .collect();
    let mut rows = Vec::new();
    let mut latest = vec![f64::NAN; SENSORS.len()];
    while let Some(cycle) = source.next_cycle().unwrap_or_else(|e| panic!("{e}")) {
        let updated: Vec<Option<f64>> = columns.iter().map(|&c| cycle.value(c)).collect();
        for (slot, value) in latest.iter_mut().zip(&updated) {
            if let Some(value) = value {
                *slot = *value;
            }
        }
        rows.push(Row {
            updated,
            latest: latest.clone(),
        });
    }
    rows
}

fn xy(row: &Row, x: S, y: S) -> Xy {
    Xy::new(row.get(x), row.get(y))
}

#[test]
fn steering_reproduces_comets_c_heading() {
    let rows = comet_rows(&data());
    let mut worst: f64 = 0.0;
    let mut count = 0;
    for row in &rows {
        // Underwater, where the heading is steered on the dead-reckoned position.
        let (Some(logged), Some(state)) = (row.updated(S::CHeading), row.updated(S::DrState))
        else {
            continue;
        };
        if state != 1.0 {
            continue;
        }
        let heading = steer(
            xy(row, S::X, S::Y),
            xy(row, S::WptX, S::WptY),
            xy(row, S::WaterVx, S::WaterVy),
            row.get(S::AvgSpeed),
        );
        worst = worst.max(angle_difference(heading, logged).abs());
        count += 1;
    }
    eprintln!("{count} c_heading values, worst {:.4}°", worst.to_degrees());
    assert!(count > 1500, "{count}");
    assert!(worst.to_degrees() < 1.0, "worst {:.3}°", worst.to_degrees());
}

#[test]
fn surfacing_estimate_reproduces_comets_initial_and_final_current() {
    let rows = comet_rows(&data());
    // The initial estimate at 154's first fix (x_dr_state 3), from the first fix,
    // the DR surfacing position, the time underwater and the prior current.
    let fix = first_fix_of_154(&rows);
    let row = &rows[fix];
    // The time underwater, by the clock: from the cycle that began dead
    // reckoning (x_dr_state 1) to the one that found the surface (2).
    let dive = rows
        .iter()
        .position(|row| row.updated(S::DrState) == Some(1.0))
        .expect("the dive");
    let surfaced = rows
        .iter()
        .position(|row| row.updated(S::DrState) == Some(2.0))
        .expect("the surfacing");
    let dr_time = rows[surfaced].get(S::Time) - rows[dive].get(S::Time);
    assert!((dr_time - row.get(S::DrTime)).abs() < 0.01, "{dr_time}");
    let error = xy(row, S::FixX, S::FixY) - xy(row, S::SurfX, S::SurfY);
    let initial = initial_water_velocity(xy(row, S::PriorVx, S::PriorVy), error, dr_time);
    let logged = xy(row, S::InitialVx, S::InitialVy);
    eprintln!("initial: {initial:?} logged {logged:?}");
    close_4(initial.x, logged.x);
    close_4(initial.y, logged.y);

    // The final estimate of the segment before (153), taken at the surface
    // at the file's start (x_dr_state 4): with the post-fix drift.
    let post = rows
        .iter()
        .position(|row| {
            row.updated(S::DrState) == Some(4.0)
                || (row.get(S::DrState) == 4.0 && row.updated(S::FinalVx).is_some())
        })
        .expect("153's x_dr_state 4");
    let first = &rows[0];
    let row = &rows[post];
    let first_fix = xy(first, S::FixX, S::FixY);
    let error = first_fix - xy(first, S::SurfX, S::SurfY);
    let drift = time_adjusted_postfix_drift(
        xy(row, S::PostfixX, S::PostfixY) - first_fix,
        first.get(S::FixTime),
        row.get(S::PostfixTime),
    );
    let prior = xy(first, S::PriorVx, S::PriorVy);
    let final_water = final_water_velocity(prior, error, drift, first.get(S::DrTime));
    let logged = xy(row, S::FinalVx, S::FinalVy);
    eprintln!("final: {final_water:?} logged {logged:?}");
    close_4(final_water.x, logged.x);
    close_4(final_water.y, logged.y);
}

/// The cycle of 154's first fix after surfacing (x_dr_state 2 → 3).
fn first_fix_of_154(rows: &[Row]) -> usize {
    let surfaced = rows
        .iter()
        .position(|row| row.updated(S::DrState) == Some(2.0))
        .expect("the surfacing");
    surfaced
        + rows[surfaced..]
            .iter()
            .position(|row| row.updated(S::DrState) == Some(3.0))
            .expect("154's first fix")
}

/// Equal to 4 significant digits.
fn close_4(got: f64, want: f64) {
    assert!(
        (got - want).abs() <= 5e-4 * want.abs(),
        "{got} is not {want} to 4 significant digits"
    );
}

/// Where and when comet was, and what it believed, at the last fix before 154's dive.
struct Start {
    time: f64,
    lat: f64,
    lon: f64,
    believed: Xy,
    avg_speed: f64,
}

fn comet_start(rows: &[Row]) -> (Start, usize) {
    let dive = rows
        .iter()
        .position(|row| row.updated(S::DrState) == Some(1.0))
        .expect("the dive");
    let last_fix = rows[..dive]
        .iter()
        .rposition(|row| row.updated(S::GpsLat).is_some())
        .expect("a fix before the dive");
    let row = &rows[last_fix];
    (
        Start {
            time: row.get(S::Time),
            lat: row.get(S::GpsLat),
            lon: row.get(S::GpsLon),
            believed: xy(&rows[dive], S::WaterVx, S::WaterVy),
            avg_speed: rows[dive].get(S::AvgSpeed),
        },
        dive,
    )
}

/// comet's nsb3.mi with its own .ma files, served from memory: the goto list
/// starts at the waypoint comet steered to in 154 (its `initial_wpt` −1 means
/// "after the last achieved", which a fresh run does not know), the every-3-hours
/// surfacing (surfac10.ma, `when_secs` after its last start) comes due when
/// comet's did, prepare_to_dive does not wait (the run starts at comet's last fix
/// before the dive), and the `sensor:` lines set the start, the belief and the water.
fn comet_mission(data: &Path, settings: &str, surface_after: f64) -> Mission {
    let path = data.join("comet/missions/nsb3.mi");
    let mut read = |file: &Path| -> std::io::Result<String> {
        let text = std::fs::read_to_string(file)?;
        let name = file.file_name().and_then(|n| n.to_str()).unwrap_or("");
        Ok(match name {
            // The run starts at comet's last fix, ready to dive.
            "nsb3.mi" => format!("{settings}{text}").replace(
                "b_arg: wait_time(s)            300",
                "b_arg: wait_time(s)            0",
            ),
            "goto_l10.ma" => text.replace("initial_wpt(enum)     -1", "initial_wpt(enum) 1"),
            "surfac10.ma" => text.replace(
                "when_secs(sec)    10800",
                &format!("when_secs(sec) {surface_after:.0}"),
            ),
            _ => text,
        })
    };
    let mission = Mission::load_with(&path, &mut read);
    assert!(!mission.has_errors(), "{}", mission.render_plain());
    mission
}

/// Flies the mission from comet's start until the first fix after surfacing;
/// gives the fix (LMC of the simulation), the time underwater, the projection
/// and the simulated glider's own initial current estimate.
fn first_fix_after_surfacing(mission: &Mission, config: &SimConfig) -> (Xy, f64, Lmc, Xy) {
    let (list, problems) = gloc_engine::sensors::parse_cac(
        &std::fs::read_to_string(data().join("cac/1f35be3b.cac")).expect("comet's sensor list"),
    );
    assert!(problems.is_empty(), "{problems:?}");
    let mut sim = Simulation::new(mission, Arc::new(list), None, config).expect("starts");
    let mut dove = false;
    while sim.step_cycle() && sim.time() < 30_000.0 {
        let nav = sim.navigation();
        dove |= nav.dr_state == gloc_sim::navigation::DrState::Underwater;
        if dove && nav.dr_state == gloc_sim::navigation::DrState::FirstFix {
            let fix = nav.gps_fix.expect("the first fix");
            return (fix, nav.dr_time, nav.lmc, nav.initial_water);
        }
    }
    panic!("no first fix after a dive in 30,000 s");
}

#[test]
fn simulated_first_fix_lands_near_comets() {
    let data = data();
    let rows = comet_rows(&data);
    let (start, dive) = comet_start(&rows);
    // What comet found after surfacing: the initial estimate at the first fix.
    let fix = first_fix_of_154(&rows);
    let found = xy(&rows[fix], S::InitialVx, S::InitialVy);
    let real_fix = (rows[fix].get(S::GpsLat), rows[fix].get(S::GpsLon));
    let real_underwater = rows[fix].get(S::DrTime);
    // Its surfacing came due during the last climb: the surface behavior
    // started when comet left its last bottom turn (deepest point before surfacing).
    let surfaced = rows
        .iter()
        .position(|row| row.updated(S::DrState) == Some(2.0))
        .expect("the surfacing");
    let bottom = (dive..surfaced)
        .max_by(|&a, &b| {
            let depth = |i: usize| {
                if rows[i].get(S::Time) > rows[surfaced].get(S::Time) - 600.0 {
                    rows[i].get(S::Depth)
                } else {
                    f64::NEG_INFINITY
                }
            };
            depth(a).total_cmp(&depth(b))
        })
        .expect("a last bottom");
    let surface_after = rows[bottom].get(S::Time) - start.time + 60.0;

    // Calibrated on the same log, as `gloc calibrate` would.
    let track = {
        let log = data.join("comet/from-glider/comet-2019-222-02-154.dbd");
        let mut source =
            gloc_dbd::open_path(&log, Some(&data.join("cac"))).unwrap_or_else(|e| panic!("{e}"));
        gloc_project::logs::read_track(source.as_mut()).unwrap_or_else(|e| panic!("{e}"))
    };
    let mut config = SimConfig::default();
    let fitted = fit(&track, 3.0, &config).unwrap_or_else(|e| panic!("{e}"));
    fitted.apply(&mut config);
    config.water_depth = track.water_depth();

    let fly = |truth: Xy| {
        let settings = format!(
            "sensor: s_ini_lat(lat) {}\nsensor: s_ini_lon(lon) {}\n\
             sensor: s_water_speed(m/s) {}\nsensor: s_water_direction(rad) {}\n\
             sensor: m_water_vx(m/s) {}\nsensor: m_water_vy(m/s) {}\n\
             sensor: m_avg_speed(m/s) {}\n",
            start.lat,
            start.lon,
            truth.length(),
            truth.x.atan2(truth.y),
            start.believed.x,
            start.believed.y,
            start.avg_speed,
        );
        let mission = comet_mission(&data, &settings, surface_after);
        let (fix, underwater, lmc, estimate) = first_fix_after_surfacing(&mission, &config);
        let real = lmc.nmea_to_xy(real_fix.0, real_fix.1);
        (fix.distance(real), underwater, estimate)
    };
    let (miss, underwater, estimate) = fly(found);
    let (null_miss, _, _) = fly(start.believed);
    // The simulated glider's own estimate at its first fix finds comet's.
    eprintln!("the simulated m_initial_water_vx/vy {estimate:?}, comet's {found:?}");
    assert!(estimate.distance(found) < 0.01, "{estimate:?} {found:?}");
    let bound = (0.015 * real_underwater).max(150.0);
    eprintln!(
        "first fix: {miss:.0} m from comet's (bound {bound:.0} m; {underwater:.0} s underwater, comet {real_underwater:.0} s); \
         with the prior current as the truth: {null_miss:.0} m"
    );
    assert!(
        miss <= bound,
        "missed comet's first fix by {miss:.0} m (bound {bound:.0} m)"
    );
    assert!(
        (4000.0..6500.0).contains(&null_miss),
        "the null model missed by {null_miss:.0} m"
    );
}
