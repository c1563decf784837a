//! The horizontal model against hand-worked geometry: headings flown, the
//! current carrying the truth away from a dead reckoning that does not know it,
//! a goto_list reaching its waypoint and a surface behavior starting on the hit,
//! the surfacing estimate finding the true current, and the sensors a script
//! reads (`docs/simulator.md`, "Navigation").

use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_sim::navigation::{DrState, Lmc, Xy};
use gloc_sim::{EndReason, Mission, SimConfig, Simulation};

/// A yo between 3 and 25 m in 40 m of water, under `above` (behaviors of
/// higher priority) and with `sensors` (`sensor:` lines).
fn mission(sensors: &str, above: &str) -> Mission {
    let text = format!(
        "sensor: s_water_depth_avg(m) 40\n{sensors}\
         behavior: abend\n  b_arg: overdepth(m) 35\n{above}\
         behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: num_half_cycles_to_do(nodim) -1\n  \
         b_arg: d_target_depth(m) 25\n  b_arg: d_target_altitude(m) -1\n  b_arg: c_target_depth(m) 3\n  \
         b_arg: c_target_altitude(m) -1\n  b_arg: end_action(enum) 2\n"
    );
    let mission = Mission::parse("nav.mi", text);
    assert!(!mission.has_errors(), "{}", mission.render_plain());
    mission
}

fn start(mission: &Mission) -> Simulation {
    Simulation::new(
        mission,
        Arc::new(SensorList::embedded()),
        None,
        &SimConfig::default(),
    )
    .expect("starts")
}

fn sensor(sim: &Simulation, name: &str) -> f64 {
    let id = sim
        .sensor_list()
        .lookup(name)
        .expect("in the embedded list");
    sim.sensor(id).expect("in range")
}

const HEADING: f64 = 1.25;

/// Steers 1.25 rad (71.6°, east-north-east).
const SET_HEADING: &str =
    "behavior: set_heading\n  b_arg: use_heading(enum) 1\n  b_arg: heading_value(X) 1.25\n";

#[test]
fn a_commanded_heading_is_flown_with_the_roll_bias_zig_zag_about_it() {
    let mut sim = start(&mission("", SET_HEADING));
    while sim.time() < 3600.0 {
        assert!(sim.step_cycle());
    }
    let nav = sim.navigation();
    let flown = sim.vehicle().distance;
    // Along the heading within the zig-zag: ±16.5° and ±13.9° about 90° lose under 4.2%
    // (1 − cos 16.5°) of the distance and wander across by a fraction.
    assert!(flown > 500.0, "{flown}");
    let along = nav.true_position.x * HEADING.sin() + nav.true_position.y * HEADING.cos();
    let across = nav.true_position.x * HEADING.cos() - nav.true_position.y * HEADING.sin();
    assert!(
        (0.955..=1.0).contains(&(along / flown)),
        "{}",
        along / flown
    );
    assert!(across.abs() < 0.1 * flown, "{:?}", nav.true_position);
    // No current: the dead reckoning follows the truth (its speed is the
    // cycle's end speed, the truth's the cycle's mean).
    assert!(nav.dead_reckoned.distance(nav.true_position) < 0.02 * flown);
    assert!((sensor(&sim, "c_heading") - HEADING).abs() < 1e-12);
}

#[test]
fn an_unknown_current_carries_the_truth_away_from_the_dead_reckoning() {
    // 0.1 m/s flowing north (direction 0); the glider believes in none.
    let sensors = "sensor: s_water_speed(m/s) 0.1\nsensor: s_water_direction(rad) 0\n";
    let mut sim = start(&mission(sensors, SET_HEADING));
    // The first cycles at the surface: the truth drifts, the DR takes fixes.
    while sim.navigation().dr_state != DrState::Underwater {
        assert!(sim.step_cycle());
    }
    let dive_time = sim.time();
    let offset = sim.navigation().true_position - sim.navigation().dead_reckoned;
    while sim.time() < dive_time + 3000.0 {
        assert!(sim.step_cycle());
    }
    let nav = sim.navigation();
    // After 3,000 s the current put the truth 300 m north of the belief.
    let gap = nav.true_position - nav.dead_reckoned - offset;
    let drift = 0.1 * (sim.time() - dive_time);
    assert!(
        (gap.y - drift).abs() < 0.01 * drift + 5.0,
        "{gap:?} {drift}"
    );
    assert!(gap.x.abs() < 0.02 * sim.vehicle().distance + 5.0, "{gap:?}");
}

