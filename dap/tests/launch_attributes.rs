//! The launch attributes VS Code's extension declares are exactly the ones the adapter
//! accepts, so a user never sets an attribute that is silently ignored.

use std::collections::BTreeSet;

use serde_json::Value;

#[test]
fn vscode_launch_attributes_match_the_adapter() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../editors/vscode/package.json"
    );
    let text =
        std::fs::read_to_string(path).unwrap_or_else(|error| panic!("cannot read {path}: {error}"));
    let manifest: Value = serde_json::from_str(&text).expect("package.json is JSON");
    let debugger = manifest["contributes"]["debuggers"]
        .as_array()
        .expect("contributes.debuggers")
        .iter()
        .find(|debugger| debugger["type"] == "gloc")
        .expect("a debugger of type gloc");
    let declared: BTreeSet<&str> = debugger["configurationAttributes"]["launch"]["properties"]
        .as_object()
        .expect("launch properties")
        .keys()
        .map(String::as_str)
        .collect();
    let accepted: BTreeSet<&str> = gloc_dap::LAUNCH_ATTRIBUTES.iter().copied().collect();
    assert_eq!(
        declared, accepted,
        "editors/vscode/package.json vs gloc_dap::LAUNCH_ATTRIBUTES"
    );
    let required = &debugger["configurationAttributes"]["launch"]["required"];
    assert_eq!(required, &serde_json::json!(["program"]));
}

/// The adapter's own list matches what its launch arguments struct reads: every name
/// deserializes into a field (an unknown name would be ignored by serde).
#[test]
fn every_accepted_attribute_is_read() {
    for name in gloc_dap::LAUNCH_ATTRIBUTES {
        let value = match *name {
            "program" | "mission" | "masterdata" | "profile" | "token" | "replay"
            | "sensorCache" => Value::from("x"),
            "stopOnEntry" | "history" => Value::from(true),
            _ => Value::from(5),
        };
        let mut arguments = serde_json::Map::new();
        arguments.insert((*name).to_string(), value.clone());
        let parsed: gloc_dap::launch::LaunchArguments =
            serde_json::from_value(Value::Object(arguments)).expect("valid launch arguments");
        let echoed = serde_json::to_value(&parsed).expect("serializable");
        if *name == "token" {
            // Read, but never written back anywhere.
            assert_eq!(parsed.token.as_deref(), Some("x"));
            assert_eq!(echoed.get("token"), None, "the token is echoed");
            continue;
        }
        assert_eq!(
            echoed.get(*name),
            Some(&value),
            "`{name}` is not read by the adapter"
        );
    }
}
