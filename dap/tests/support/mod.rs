//! Test harness: runs `gloc_dap::serve` in a thread over in-memory pipes, sends framed
//! requests, and validates EVERY message the adapter sends against the official schema.
#![allow(dead_code)]

pub mod schema;

use std::io::{self, Read, Write};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

/// The read end of an in-memory pipe.
struct PipeReader {
    receiver: Receiver<Vec<u8>>,
    pending: Vec<u8>,
}

impl Read for PipeReader {
    fn read(&mut self, buffer: &mut [u8]) -> io::Result<usize> {
        if self.pending.is_empty() {
            match self.receiver.recv() {
                Ok(bytes) => self.pending = bytes,
                Err(_) => return Ok(0),
            }
        }
        let count = buffer.len().min(self.pending.len());
        buffer[..count].copy_from_slice(&self.pending[..count]);
        self.pending.drain(..count);
        Ok(count)
    }
}

struct PipeWriter(Sender<Vec<u8>>);

impl Write for PipeWriter {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        self.0
            .send(data.to_vec())
            .map_err(|_| io::Error::other("closed"))?;
        Ok(data.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

pub struct Client {
    to_adapter: Option<Sender<Vec<u8>>>,
    from_adapter: Receiver<Vec<u8>>,
    buffer: Vec<u8>,
    next_seq: i64,
    schema: schema::Schema,
    /// Every message received so far, in order.
    pub received: Vec<Value>,
    /// Events not yet taken by `event`.
    pub unclaimed: Vec<Value>,
    last_seq: i64,
    server: Option<JoinHandle<io::Result<()>>>,
}

pub const TIMEOUT: Duration = Duration::from_secs(20);

impl Client {
    pub fn start() -> Client {
        let (to_adapter, adapter_input) = mpsc::channel();
        let (adapter_output, from_adapter) = mpsc::channel();
        let reader = PipeReader {
            receiver: adapter_input,
            pending: Vec::new(),
        };
        let server =
            std::thread::spawn(move || gloc_dap::serve(reader, PipeWriter(adapter_output)));
        Client {
            to_adapter: Some(to_adapter),
            from_adapter,
            buffer: Vec::new(),
            next_seq: 1,
            schema: schema::Schema::dap(),
            received: Vec::new(),
            unclaimed: Vec::new(),
            last_seq: 0,
            server: Some(server),
        }
    }

    pub fn send_raw(&mut self, bytes: &[u8]) {
        if let Some(sender) = &self.to_adapter {
            let _ = sender.send(bytes.to_vec());
        }
    }

    pub fn send_body(&mut self, body: &str) {
        let framed = format!("Content-Length: {}\r\n\r\n{}", body.len(), body);
        self.send_raw(framed.as_bytes());
    }

    /// Sends a request; `arguments` of `None` omits the field entirely.
    pub fn send(&mut self, command: &str, arguments: Option<Value>) -> i64 {
        let seq = self.next_seq;
        self.next_seq += 1;
        let mut message = json!({ "seq": seq, "type": "request", "command": command });
        if let Some(arguments) = arguments {
            message["arguments"] = arguments;
        }
        self.send_body(&message.to_string());
        seq
    }

    /// The `seq` the next request will carry.
    pub fn next_seq_peek(&self) -> i64 {
        self.next_seq
    }

    /// Closes the adapter's input, as a client that goes away does.
    pub fn close(&mut self) {
        self.to_adapter = None;
    }

    /// The next message, validated against the schema; panics on a timeout.
    pub fn next_message(&mut self) -> Value {
        self.try_next_message(TIMEOUT)
            .expect("the adapter sent nothing in time")
    }

    pub fn try_next_message(&mut self, timeout: Duration) -> Option<Value> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(message) = self.parse_buffered() {
                let errors = self.schema.validate_message(&message);
                assert!(
                    errors.is_empty(),
                    "message violates the DAP schema: {message}\n{}",
                    errors.join("\n")
                );
                let seq = message["seq"].as_i64().expect("seq");
                assert!(seq > self.last_seq, "seq {seq} after {}", self.last_seq);
                self.last_seq = seq;
                self.received.push(message.clone());
                return Some(message);
            }
            let left = deadline.checked_duration_since(Instant::now())?;
            match self.from_adapter.recv_timeout(left) {
                Ok(bytes) => self.buffer.extend_from_slice(&bytes),
                Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => {
                    return None
                }
            }
        }
    }