#[test]
fn goto_list_reaches_its_waypoint_and_a_surface_starts_on_the_hit() {
    // One waypoint 1′ of latitude north (1,855 m at 54°18′ N), reached within
    // 100 m; the surface behavior above waits for the hit (start_when 8) and ends the mission.
    let above = "behavior: surface\n  b_arg: start_when(enum) 8\n  b_arg: end_action(enum) 0\n  \
                 b_arg: gps_wait_time(s) 60\n\
                 behavior: goto_list\n  b_arg: num_waypoints(nodim) 1\n  b_arg: num_legs_to_run(nodim) -1\n  \
                 b_arg: list_when_wpt_dist(m) 100\n  b_arg: wpt_x_0(X) 724.0\n  b_arg: wpt_y_0(X) 5419.0\n";
    let sensors = "sensor: s_ini_lat(lat) 5418.0\nsensor: s_ini_lon(lon) 724.0\n";
    let mut sim = start(&mission(sensors, above));
    let waypoint = Lmc::from_nmea(5418.0, 724.0).nmea_to_xy(5419.0, 724.0);
    assert!((waypoint.y - 1855.0).abs() < 2.0);
    let mut hit_at = None;
    while sim.step_cycle() && sim.time() < 6.0 * 3600.0 {
        if hit_at.is_none() && sensor(&sim, "x_hit_a_waypoint") == 1.0 {
            hit_at = Some(sim.navigation().true_position);
        }
    }
    let end = sim.end().expect("the surface behavior ended the mission");
    assert_eq!(end.reason, EndReason::Completed);
    let hit = hit_at.expect("a waypoint hit");
    // Judged on the dead reckoning, which without a current is the truth to
    // a few metres: within the 100 m, plus the cycle's travel.
    assert!(hit.distance(waypoint) < 100.0 + 10.0, "{hit:?}");
    assert!((sensor(&sim, "c_wpt_lat") - 5419.0).abs() < 1e-6);
    assert!((sensor(&sim, "c_wpt_lon") - 724.0).abs() < 1e-6);
}

#[test]
fn the_surfacing_estimate_finds_the_true_current() {
    // 0.12 m/s flowing to 45° (north-east); believed none. Surface every hour.
    let speed = 0.12;
    let direction = std::f64::consts::FRAC_PI_4;
    let sensors = format!(
        "sensor: s_water_speed(m/s) {speed}\nsensor: s_water_direction(rad) {direction}\n\
         sensor: u_use_current_correction(nodim) 1\n"
    );
    let above = "behavior: surface\n  b_arg: start_when(enum) 9\n  b_arg: when_secs(sec) 3600\n  \
                 b_arg: end_action(enum) 2\n  b_arg: gps_wait_time(s) 300\n";
    let mut sim = start(&mission(&sensors, &format!("{above}{SET_HEADING}")));
    let truth = Xy::polar(speed, direction);
    let mut initial = None;
    let mut finals = Vec::new();
    let mut state = sim.navigation().dr_state;
    while sim.step_cycle() && sim.time() < 3.0 * 3600.0 {
        let nav = sim.navigation();
        if state != nav.dr_state {
            match nav.dr_state {
                DrState::FirstFix if initial.is_none() => {
                    // The DR surfacing position froze while the truth drifted
                    // gps_fix_time (106 s) more: initial = c·(1 + 106 s / m_dr_time).
                    initial = Some((nav.initial_water, nav.dr_time, nav.fix_time));
                }
                DrState::PostFix => finals.push(nav.final_water),
                _ => {}
            }
            state = nav.dr_state;
        }
    }
    let (initial, dr_time, fix_time) = initial.expect("a first fix");
    let expected = truth * (1.0 + fix_time / dr_time);
    assert!(
        initial.distance(expected) < 0.005,
        "{initial:?} {expected:?}"
    );
    // The final estimate takes the surface drift out: the current itself.
    let first_final = finals.first().expect("a final estimate");
    assert!(
        first_final.distance(truth) < 0.005,
        "{first_final:?} {truth:?}"
    );
    // The glider now believes it.
    assert!((sensor(&sim, "m_water_vx") - truth.x).abs() < 0.005);
    assert!((sensor(&sim, "m_water_vy") - truth.y).abs() < 0.005);
}

