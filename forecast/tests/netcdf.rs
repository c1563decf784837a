//! Currents and bathymetry from NetCDF files the test writes with the
//! `netcdf3` crate's writer (classic format), whose answers are known: a
//! uniform current averaged over the glider's depth range gives the uniform
//! track; a solid-body rotation carries a drifting glider round a circle; a
//! track leaving the grid is an error saying where and when; a GEBCO-style
//! elevation grid gives the water depth, land an error.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gloc_engine::sensors::SensorList;
use gloc_forecast::currents::CurrentField;
use gloc_forecast::fly::{fly, prepare_mission, Flight, FlightPlan, Outside, Start, StopAt, Truth};
use gloc_forecast::netcdf::{read_bathymetry, read_currents, DepthField};
use gloc_forecast::ForecastError;
use gloc_sim::navigation::{degrees_to_nmea, Lmc, Xy};
use gloc_sim::{Mission, SimConfig};
use netcdf3::{DataSet, FileWriter, Version};

/// 2019-08-21T12:00:00Z.
const T0: f64 = 1_566_388_800.0;

fn folder(name: &str) -> PathBuf {
    let folder = std::env::temp_dir().join(format!("gloc-forecast-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).expect("a temporary folder");
    folder
}

/// Writes u, v on time × [depth ×] lat × lon (f64), from `field(t, depth, lat, lon)`.
fn write_currents(
    path: &Path,
    times_hours: &[f64],
    depths: Option<&[f64]>,
    lats: &[f64],
    lons: &[f64],
    field: impl Fn(f64, f64, f64, f64) -> (f64, f64),
) {
    let mut data = DataSet::new();
    data.add_fixed_dim("time", times_hours.len()).expect("dim");
    if let Some(depths) = depths {
        data.add_fixed_dim("depth", depths.len()).expect("dim");
    }
    data.add_fixed_dim("lat", lats.len()).expect("dim");
    data.add_fixed_dim("lon", lons.len()).expect("dim");
    data.add_var_f64("time", &["time"]).expect("var");
    data.add_var_attr_string("time", "units", "hours since 2019-08-21 12:00:00")
        .expect("attr");
    data.add_var_f64("lat", &["lat"]).expect("var");
    data.add_var_attr_string("lat", "units", "degrees_north")
        .expect("attr");
    data.add_var_f64("lon", &["lon"]).expect("var");
    data.add_var_attr_string("lon", "units", "degrees_east")
        .expect("attr");
    let dims: Vec<&str> = match depths {
        Some(_) => {
            data.add_var_f64("depth", &["depth"]).expect("var");
            data.add_var_attr_string("depth", "positive", "down")
                .expect("attr");
            vec!["time", "depth", "lat", "lon"]
        }
        None => vec!["time", "lat", "lon"],
    };
    for (name, standard) in [
        ("uo", "eastward_sea_water_velocity"),
        ("vo", "northward_sea_water_velocity"),
    ] {
        data.add_var_f64(name, &dims).expect("var");
        data.add_var_attr_string(name, "standard_name", standard)
            .expect("attr");
        data.add_var_attr_f64(name, "_FillValue", vec![-9999.0])
            .expect("attr");
    }
    let levels = depths.map_or(vec![0.0], <[f64]>::to_vec);
    let (mut u, mut v) = (Vec::new(), Vec::new());
    for &t in times_hours {
        for &depth in &levels {
            for &lat in lats {
                for &lon in lons {
                    let (east, north) = field(t, depth, lat, lon);
                    u.push(east);
                    v.push(north);
                }
            }
        }
    }
    let mut writer = FileWriter::create_new(path).expect("a new file");
    writer
        .set_def(&data, Version::Classic, 0)
        .expect("the header");
    writer.write_var_f64("time", times_hours).expect("time");
    writer.write_var_f64("lat", lats).expect("lat");
    writer.write_var_f64("lon", lons).expect("lon");
    if let Some(depths) = depths {
        writer.write_var_f64("depth", depths).expect("depth");
    }
    writer.write_var_f64("uo", &u).expect("u");
    writer.write_var_f64("vo", &v).expect("v");
    writer.close().expect("closed");
}

fn grid(from: f64, to: f64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|i| from + (to - from) * i as f64 / (count - 1) as f64)
        .collect()
}

fn start_at(lat: f64, lon: f64) -> Start {
    Start {
        time: T0,
        lat: degrees_to_nmea(lat),
        lon: degrees_to_nmea(lon),
        believed: Xy::ZERO,
        avg_speed: None,
        waypoint: None,
        timers_elapsed: 0.0,
        amp_hours: None,
        battery: None,
        battery_capacity: None,
        heading: None,
    }
}

fn plan(hours: f64) -> FlightPlan {
    FlightPlan {
        seconds: hours * 3600.0,
        record_every: 60.0,
        stop_at_first_fix: StopAt::Horizon,
        outside: Outside::Fail,
    }
}

fn comet_mission() -> Mission {
    Mission::load(&gloc_testsupport::data("comet/missions/nsb3.mi"))
}

#[test]
fn a_uniform_current_averaged_over_the_glider_s_depths_flies_the_uniform_track() {
    let folder = folder("uniform");
    let path = folder.join("uniform.nc");
    // Levels 0, 10, 20, 100 m; the glider flies 5–30 m: levels 10 and 20
    // average to (0.2 + 0.4)/2 = 0.3 east and (−0.1 − 0.3)/2 = −0.2 north.
    let depths = [0.0, 10.0, 20.0, 100.0];
    write_currents(
        &path,
        &[0.0, 6.0, 12.0],
        Some(&depths),
        &grid(54.0, 54.8, 5),
        &grid(6.8, 7.8, 6),
        |_, depth, _, _| match depth as i64 {
            0 => (1.0, -1.0),
            10 => (0.2, -0.1),
            20 => (0.4, -0.3),
            _ => (5.0, 2.0),
        },
    );
    let field = read_currents(&path, Some((5.0, 30.0))).expect("readable");
    assert_eq!(field.levels, vec![10.0, 20.0]);
    let water = field.at(T0 + 3.3 * 3600.0, 54.317, 7.123).expect("inside");
    assert!(
        (water.x - 0.3).abs() < 1e-12 && (water.y + 0.2).abs() < 1e-12,
        "{water:?}"
    );

    let start = start_at(54.3, 7.36);
    let mission = prepare_mission(&comet_mission(), &start);
    let sensors = Arc::new(SensorList::embedded());
    let config = SimConfig::default();
    let from_file = fly(
        &mission,
        &sensors,
        &config,
        &start,
        &Truth::Field(Arc::new(field), Xy::ZERO),
        None,
        &plan(6.0),
    )
    .expect("flies");
    let uniform = fly(
        &mission,
        &sensors,
        &config,
        &start,
        &Truth::Uniform(Xy::new(0.3, -0.2)),
        None,
        &plan(6.0),
    )
    .expect("flies");
    assert_eq!(from_file.points.len(), uniform.points.len());
    let lmc = start.lmc();
    let worst = from_file
        .points
        .iter()
        .zip(&uniform.points)
        .map(|(a, b)| lmc.to_xy(a.lat, a.lon).distance(lmc.to_xy(b.lat, b.lon)))
        .fold(0.0, f64::max);
    assert!(worst < 0.01, "{worst} m apart");
    assert!(!from_file.surfacings.is_empty());
}

#[test]
fn a_solid_body_rotation_carries_a_drifting_glider_round_its_circle() {
    let folder = folder("rotation");
    let path = folder.join("rotation.nc");
    // One turn in 12 hours about 54.3° N 7.3° E: u = −ω·north, v = ω·east
    // (metres from the centre, linear in latitude and longitude, so the
    // grid's bilinear interpolation is exact).
    let (lat_c, lon_c) = (54.3, 7.3);
    let centre = Lmc::new(lat_c, lon_c);
    let omega = std::f64::consts::TAU / (12.0 * 3600.0);
    let metres = |lat: f64, lon: f64| centre.to_xy(lat, lon);
    write_currents(
        &path,
        &[0.0, 8.0],
        None,
        &grid(54.2, 54.4, 9),
        &grid(7.1, 7.5, 9),
        |_, _, lat, lon| {
            let at = metres(lat, lon);
            (-omega * at.y, omega * at.x)
        },
    );
    let field = read_currents(&path, None).expect("readable");
    // Start 3 km east of the centre: 0.436 m/s north at first.
    let (lat0, lon0) = centre.to_lat_lon(Xy::new(3000.0, 0.0));
    let water = field.at(T0, lat0, lon0).expect("inside");
    assert!(
        (water.x).abs() < 1e-9 && (water.y - omega * 3000.0).abs() < 1e-9,
        "{water:?}"
    );
    // A glider that never dives (abend and a passive behavior): it drifts.
    let drifter = Mission::parse(
        "drift.mi",
        "behavior: abend\n  b_arg: overdepth(m) 35\nbehavior: sensors_in\n",
    );
    assert!(!drifter.has_errors(), "{}", drifter.render_plain());
    let start = start_at(lat0, lon0);
    let track = fly(
        &prepare_mission(&drifter, &start),
        &Arc::new(SensorList::embedded()),
        &SimConfig::default(),
        &start,
        &Truth::Field(Arc::new(field), Xy::ZERO),
        None,
        &plan(6.0),
    )
    .expect("flies");
    let mut worst: f64 = 0.0;
    for point in &track.points {
        let angle = omega * (point.time - T0);
        let expected = Xy::new(3000.0 * angle.cos(), 3000.0 * angle.sin());
        worst = worst.max(metres(point.lat, point.lon).distance(expected));
    }
    // After half a turn the drifter is 3 km west of the centre; forward Euler
    // over 4.5 s cycles grows the radius by about 0.1 % (3 m).
    let last = track.points.last().expect("points");
    let end = metres(last.lat, last.lon);
    assert!(
        (end.x + 3000.0).abs() < 15.0 && end.y.abs() < 15.0,
        "{end:?}"
    );
    assert!(worst < 15.0, "worst {worst:.1} m from the circle");
}

#[test]
fn leaving_the_grid_is_an_error_saying_where_and_when() {
    let folder = folder("leave");
    let path = folder.join("small.nc");
    // 0.5 m/s east; the grid ends 0.02° (1.3 km) east of the start.
    write_currents(
        &path,
        &[0.0, 12.0],
        None,
        &grid(54.2, 54.4, 3),
        &grid(7.3, 7.32, 3),
        |_, _, _, _| (0.5, 0.0),
    );
    let field = read_currents(&path, None).expect("readable");
    let drifter = Mission::parse(
        "drift.mi",
        "behavior: abend\n  b_arg: overdepth(m) 35\nbehavior: sensors_in\n",
    );
    let start = start_at(54.3, 7.3);
    let error = fly(
        &prepare_mission(&drifter, &start),
        &Arc::new(SensorList::embedded()),
        &SimConfig::default(),
        &start,
        &Truth::Field(Arc::new(field), Xy::ZERO),
        None,
        &plan(3.0),
    )
    .expect_err("leaves the grid");
    let ForecastError::Currents(message) = error else {
        panic!("{error}");
    };
    // 1,300 m at 0.5 m/s: about 2,600 s after 12:00, at 7.32° E.
    assert!(message.contains("leaves the currents"), "{message}");
    assert!(message.contains("outside its longitudes"), "{message}");
    assert!(message.contains("2019-08-21T12:4"), "{message}");
    assert!(message.contains("54.3000° N, 7.320"), "{message}");
}

#[test]
fn a_gebco_elevation_grid_gives_the_water_depth_and_land_is_an_error() {
    let folder = folder("gebco");
    let path = folder.join("gebco.nc");
    let lats = grid(54.0, 54.5, 6);
    let lons = grid(7.0, 7.5, 6);
    let mut data = DataSet::new();
    data.add_fixed_dim("lat", lats.len()).expect("dim");
    data.add_fixed_dim("lon", lons.len()).expect("dim");
    data.add_var_f64("lat", &["lat"]).expect("var");
    data.add_var_attr_string("lat", "units", "degrees_north")
        .expect("attr");
    data.add_var_f64("lon", &["lon"]).expect("var");
    data.add_var_attr_string("lon", "units", "degrees_east")
        .expect("attr");
    data.add_var_i16("elevation", &["lat", "lon"]).expect("var");
    // Elevation −20 m at 7.0° E deepening 10 m per 0.1°; land (+5 m) in the
    // north-east corner cell.
    let mut elevation = Vec::new();
    for (y, _) in lats.iter().enumerate() {
        for (x, lon) in lons.iter().enumerate() {
            let value = if y == 5 && x == 5 {
                5.0
            } else {
                -20.0 - (lon - 7.0) * 100.0
            };
            elevation.push(value.round() as i16);
        }
    }
    let mut writer = FileWriter::create_new(&path).expect("a new file");
    writer
        .set_def(&data, Version::Classic, 0)
        .expect("the header");
    writer.write_var_f64("lat", &lats).expect("lat");
    writer.write_var_f64("lon", &lons).expect("lon");
    writer
        .write_var_i16("elevation", &elevation)
        .expect("elevation");
    writer.close().expect("closed");
    let bathymetry = read_bathymetry(&path).expect("readable");
    // 7.25° E: 20 + 25 = 45 m, anywhere south of the land cell.
    let depth = bathymetry.depth_at(T0, 54.13, 7.25).expect("at sea");
    assert!((depth - 45.0).abs() < 1e-9, "{depth}");
    let error = bathymetry.depth_at(T0, 54.5, 7.5).expect_err("land");
    assert!(
        error.contains("reaches land") && error.contains("54.5000° N, 7.5000° E"),
        "{error}"
    );
    let error = bathymetry
        .depth_at(T0, 53.9, 7.2)
        .expect_err("off the grid");
    assert!(error.contains("leaves the bathymetry"), "{error}");
    // A forecast over it flies (the yo turns at the grid's depth).
    let start = start_at(54.2, 7.3);
    let mission = prepare_mission(&comet_mission(), &start);
    let shared: Arc<dyn DepthField> = Arc::new(bathymetry);
    let track = fly(
        &mission,
        &Arc::new(SensorList::embedded()),
        &SimConfig::default(),
        &start,
        &Truth::Uniform(Xy::ZERO),
        Some(&shared),
        &plan(2.0),
    )
    .expect("flies");
    let deepest = track.points.iter().map(|p| p.depth).fold(0.0, f64::max);
    assert!(deepest > 10.0 && deepest < 50.0, "{deepest}");
}

#[test]
fn netcdf4_and_garbage_are_refused_with_what_to_do() {
    let folder = folder("refuse");
    let hdf = folder.join("model.nc");
    std::fs::write(&hdf, b"\x89HDF\r\n\x1a\n rest").expect("write");
    let error = read_currents(&hdf, None).expect_err("NetCDF-4");
    assert!(error.contains("nccopy -k classic"), "{error}");
    let junk = folder.join("junk.nc");
    std::fs::write(&junk, b"CDF\x01\xff\xff\xff\xff\xff\xff").expect("write");
    assert!(read_currents(&junk, None).is_err());
    let text = folder.join("text.nc");
    std::fs::write(&text, b"time,u,v\n").expect("write");
    assert!(read_currents(&text, None)
        .expect_err("not NetCDF")
        .contains("not a NetCDF file"));
}

#[test]
fn damaged_netcdf_files_are_errors_not_panics() {
    let folder = folder("damaged");
    let path = folder.join("good.nc");
    write_currents(
        &path,
        &[0.0, 6.0],
        Some(&[0.0, 10.0]),
        &grid(54.0, 54.4, 3),
        &grid(7.0, 7.4, 3),
        |_, _, _, _| (0.1, 0.2),
    );
    let good = std::fs::read(&path).expect("written");
    let mut rng = gloc_testsupport::Rng::new(2026);
    let damaged = folder.join("damaged.nc");
    let mut refused = 0;
    for round in 0..400 {
        let mut bytes = good.clone();
        match round % 3 {
            // Flip bytes, mostly in the header where the sizes are.
            0 | 1 => {
                for _ in 0..1 + rng.index(4) {
                    let at =
                        rng.index(
                            bytes
                                .len()
                                .min(if round % 3 == 0 { 400 } else { bytes.len() }),
                        );
                    bytes[at] = rng.next_u64() as u8;
                }
            }
            _ => bytes.truncate(rng.index(bytes.len())),
        }
        std::fs::write(&damaged, &bytes).expect("write");
        // Either a field or an error; never a panic, never a hang.
        if read_currents(&damaged, Some((5.0, 30.0))).is_err() {
            refused += 1;
        }
        let _ = read_bathymetry(&damaged);
    }
    assert!(refused > 100, "{refused}");
}

#[test]
fn ensemble_members_that_leave_the_grid_stop_there_and_are_reported() {
    use gloc_forecast::ensemble::{run_ensemble, EnsembleInput, EnsembleOptions};
    let folder = folder("members");
    let path = folder.join("narrow.nc");
    // A calm grid 0.04° (2.6 km) wide around the start; members drift with
    // σ 0.3 m/s east and north: most leave it within three hours.
    write_currents(
        &path,
        &[0.0, 12.0],
        None,
        &grid(54.2, 54.4, 3),
        &grid(7.33, 7.37, 3),
        |_, _, _, _| (0.0, 0.0),
    );
    let field: Arc<dyn gloc_forecast::currents::CurrentField> =
        Arc::new(read_currents(&path, None).expect("readable"));
    let drifter = Mission::parse(
        "drift.mi",
        "behavior: abend\n  b_arg: overdepth(m) 35\nbehavior: sensors_in\n",
    );
    let start = start_at(54.3, 7.35);
    let prepared = prepare_mission(&drifter, &start);
    let truth = Truth::Field(field, Xy::ZERO);
    let sensors = Arc::new(SensorList::embedded());
    let config = SimConfig::default();
    let input = EnsembleInput {
        flight: Flight {
            mission: &prepared,
            sensors: &sensors,
            config: &config,
            start: &start,
            truth: &truth,
            bathymetry: None,
        },
        hours: 3.0,
    };
    let options = EnsembleOptions {
        members: 20,
        seed: 4,
        spread: Xy::new(0.3, 0.3),
        threads: 2,
    };
    let ensemble = run_ensemble(&input, &options).expect("the ensemble flies");
    assert!(!ensemble.left_grid.is_empty());
    assert!(ensemble
        .left_grid
        .iter()
        .all(|(_, message)| message.contains("leaves the currents")));
    // A member that left is missing from the later regions, never from the earlier ones.
    let counts: Vec<usize> = ensemble.regions.iter().map(|r| r.members).collect();
    assert!(counts.windows(2).all(|w| w[1] <= w[0]), "{counts:?}");
    assert_eq!(
        counts.last().copied().unwrap_or(0) + ensemble.left_grid.len(),
        20,
        "{counts:?}"
    );
}
