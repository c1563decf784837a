//! A small Draft-04 JSON-schema validator, enough for the official DAP schema: `$ref`,
//! `allOf`, `oneOf`, `type`, `properties`, `required`, `additionalProperties`, `enum`,
//! `items`, `minimum`, `maximum`. Written here rather than pulling the `jsonschema` crate
//! (about 80 crates to build on a shared 2-core machine) for the handful of keywords the
//! DAP schema actually uses; an unknown keyword other than annotations fails loudly.

use serde_json::Value;

pub struct Schema {
    root: Value,
}

const ANNOTATIONS: &[&str] = &[
    "description",
    "title",
    "format",
    "_enum",
    "enumDescriptions",
    "$schema",
    "definitions",
    "default",
];

impl Schema {
    pub fn dap() -> Schema {
        let text = include_str!("../schema/debugAdapterProtocol.json");
        Schema {
            root: serde_json::from_str(text).expect("the bundled DAP schema is JSON"),
        }
    }

    pub fn has_definition(&self, name: &str) -> bool {
        self.root["definitions"].get(name).is_some()
    }

    /// Validates `value` against `#/definitions/<name>`; the errors name the JSON path.
    pub fn validate(&self, name: &str, value: &Value) -> Vec<String> {
        let mut errors = Vec::new();
        let schema = &self.root["definitions"][name];
        assert!(!schema.is_null(), "no definition {name} in the schema");
        self.check(schema, value, "$", &mut errors);
        errors
    }

    fn resolve<'a>(&'a self, reference: &str) -> &'a Value {
        let name = reference
            .strip_prefix("#/definitions/")
            .unwrap_or_else(|| panic!("unsupported $ref {reference}"));
        &self.root["definitions"][name]
    }

    fn check(&self, schema: &Value, value: &Value, path: &str, errors: &mut Vec<String>) {
        let Some(object) = schema.as_object() else {
            return;
        };
        for (keyword, argument) in object {
            match keyword.as_str() {
                "$ref" => {
                    let target = self.resolve(argument.as_str().expect("$ref is a string"));
                    self.check(target, value, path, errors);
                }
                "allOf" => {
                    for part in argument.as_array().expect("allOf is an array") {
                        self.check(part, value, path, errors);
                    }
                }
                "oneOf" => {
                    let matching = argument
                        .as_array()
                        .expect("oneOf is an array")
                        .iter()
                        .filter(|part| {
                            let mut inner = Vec::new();
                            self.check(part, value, path, &mut inner);
                            inner.is_empty()
                        })
                        .count();
                    if matching != 1 {
                        errors.push(format!("{path}: matches {matching} oneOf branches, not 1"));
                    }
                }
                "type" => {
                    let allowed: Vec<&str> = match argument {
                        Value::String(name) => vec![name.as_str()],
                        Value::Array(names) => names.iter().filter_map(Value::as_str).collect(),
                        _ => panic!("bad type keyword"),
                    };
                    if !allowed.iter().any(|ty| has_type(value, ty)) {
                        errors.push(format!("{path}: {value} is not of type {allowed:?}"));
                    }
                }
                "properties" => {
                    if let Some(fields) = value.as_object() {
                        for (name, sub) in argument.as_object().expect("properties is an object") {
                            if let Some(field) = fields.get(name) {
                                self.check(sub, field, &format!("{path}.{name}"), errors);
                            }
                        }
                    }
                }
                "required" => {
                    if let Some(fields) = value.as_object() {
                        for name in argument.as_array().expect("required is an array") {
                            let name = name.as_str().expect("required names are strings");
                            if !fields.contains_key(name) {
                                errors.push(format!("{path}: `{name}` is required"));
                            }
                        }
                    }
                }
                "additionalProperties" => {
                    if let Some(fields) = value.as_object() {
                        let known = object.get("properties").and_then(Value::as_object);
                        for (name, field) in fields {
                            if known.is_some_and(|known| known.contains_key(name)) {
                                continue;
                            }
                            match argument {
                                Value::Bool(false) => {
                                    errors.push(format!("{path}: unexpected property `{name}`"))
                                }
                                Value::Bool(true) => {}
                                sub => self.check(sub, field, &format!("{path}.{name}"), errors),
                            }
                        }
                    }
                }
                "enum" => {
                    let options = argument.as_array().expect("enum is an array");
                    if !options.contains(value) {
                        errors.push(format!("{path}: {value} is not one of {argument}"));
                    }
                }
                "items" => {
                    if let Some(items) = value.as_array() {
                        for (index, item) in items.iter().enumerate() {
                            self.check(argument, item, &format!("{path}[{index}]"), errors);
                        }
                    }
                }
                "minimum" => {
                    if let (Some(number), Some(minimum)) = (value.as_f64(), argument.as_f64()) {
                        if number < minimum {
                            errors.push(format!("{path}: {number} is below the minimum {minimum}"));
                        }
                    }
                }
                "maximum" => {
                    if let (Some(number), Some(maximum)) = (value.as_f64(), argument.as_f64()) {
                        if number > maximum {
                            errors.push(format!("{path}: {number} is above the maximum {maximum}"));
                        }
                    }
                }
                other if ANNOTATIONS.contains(&other) => {}
                other => panic!("schema keyword `{other}` is not supported by this validator"),
            }
        }
    }

    /// Validates one message the adapter sent: every message against its base type, and a
    /// response or event against its specific definition where the schema has one.
    pub fn validate_message(&self, message: &Value) -> Vec<String> {
        let mut errors = self.validate("ProtocolMessage", message);
        match message["type"].as_str() {
            Some("response") => {
                if message["success"] == Value::Bool(false) {
                    errors.extend(self.validate("ErrorResponse", message));
                } else {
                    errors.extend(self.validate("Response", message));
                    let command = message["command"].as_str().unwrap_or_default();
                    let name = format!("{}Response", capitalize(command));
                    if self.has_definition(&name) {
                        errors.extend(self.validate(&name, message));
                    }
                }
            }
            Some("event") => {
                errors.extend(self.validate("Event", message));
                let event = message["event"].as_str().unwrap_or_default();
                let name = format!("{}Event", capitalize(event));
                if self.has_definition(&name) {
                    errors.extend(self.validate(&name, message));
                }
            }
            other => errors.push(format!("the adapter sent a message of type {other:?}")),
        }
        errors
    }
}

fn has_type(value: &Value, ty: &str) -> bool {
    match ty {
        "object" => value.is_object(),
        "array" => value.is_array(),
        "string" => value.is_string(),
        "boolean" => value.is_boolean(),
        "null" => value.is_null(),
        "number" => value.is_number(),
        "integer" => value.is_i64() || value.is_u64(),
        _ => panic!("unknown type {ty}"),
    }
}

fn capitalize(name: &str) -> String {
    let mut chars = name.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}