    fn parse_buffered(&mut self) -> Option<Value> {
        let text = String::from_utf8_lossy(&self.buffer).into_owned();
        let header_end = text.find("\r\n\r\n")?;
        let length: usize = text[..header_end]
            .lines()
            .find_map(|line| line.strip_prefix("Content-Length: "))
            .expect("Content-Length header")
            .trim()
            .parse()
            .expect("numeric length");
        let start = header_end + 4;
        if self.buffer.len() < start + length {
            return None;
        }
        let body = self.buffer[start..start + length].to_vec();
        self.buffer.drain(..start + length);
        Some(serde_json::from_slice(&body).expect("the adapter sent valid JSON"))
    }

    /// Waits for the response to `seq`; events seen on the way stay claimable.
    pub fn response(&mut self, seq: i64) -> Value {
        loop {
            let message = self.next_message();
            if message["type"] == "response" && message["request_seq"] == seq {
                return message;
            }
            if message["type"] == "event" {
                self.unclaimed.push(message);
            }
        }
    }

    pub fn request(&mut self, command: &str, arguments: Option<Value>) -> Value {
        let seq = self.send(command, arguments);
        let response = self.response(seq);
        assert_eq!(response["command"], command, "{response}");
        response
    }

    /// A request that must succeed; returns its body.
    pub fn ok(&mut self, command: &str, arguments: Value) -> Value {
        let response = self.request(command, Some(arguments));
        assert_eq!(response["success"], true, "{command} failed: {response}");
        response.get("body").cloned().unwrap_or(Value::Null)
    }

    /// The next event called `name` not claimed before.
    pub fn event(&mut self, name: &str) -> Value {
        if let Some(index) = self
            .unclaimed
            .iter()
            .position(|event| event["event"] == name)
        {
            return self.unclaimed.remove(index);
        }
        loop {
            let message = self.next_message();
            if message["type"] == "event" {
                if message["event"] == name {
                    return message;
                }
                self.unclaimed.push(message);
            }
        }
    }

    /// Waits for the adapter thread to finish (it must, after disconnect or close).
    pub fn join(&mut self) -> bool {
        let Some(server) = self.server.take() else {
            return true;
        };
        let deadline = Instant::now() + TIMEOUT;
        while !server.is_finished() {
            if Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        server.join().map(|result| result.is_ok()).unwrap_or(false)
    }
}

/// The Sensors scope's `variablesReference`.
pub const SENSORS: i64 = 3;
/// The Vehicle scope's `variablesReference`.
pub const VEHICLE: i64 = 4;

/// The body of the next `stopped` event.
pub fn stopped(client: &mut Client) -> Value {
    client.event("stopped")["body"].clone()
}

/// name → value of a variables container.
pub fn values(client: &mut Client, reference: i64) -> Vec<(String, String)> {
    let body = client.ok("variables", json!({ "variablesReference": reference }));
    body["variables"]
        .as_array()
        .expect("variables")
        .iter()
        .map(|variable| {
            (
                variable["name"].as_str().unwrap_or_default().to_string(),
                variable["value"].as_str().unwrap_or_default().to_string(),
            )
        })
        .collect()
}

pub fn value(client: &mut Client, reference: i64, name: &str) -> String {
    values(client, reference)
        .into_iter()
        .find(|(known, _)| known == name)
        .map(|(_, value)| value)
        .unwrap_or_else(|| panic!("no `{name}` in variables {reference}"))
}

/// The current cycle, from the Vehicle scope.
pub fn cycle(client: &mut Client) -> u64 {
    value(client, VEHICLE, "cycle")
        .parse()
        .expect("cycle number")
}

/// A sensor's value, from the Sensors scope.
pub fn sensor(client: &mut Client, name: &str) -> f64 {
    value(client, SENSORS, name).parse().expect("a number")
}
