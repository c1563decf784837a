//! The debugger's expressions are GBASIC's: a differential test of random well-typed
//! expressions against what the compiled script prints for them, a walk of every
//! `evaluateName` the debugger hands out for the thermocline tracker, and the cases in
//! which the debugger's old evaluator disagreed with the script.

mod support;

use gloc_testsupport::Rng;
use serde_json::{json, Value};
use support::{stopped, Client};

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the workspace")
        .to_path_buf()
}

fn launch(arguments: Value) -> Client {
    let mut client = Client::start();
    client.ok(
        "initialize",
        json!({ "adapterID": "gloc", "linesStartAt1": true }),
    );
    client.ok("launch", arguments);
    client.event("initialized");
    client
}

fn evaluate(client: &mut Client, expression: &str) -> Value {
    client.request(
        "evaluate",
        Some(json!({ "expression": expression, "frameId": 1, "context": "watch" })),
    )
}

// ---------------------------------------------------------------------------------------
// The differential test

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Ty {
    Integer,
    Float,
}

/// An expression's text, its GBASIC type and how tightly its outermost operator binds
/// (the parser's levels, loosest first: or 1, and 2, not 3, comparison 4, + - 5, mod 6,
/// `\` 7, * / 8, unary minus 9; 10 for a leaf, a call or parentheses).
struct Generated {
    text: String,
    ty: Ty,
    binds: u8,
}

/// Names of the generated script (declared by `script`).
const INTEGERS: &[&str] = &["i1", "i2", "i3", "NI"];
const FLOATS: &[&str] = &["f1", "f2", "f3", "NF"];
const SENSORS: &[&str] = &["m_depth", "m_pitch", "m_present_time", "sci_water_temp"];
const ARRAY_SIZE: u64 = 5;

fn leaf(random: &mut Rng, ty: Ty) -> Generated {
    let text = match (ty, random.below(4)) {
        (Ty::Integer, 0) => random
            .pick(&[
                "0",
                "1",
                "2",
                "3",
                "7",
                "10",
                "255",
                "123456789",
                "9223372036854775807",
            ])
            .to_string(),
        (Ty::Integer, 1) => format!("ia({})", random.below(ARRAY_SIZE)),
        (Ty::Integer, _) => random.pick(INTEGERS).to_string(),
        (Ty::Float, 0) => random
            .pick(&["0.5", "2.25", "0.1", "3.0", "1e3", "1.5e-3", "100.125"])
            .to_string(),
        (Ty::Float, 1) => format!("fa({})", random.below(ARRAY_SIZE)),
        (Ty::Float, 2) => random.pick(SENSORS).to_string(),
        (Ty::Float, _) => random.pick(FLOATS).to_string(),
    };
    Generated {
        text,
        ty,
        binds: 10,
    }
}

/// `part` as an operand of an operator that binds at `binds`: in parentheses unless
/// it binds more tightly, so the text parses as generated.
fn operand(part: Generated, binds: u8) -> String {
    if part.binds > binds {
        part.text
    } else {
        format!("({})", part.text)
    }
}

fn any_ty(random: &mut Rng) -> Ty {
    if random.below(2) == 0 {
        Ty::Integer
    } else {
        Ty::Float
    }
}

