//! The launch attributes VS Code's extension declares are exactly the ones the adapter
//! accepts, so a user never sets an attribute that is silently ignored.

use serde_json::Value;

/// The adapter's own list matches what its launch arguments struct reads: every name
/// deserializes into a field (an unknown name would be ignored by serde).
#[test]
fn every_accepted_attribute_is_read() {
    for name in gloc_dap::LAUNCH_ATTRIBUTES {
        let value = match *name {
            "program" | "mission" | "masterdata" | "profile" => Value::from("x"),
            "stopOnEntry" | "history" => Value::from(true),
            _ => Value::from(5),
        };
        let mut arguments = serde_json::Map::new();
        arguments.insert((*name).to_string(), value.clone());
        let parsed: gloc_dap::session::LaunchArguments =
            serde_json::from_value(Value::Object(arguments)).expect("valid launch arguments");
        let echoed = serde_json::to_value(&parsed).expect("serializable");
        assert_eq!(
            echoed.get(*name),
            Some(&value),
            "`{name}` is not read by the adapter"
        );
    }
}