#[test]
fn a_mission_without_navigation_starts_at_the_default_position() {
    let mut sim = start(&mission("", ""));
    assert!(sim.step_cycle());
    let (lat, lon) = gloc_sim::navigation::DEFAULT_START_NMEA;
    assert!((sensor(&sim, "m_lat") - lat).abs() < 1e-9);
    assert!((sensor(&sim, "m_lon") - lon).abs() < 1e-9);
    assert!((sensor(&sim, "m_gps_lat") - lat).abs() < 1e-9);
}

#[test]
fn a_script_reads_the_position_and_the_distance_to_the_waypoint() {
    use gloc_engine::gloc::{self, CheckOptions};
    let list = Arc::new(SensorList::embedded());
    let index = |name: &str| list.lookup(name).expect("in the embedded list").index();
    let script = format!(
        "nregs 2\nnblbs 1\nninstr 7\nlabel 0\nloads {},r0\nloads {},r1\nwrite r0\nprint r1\nyield\njumpi 0\n",
        index("m_y_lmc"),
        index("m_dist_to_wpt"),
    );
    let checked = gloc::check(&gloc::parse(&script), &list, &CheckOptions::default());
    let program = checked
        .program
        .unwrap_or_else(|| panic!("{:?}", checked.diagnostics));
    let above = "behavior: goto_wpt\n  b_arg: wpt_x(X) 724.0\n  b_arg: wpt_y(X) 5419.0\n  \
                 b_arg: when_wpt_dist(m) 50\n";
    let sensors = "sensor: s_ini_lat(lat) 5418.0\nsensor: s_ini_lon(lon) 724.0\n";
    let mut sim = Simulation::new(
        &mission(sensors, above),
        list.clone(),
        Some(program),
        &SimConfig::default(),
    )
    .expect("starts");
    let waypoint_north = Lmc::from_nmea(5418.0, 724.0).nmea_to_xy(5419.0, 724.0).y;
    let mut seen = 0;
    while sim.time() < 1800.0 && sim.step_cycle() {
        let line = sim.printed().next().expect("a line per cycle").to_string();
        let mut words = line
            .split(' ')
            .map(|word| word.parse::<f64>().expect("a number"));
        let (north, distance) = (words.next().expect("y"), words.next().expect("distance"));
        // What the script read is the published belief of this cycle.
        assert_eq!(north, sensor(&sim, "m_y_lmc"));
        assert_eq!(distance, sensor(&sim, "m_dist_to_wpt"));
        if distance > 0.0 {
            // Steering north along the meridian: the distance is what is left of it.
            assert!(
                (distance - (waypoint_north - north)).abs() < 0.05 * waypoint_north,
                "{line}"
            );
            seen += 1;
        }
    }
    assert!(seen > 300, "{seen}");
}