/// A well-typed expression of type `ty`, at most `depth` operators deep.
fn generate(random: &mut Rng, ty: Ty, depth: u32) -> Generated {
    if depth == 0 || random.below(5) == 0 {
        return leaf(random, ty);
    }
    let binary =
        |random: &mut Rng, left: Generated, symbol: &str, binds: u8, right: Generated, ty: Ty| {
            Generated {
                text: format!(
                    "{} {symbol} {}",
                    operand(left, binds - 1),
                    operand(right, binds)
                ),
                ty,
                binds,
            }
            .tap(random)
        };
    match ty {
        Ty::Integer => match random.below(9) {
            0..=1 => {
                let symbol = random.pick(&["+", "-", "*"]);
                let binds = if symbol == "*" { 8 } else { 5 };
                let left = generate(random, Ty::Integer, depth - 1);
                let right = generate(random, Ty::Integer, depth - 1);
                binary(random, left, symbol, binds, right, Ty::Integer)
            }
            2 => {
                // `\` and integer `mod` trap on a zero divisor: `abs(x) + 1` is never
                // zero (abs wraps i64::MIN to itself, and + 1 wraps only i64::MAX).
                let symbol = random.pick(&["\\", "mod"]);
                let binds = if symbol == "mod" { 6 } else { 7 };
                let left = generate(random, Ty::Integer, depth - 1);
                let divisor = generate(random, Ty::Integer, depth - 1);
                let right = Generated {
                    text: format!("(abs({}) + 1)", divisor.text),
                    ty: Ty::Integer,
                    binds: 10,
                };
                binary(random, left, symbol, binds, right, Ty::Integer)
            }
            3 => {
                let symbol = random.pick(&["=", "<>", "<", "<=", ">", ">="]);
                let (a, b) = (any_ty(random), any_ty(random));
                let left = generate(random, a, depth - 1);
                let right = generate(random, b, depth - 1);
                binary(random, left, symbol, 4, right, Ty::Integer)
            }
            4 => {
                let symbol = random.pick(&["and", "or"]);
                let binds = if symbol == "and" { 2 } else { 1 };
                let left = generate(random, Ty::Integer, depth - 1);
                let right = generate(random, Ty::Integer, depth - 1);
                binary(random, left, symbol, binds, right, Ty::Integer)
            }
            5 => {
                let inner = generate(random, Ty::Integer, depth - 1);
                Generated {
                    text: format!("not {}", operand(inner, 2)),
                    ty: Ty::Integer,
                    binds: 3,
                }
            }
            6 => {
                let inner = generate(random, Ty::Integer, depth - 1);
                Generated {
                    text: format!("-{}", operand(inner, 8)),
                    ty: Ty::Integer,
                    binds: 9,
                }
            }
            7 => {
                let inner = generate(random, Ty::Float, depth - 1);
                call("int", &[inner], Ty::Integer)
            }
            _ => {
                let name = random.pick(&["abs", "min", "max"]);
                let first = generate(random, Ty::Integer, depth - 1);
                if name == "abs" {
                    call(name, &[first], Ty::Integer)
                } else {
                    let second = generate(random, Ty::Integer, depth - 1);
                    call(name, &[first, second], Ty::Integer)
                }
            }
        },
        Ty::Float => match random.below(7) {
            0..=2 => {
                // At least one float operand makes the operation float.
                let symbol = random.pick(&["+", "-", "*", "mod"]);
                let binds = match symbol {
                    "*" => 8,
                    "mod" => 6,
                    _ => 5,
                };
                let other = any_ty(random);
                let (a, b) = if random.below(2) == 0 {
                    (Ty::Float, other)
                } else {
                    (other, Ty::Float)
                };
                let left = generate(random, a, depth - 1);
                let right = generate(random, b, depth - 1);
                binary(random, left, symbol, binds, right, Ty::Float)
            }
            3 => {
                // `/` is float division whatever its operands.
                let (a, b) = (any_ty(random), any_ty(random));
                let left = generate(random, a, depth - 1);
                let right = generate(random, b, depth - 1);
                binary(random, left, "/", 8, right, Ty::Float)
            }
            4 => {
                let inner = generate(random, Ty::Float, depth - 1);
                Generated {
                    text: format!("-{}", operand(inner, 8)),
                    ty: Ty::Float,
                    binds: 9,
                }
            }
            5 => {
                let name = random.pick(&["sqrt", "float", "abs"]);
                let argument_ty = if name == "abs" {
                    Ty::Float
                } else {
                    any_ty(random)
                };
                let inner = generate(random, argument_ty, depth - 1);
                call(name, &[inner], Ty::Float)
            }
            _ => {
                let name = random.pick(&["min", "max"]);
                let first = generate(random, Ty::Float, depth - 1);
                let other = any_ty(random);
                let second = generate(random, other, depth - 1);
                call(name, &[first, second], Ty::Float)
            }
        },
    }
}

