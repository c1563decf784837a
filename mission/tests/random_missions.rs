//! Random missions and `.ma` files built from the language's own words: loading and
//! checking never panics, and every diagnostic's span (and label) lies in its file.

use std::path::Path;

use gloc_engine::sensors::SensorList;
use gloc_mission::Mission;
use gloc_testsupport::Rng;

const WORDS: &[&str] = &[
    "behavior:",
    "b_arg:",
    "sensor:",
    "yo",
    "surface",
    "abend",
    "goto_list",
    "drift_at_depth",
    "args_from_file(enum)",
    "d_target_depth(m)",
    "c_target_depth(m)",
    "overdepth(m)",
    "overtime(sec)",
    "when_secs(sec)",
    "start_when(enum)",
    "num_waypoints(nodim)",
    "s_water_depth_avg(m)",
    "behavior_name=goto_list",
    "behavior_name=yo",
    "<start:b_arg>",
    "<end:b_arg>",
    "<start:waypoints>",
    "<end:waypoints>",
    "-7032.064",
    "4138.106",
    "10",
    "1",
    "99",
    "-1",
    "1e6",
    "2000",
    "0.5",
    "|",
    "#",
    "é",
    "\t",
    "(",
    ")",
    "1e308",
    "-0",
];

fn text(rng: &mut Rng) -> String {
    let mut out = String::new();
    for _ in 0..rng.below(40) {
        for _ in 0..=rng.below(4) {
            out.push_str(WORDS[rng.below(WORDS.len() as u64) as usize]);
            out.push(' ');
        }
        out.push_str(if rng.below(5) == 0 { "\r\n" } else { "\n" });
    }
    out
}

#[test]
fn random_missions_never_panic_and_spans_stay_in_their_files() {
    let mut rng = Rng::new(24);
    let sensors = SensorList::embedded();
    for _ in 0..2000 {
        let mission_text = text(&mut rng);
        let ma_text = text(&mut rng);
        let mission = Mission::load_with(Path::new("/m/missions/x.mi"), &mut |path: &Path| {
            Ok(if path.ends_with("x.mi") {
                mission_text.clone()
            } else {
                ma_text.clone()
            })
        });
        let checks = mission.check(&sensors);
        for entry in mission.diagnostics.iter().chain(&checks) {
            let source = &mission.sources[entry.file].text;
            let spans = std::iter::once(entry.diagnostic.span)
                .chain(entry.diagnostic.labels.iter().map(|label| label.span));
            for span in spans {
                assert!(
                    span.start <= span.end && span.end as usize <= source.len(),
                    "{span:?} outside {} bytes: {}\n{mission_text}",
                    source.len(),
                    mission.render_one(entry)
                );
            }
        }
        let alone = Mission::parse_args_file("x.ma", ma_text.clone());
        let _ = alone.check(&sensors);
    }
}