#[test]
fn hostile_navigation_settings_fly_without_a_panic() {
    let cases = [
        "sensor: s_ini_lat(lat) 1e308\nsensor: s_ini_lon(lon) -1e308\n",
        "sensor: s_ini_lat(lat) 9000\nsensor: s_ini_lon(lon) 18000\nsensor: s_water_speed(m/s) 1e300\n",
        "sensor: s_water_speed(m/s) -1e308\nsensor: s_water_direction(rad) 1e308\nsensor: m_water_vx(m/s) 1e308\n",
        "sensor: m_avg_speed(m/s) -5\nsensor: u_use_current_correction(nodim) 1\nsensor: m_water_vy(m/s) 1e30\n",
    ];
    let behaviors = [
        "behavior: goto_list\n  b_arg: num_waypoints(nodim) 1e20\n  b_arg: initial_wpt(enum) -7\n  \
         b_arg: wpt_x_0(X) -1e308\n  b_arg: wpt_y_0(X) 69696969\n  b_arg: wpt_x_1(X) 1e300\n  b_arg: wpt_y_1(X) 5419\n",
        "behavior: goto_wpt\n  b_arg: wpt_x(X) -18000\n  b_arg: wpt_y(X) -9000\n  b_arg: when_wpt_dist(m) -1e308\n",
        "behavior: set_heading\n  b_arg: heading_value(X) 1e308\n",
        "behavior: surface\n  b_arg: start_when(enum) 15\n  b_arg: when_wpt_dist(m) -1\n  b_arg: end_action(enum) 2\n\
         behavior: goto_list\n  b_arg: num_waypoints(nodim) 3\n  b_arg: num_legs_to_run(nodim) 2\n  \
         b_arg: wpt_x_0(X) 724.1\n  b_arg: wpt_y_0(X) 5418.1\n",
    ];
    // Mission values are finite (the parser refuses NaN and infinities): the
    // extremes are the largest finite ones.
    let mut flown = 0;
    for sensors in cases {
        for above in behaviors {
            let text = format!(
                "{sensors}behavior: abend\n  b_arg: overdepth(m) 35\n{above}\
                 behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: d_target_depth(m) 20\n  \
                 b_arg: c_target_depth(m) 3\n  b_arg: end_action(enum) 2\n"
            );
            let mission = Mission::parse("hostile.mi", text);
            assert!(!mission.has_errors(), "{}", mission.render_plain());
            let mut sim = Simulation::new(
                &mission,
                Arc::new(SensorList::embedded()),
                None,
                &SimConfig::default(),
            )
            .expect("starts");
            flown += 1;
            for _ in 0..2000 {
                if !sim.step_cycle() {
                    break;
                }
            }
        }
    }
    assert_eq!(flown, 16);
}

#[test]
fn abend_aborts_when_the_waypoint_is_too_far() {
    // The waypoint 1′ north is 1,855 m away: 1,000 m aborts at once, 300 km never.
    let goto = "behavior: goto_wpt\n  b_arg: wpt_x(X) 724.0\n  b_arg: wpt_y(X) 5419.0\n";
    let sensors = "sensor: s_ini_lat(lat) 5418.0\nsensor: s_ini_lon(lon) 724.0\n";
    for (limit, aborts) in [(1000.0, true), (300_000.0, false), (-1.0, false)] {
        let text = format!(
            "{sensors}behavior: abend\n  b_arg: max_wpt_distance(m) {limit}\n{goto}\
             behavior: yo\n  b_arg: start_when(enum) 0\n  b_arg: d_target_depth(m) 20\n  \
             b_arg: c_target_depth(m) 3\n  b_arg: end_action(enum) 2\n"
        );
        let mut sim = start(&Mission::parse("far.mi", text));
        while sim.time() < 600.0 && sim.step_cycle() {}
        let reason = sim.end().map(|end| end.reason);
        if aborts {
            assert_eq!(
                reason,
                Some(EndReason::Aborted(
                    gloc_sim::behaviors::AbortReason::WptTooFar
                ))
            );
            assert_eq!(sim.end().map(|end| end.cycle), Some(0));
        } else {
            assert_eq!(reason, None, "{limit}");
        }
    }
}