trait Tap {
    fn tap(self, random: &mut Rng) -> Self;
}

impl Tap for Generated {
    /// Sometimes adds parentheses that are not needed, as people write them.
    fn tap(self, random: &mut Rng) -> Generated {
        if random.below(8) == 0 {
            Generated {
                text: format!("({})", self.text),
                binds: 10,
                ..self
            }
        } else {
            self
        }
    }
}

fn call(name: &str, args: &[Generated], ty: Ty) -> Generated {
    let args: Vec<&str> = args.iter().map(|arg| arg.text.as_str()).collect();
    Generated {
        text: format!("{name}({})", args.join(", ")),
        ty,
        binds: 10,
    }
}

/// A GBASIC script that sets its variables from `random`, flies three cycles, then
/// prints each expression; and the 1-based line of the first `print`.
fn script(random: &mut Rng, expressions: &[Generated]) -> (String, usize) {
    let mut lines = vec![
        "' Generated by dap/tests/expressions.rs (the differential test).".to_string(),
        format!("const NI = {}", random.below(100) as i64 - 50),
        format!("const NF = {:?}", (random.below(1000) as f64 - 500.0) / 8.0),
        "dim i1 as integer".into(),
        "dim i2 as integer".into(),
        "dim i3 as integer".into(),
        "dim f1 as float".into(),
        "dim f2 as float".into(),
        "dim f3 as float".into(),
        format!("dim ia({ARRAY_SIZE}) as integer"),
        format!("dim fa({ARRAY_SIZE}) as float"),
        "dim k as integer".into(),
        format!("i1 = {}", random.below(20) as i64 - 10),
        format!("i2 = {}", random.below(2000) as i64 - 1000),
        "i3 = -9223372036854775807 - 1".into(),
        format!("f1 = {:?}", (random.below(200) as f64 - 100.0) / 4.0),
        format!("f2 = {:?}", random.below(1000) as f64 / 3.0),
        "f3 = -0.0".into(),
        format!("for k = 0 to {}", ARRAY_SIZE - 1),
        format!("  ia(k) = k * {} - 4", random.below(7)),
        "next".into(),
        // fa's last cell is never written: it holds integer 0, read as 0.0.
        format!("for k = 0 to {}", ARRAY_SIZE - 2),
        format!("  fa(k) = k * {:?} - 2.0", random.below(16) as f64 / 4.0),
        "next".into(),
        "for k = 1 to 3".into(),
        "  yield".into(),
        "next".into(),
    ];
    let first_print = lines.len() + 1;
    for expression in expressions {
        lines.push(format!("print {}", expression.text));
    }
    lines.extend(["label: done".into(), "yield".into(), "goto done".into()]);
    (lines.join("\n") + "\n", first_print)
}

