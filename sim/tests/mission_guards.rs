//! The mission checked against the sensor list and the script: S0106 (a `sensor:`
//! setting the list lacks, caret on the name) and S0107 (the script stores
//! `sci_ruhp_behs` but the mission has no hook behavior). On comet's real mission
//! `nsb3.mi` (data/): its `sensor:` lines were compared with the embedded
//! list by hand (only line 12, `u_sci_dbd_sensor_list_xmit_control`, is missing), and
//! it has no `behavior: hook`.

use std::sync::Arc;

use gloc_engine::gloc::{self, CheckOptions};
use gloc_engine::program::{Pc, Program};
use gloc_engine::sensors::SensorList;
use gloc_sim::{default_mission, Mission};

const FIG2: &str = include_str!("../../examples/fig2.gloc");

fn fig2(list: &SensorList) -> Arc<Program> {
    gloc::check(&gloc::parse(FIG2), list, &CheckOptions::default())
        .program
        .expect("Fig. 2 checks")
}

fn nsb3() -> Mission {
    let path = gloc_testsupport::data("comet/missions/nsb3.mi");
    let mission = Mission::load(&path);
    assert!(!mission.has_errors(), "{}", mission.render_plain());
    mission
}

#[test]
fn a_sensor_setting_the_list_lacks_has_a_code_and_points_at_the_name() {
    let mission = nsb3();
    let list = SensorList::embedded();
    let found: Vec<String> = mission
        .check_sensor_settings(&list)
        .iter()
        .map(|entry| mission.render_one(entry))
        .collect();
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].ends_with(
            "nsb3.mi:12:9: warning[S0106]: sensor `u_sci_dbd_sensor_list_xmit_control` is not in \
             the sensor list; the setting is ignored (help: did you mean \
             `u_dbd_sensor_list_xmit_control`?)"
        ),
        "{}",
        found[0]
    );
    // The span is exactly the name (34 characters).
    let entry = &mission.check_sensor_settings(&list)[0];
    assert_eq!(entry.diagnostic.span.end - entry.diagnostic.span.start, 34);
    assert!(default_mission().check_sensor_settings(&list).is_empty());
}

#[test]
fn fig2_flown_with_a_mission_without_a_hook_names_both_stores() {
    let list = SensorList::embedded();
    let program = fig2(&list);
    // Fig. 2's instructions without its labels: the two `stores` are the 6th and
    // the 15th (counted by hand).
    assert_eq!(nsb3().unhooked_stores(&list, &program), [Pc(5), Pc(14)]);
    // Its own mission has `behavior: hook`.
    assert!(default_mission()
        .unhooked_stores(&list, &program)
        .is_empty());
    let spans = [program.span(Pc(5)), program.span(Pc(14))];
    let warning = nsb3().unhooked_store_warning(&spans).expect("a warning");
    assert_eq!(warning.code, "S0107");
    assert_eq!(warning.span, spans[0]);
    assert_eq!(warning.labels.len(), 1);
    assert!(warning.message.contains("has no `behavior: hook`"));
    assert!(nsb3().unhooked_store_warning(&[]).is_none());
}
