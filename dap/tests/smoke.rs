mod support;
use serde_json::json;
use support::Client;

#[test]
fn smoke() {
    let mut client = Client::start();
    client.ok("initialize", json!({"adapterID":"gloc"}));
    let program = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/fig3.gbas");
    client.ok("launch", json!({"program": program, "stopOnEntry": true}));
    client.event("initialized");
    client.ok("configurationDone", json!({}));
    println!("{}", client.event("stopped"));
    println!("{}", client.ok("stackTrace", json!({"threadId":1})));
    println!("{}", client.ok("scopes", json!({"frameId":1})));
    for r in 1..=4 { println!("{}", client.ok("variables", json!({"variablesReference": r}))); }
    client.ok("next", json!({"threadId":1}));
    println!("{}", client.event("stopped"));
    println!("{}", client.ok("stackTrace", json!({"threadId":1})));
    println!("{}", client.ok("variables", json!({"variablesReference": 4})));
    client.ok("setBreakpoints", json!({"source":{"path":program},"breakpoints":[{"line":3}]}));
    client.ok("continue", json!({"threadId":1}));
    println!("{}", client.event("stopped"));
    println!("{}", client.ok("stackTrace", json!({"threadId":1})));
    println!("{}", client.ok("variables", json!({"variablesReference": 4})));
    println!("{}", client.ok("variables", json!({"variablesReference": 3})));
    client.ok("stepBack", json!({"threadId":1}));
    println!("{}", client.event("stopped"));
    println!("{}", client.ok("stackTrace", json!({"threadId":1})));
    println!("{}", client.ok("disassemble", json!({"memoryReference":"0x0","instructionCount":30})));
    client.ok("setBreakpoints", json!({"source":{"path":program},"breakpoints":[]}));
    client.ok("continue", json!({"threadId":1}));
    loop { let m = client.next_message(); println!("{m}"); if m["event"]=="terminated" {break;} }
    client.request("disconnect", None);
}