#[test]
fn random_expressions_evaluate_to_what_the_compiled_script_prints() {
    const COUNT: usize = 600;
    let mut random = Rng::new(0x00c0_ffee_2026_1124);
    let expressions: Vec<Generated> = (0..COUNT)
        .map(|_| {
            let ty = any_ty(&mut random);
            generate(&mut random, ty, 4)
        })
        .collect();
    let (text, first_print) = script(&mut random, &expressions);
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("differential.gbas");
    std::fs::write(&path, &text).expect("write the generated script");
    let mut client = launch(json!({ "program": path, "cycleBudget": 1_000_000 }));
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": path }, "breakpoints": [{ "line": first_print }] }),
    );
    assert_eq!(body["breakpoints"][0]["verified"], true, "{body}");
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let evaluated: Vec<(String, String)> = expressions
        .iter()
        .map(|expression| {
            let response = evaluate(&mut client, &expression.text);
            assert_eq!(response["success"], true, "{}: {response}", expression.text);
            let body = &response["body"];
            (
                body["result"].as_str().unwrap_or_default().to_string(),
                body["type"].as_str().unwrap_or_default().to_string(),
            )
        })
        .collect();
    // Run the prints: the script's share of this cycle ends after the last one.
    client.ok("stepOut", json!({ "threadId": 1 }));
    stopped(&mut client);
    let printed: Vec<String> = client
        .received
        .iter()
        .filter(|message| message["event"] == "output" && message["body"]["category"] == "stdout")
        .flat_map(|message| {
            message["body"]["output"]
                .as_str()
                .unwrap_or_default()
                .lines()
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(printed.len(), COUNT, "{printed:?}");
    let mut floats = 0;
    for ((expression, (result, ty)), printed) in expressions.iter().zip(&evaluated).zip(&printed) {
        assert_eq!(
            result, printed,
            "`{}`: the debugger says {result}, the script printed {printed}",
            expression.text
        );
        let expected_ty = match expression.ty {
            Ty::Integer => "integer",
            Ty::Float => "float",
        };
        assert_eq!(ty, expected_ty, "`{}`", expression.text);
        floats += usize::from(expression.ty == Ty::Float);
    }
    // Both types well represented, and deep expressions among them.
    assert!(
        floats > COUNT / 4 && floats < COUNT * 3 / 4,
        "{floats} floats"
    );
    let operators = expressions
        .iter()
        .filter(|expression| expression.text.matches('(').count() >= 3)
        .count();
    assert!(operators > COUNT / 4, "{operators} nested expressions");
}

// ---------------------------------------------------------------------------------------
// Every evaluateName of the thermocline tracker

/// Every variable of `reference` and of the containers under it, as (evaluateName,
/// value), following `variablesReference`s (arrays, "All sensors").
fn walk(client: &mut Client, reference: i64, found: &mut Vec<(String, String, String)>) {
    let body = client.ok("variables", json!({ "variablesReference": reference }));
    for variable in body["variables"].as_array().expect("variables").clone() {
        if let Some(name) = variable["evaluateName"].as_str() {
            found.push((
                name.to_string(),
                variable["value"].as_str().unwrap_or_default().to_string(),
                variable["name"].as_str().unwrap_or_default().to_string(),
            ));
        }
        let child = variable["variablesReference"].as_i64().unwrap_or(0);
        if child > 0 {
            walk(client, child, found);
        }
    }
}

fn walk_every_scope(client: &mut Client) -> Vec<(String, String, String)> {
    let body = client.ok("scopes", json!({ "frameId": 1 }));
    let mut found = Vec::new();
    for scope in body["scopes"].as_array().expect("scopes").clone() {
        walk(
            client,
            scope["variablesReference"].as_i64().expect("reference"),
            &mut found,
        );
    }
    found
}

fn every_evaluate_name_evaluates(client: &mut Client, stop: &str) -> usize {
    let found = walk_every_scope(client);
    for (expression, shown, name) in &found {
        let response = evaluate(client, expression);
        assert_eq!(
            response["success"], true,
            "{stop}: `{expression}` (for `{name}`) does not evaluate: {response}"
        );
        assert_eq!(
            response["body"]["result"].as_str(),
            Some(shown.as_str()),
            "{stop}: `{expression}` (for `{name}`)"
        );
    }
    found.len()
}

#[test]
fn every_evaluate_name_of_the_thermocline_tracker_evaluates_to_its_value() {
    let root = root();
    let program = root.join("examples/thermocline.gbas");
    let mut client = launch(json!({
        "program": program,
        "mission": root.join("examples/thermocline.mi"),
        "stopOnEntry": true,
    }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let at_entry = every_evaluate_name_evaluates(&mut client, "entry");
    let names: Vec<String> = walk_every_scope(&mut client)
        .into_iter()
        .map(|(name, _, _)| name)
        .collect();
    // What the issue found unevaluable: arrays, elements, constants, Vehicle entries.
    for expected in [
        "tsum", "tsum(3)", "grad(44)", "DIVE", "NBINS", "MARGIN", "m_depth", "r0",
    ] {
        assert!(
            names.iter().any(|name| name == expected),
            "`{expected}` is not handed out: {names:?}"
        );
    }
    // The Vehicle entries the simulator writes to sensors are named by them.
    let vehicle = client.ok(
        "variables",
        json!({ "variablesReference": support::VEHICLE }),
    );
    let named: Vec<(String, String)> = vehicle["variables"]
        .as_array()
        .expect("variables")
        .iter()
        .filter_map(|variable| {
            Some((
                variable["name"].as_str()?.to_string(),
                variable["evaluateName"].as_str()?.to_string(),
            ))
        })
        .collect();
    let expected = [
        ("m_present_time", "m_present_time"),
        ("depth (m)", "m_depth"),
        ("pitch (rad)", "m_pitch"),
        ("water depth (m)", "m_water_depth"),
    ]
    .map(|(name, sensor)| (name.to_string(), sensor.to_string()));
    assert_eq!(named, expected);
    // The sensors of the list (1389), the script's 21 variables, 45 × 4 elements,
    // 7 constants, registers and the Vehicle entries named by their sensors.
    assert!(at_entry > 1389 + 22 + 180 + 7, "{at_entry}");
    // Inside the script, at the first leg's end, when the bins hold samples.
    client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [{ "line": 80 }] }),
    );
    client.ok("continue", json!({ "threadId": 1 }));
    stopped(&mut client);
    every_evaluate_name_evaluates(&mut client, "line 80");
    let average = evaluate(&mut client, "tsum(i) / tcount(i)");
    assert_eq!(average["body"]["type"], "float", "{average}");
    // At a cycle boundary, after the vehicle moved.
    client.ok(
        "setBreakpoints",
        json!({ "source": { "path": program }, "breakpoints": [] }),
    );
    client.ok("next", json!({ "threadId": 1 }));
    stopped(&mut client);
    every_evaluate_name_evaluates(&mut client, "next boundary");
}

#[test]
fn every_evaluate_name_of_a_replayed_deployment_evaluates_to_its_value() {
    // comet's real logs (data/): the Vehicle scope shows recorded sensors.
    let shared = gloc_testsupport::data("");
    let logs = shared.join("comet/from-glider/comet-2019-222-02-154");
    let mut client = Client::start();
    client.ok(
        "initialize",
        json!({ "adapterID": "gloc", "linesStartAt1": true }),
    );
    client.ok(
        "launch",
        json!({
            "program": root().join("dap/tests/fixtures/fig3.gbas"),
            "replay": [logs.with_extension("dbd"), logs.with_extension("ebd")],
            "sensorCache": shared.join("cac"),
        }),
    );
    client.event("initialized");
    client.ok(
        "setFunctionBreakpoints",
        json!({ "breakpoints": [{ "name": "cycle 40" }] }),
    );
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let count = every_evaluate_name_evaluates(&mut client, "replay cycle 40");
    let names: Vec<String> = walk_every_scope(&mut client)
        .into_iter()
        .map(|(name, _, _)| name)
        .collect();
    for expected in ["m_depth", "m_pitch", "sci_water_temp", "state1"] {
        let handed_out = names.iter().any(|name| name == expected);
        // `state1` is a label of fig3.gbas, not a value: never handed out.
        assert_eq!(handed_out, expected != "state1", "`{expected}`: {names:?}");
    }
    assert!(count > 100, "{count}");
}

// ---------------------------------------------------------------------------------------
// The cases found: the old evaluator's rules against the script's

#[test]
fn the_debugger_computes_as_the_script_does() {
    let root = root();
    let mut client = launch(json!({
        "program": root.join("examples/thermocline.gbas"),
        "mission": root.join("examples/thermocline.mi"),
        "stopOnEntry": true,
    }));
    client.ok("configurationDone", json!({}));
    stopped(&mut client);
    let result = |client: &mut Client, expression: &str| {
        let response = evaluate(client, expression);
        assert_eq!(response["success"], true, "{expression}: {response}");
        (
            response["body"]["result"]
                .as_str()
                .unwrap_or_default()
                .to_string(),
            response["body"]["type"]
                .as_str()
                .unwrap_or_default()
                .to_string(),
        )
    };
    // GBASIC's `/` is float division; the old evaluator gave 3.
    assert_eq!(result(&mut client, "7 / 2"), ("3.5".into(), "float".into()));
    // `\` is integer division; the old evaluator refused it.
    assert_eq!(
        result(&mut client, "7 \\ 2"),
        ("3".into(), "integer".into())
    );
    // `mod` binds looser than `*`: 7 mod (2 * 3), not (7 mod 2) * 3 = 3.
    assert_eq!(
        result(&mut client, "7 mod 2 * 3"),
        ("1".into(), "integer".into())
    );
    assert_eq!(
        result(&mut client, "NBINS mod 10"),
        ("5".into(), "integer".into())
    );
    // C's operators are refused, with the column and GBASIC's word.
    let refused = |client: &mut Client, expression: &str| {
        let response = evaluate(client, expression);
        assert_eq!(response["success"], false, "{expression}: {response}");
        response["message"].as_str().unwrap_or_default().to_string()
    };
    let message = refused(&mut client, "leg = DIVE && bin > 0");
    assert!(
        message.contains("column 12") && message.contains("`and`"),
        "{message}"
    );
    assert!(refused(&mut client, "NBINS % 10").contains("`mod`"));
    assert!(refused(&mut client, "!leg").contains("`not`"));
    // A condition that could not compile in the script is refused at setBreakpoints.
    let body = client.ok(
        "setBreakpoints",
        json!({ "source": { "path": root.join("examples/thermocline.gbas") }, "breakpoints": [
            { "line": 80, "condition": "i > 3 && tcount(i) > 0" },
            { "line": 80, "condition": "m_depth \\ 2 = 1" },
            { "line": 80, "condition": "i > 3 and tcount(i) > 0" }
        ] }),
    );
    let breakpoints = body["breakpoints"].as_array().expect("breakpoints");
    assert_eq!(breakpoints[0]["verified"], false);
    assert_eq!(breakpoints[1]["verified"], false);
    let message = breakpoints[1]["message"].as_str().unwrap_or_default();
    assert!(
        message.contains("integer division") && message.contains("column 1"),
        "{message}"
    );
    assert_eq!(breakpoints[2]["verified"], true, "{}", breakpoints[2]);
    // setVariable takes a GBASIC expression and keeps the variable's type.
    let set = client.ok(
        "setVariable",
        json!({ "variablesReference": 1, "name": "bin", "value": "NBINS \\ 2" }),
    );
    assert_eq!(set["value"], "22");
    let response = client.request(
        "setVariable",
        Some(json!({ "variablesReference": 1, "name": "bin", "value": "7 / 2" })),
    );
    assert_eq!(response["success"], false, "{response}");
    let set = client.ok(
        "setVariable",
        json!({ "variablesReference": 1, "name": "mean", "value": "7 \\ 2" }),
    );
    assert_eq!(set["value"], "3.0");
    let response = client.request(
        "setVariable",
        Some(json!({ "variablesReference": 1, "name": "DIVE", "value": "1" })),
    );
    assert_eq!(response["success"], false, "{response}");
    // A sensor set by hand no longer holds the vehicle's depth: the Vehicle entry keeps
    // showing the vehicle's and hands out no evaluateName that would give another value.
    let set = client.ok(
        "setVariable",
        json!({ "variablesReference": support::SENSORS, "name": "m_depth", "value": "NBINS + 0.5" }),
    );
    assert_eq!(set["value"], "45.5");
    let vehicle = client.ok(
        "variables",
        json!({ "variablesReference": support::VEHICLE }),
    );
    let depth = vehicle["variables"]
        .as_array()
        .expect("variables")
        .iter()
        .find(|variable| variable["name"] == "depth (m)")
        .expect("depth")
        .clone();
    assert_ne!(depth["value"], "45.5", "{depth}");
    assert!(depth.get("evaluateName").is_none(), "{depth}");
}
