//! Round-trip latency of requests to `gloc dap --port` over loopback TCP
//! (`cargo bench -p gloc-dap --bench tcp`): each message goes out in one write with
//! `TCP_NODELAY`, so a request costs no delayed-ACK wait. Prints figures; asserts
//! nothing about time.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::Instant;

use serde_json::{json, Value};

const ROUND_TRIPS: usize = 500;

struct Client {
    stream: TcpStream,
    buffer: Vec<u8>,
    seq: i64,
}

impl Client {
    fn request(&mut self, command: &str, arguments: Value) -> Value {
        self.seq += 1;
        let body = json!({ "seq": self.seq, "type": "request", "command": command, "arguments": arguments })
            .to_string();
        self.stream
            .write_all(format!("Content-Length: {}\r\n\r\n{body}", body.len()).as_bytes())
            .expect("send");
        loop {
            let message = self.next_message();
            if message["type"] == "response" && message["request_seq"] == json!(self.seq) {
                return message;
            }
        }
    }

    fn next_message(&mut self) -> Value {
        loop {
            if let Some(end) = self
                .buffer
                .windows(4)
                .position(|window| window == b"\r\n\r\n")
            {
                let header = std::str::from_utf8(&self.buffer[..end]).expect("header");
                let length: usize = header["Content-Length: ".len()..].parse().expect("length");
                if self.buffer.len() >= end + 4 + length {
                    let message = serde_json::from_slice(&self.buffer[end + 4..end + 4 + length])
                        .expect("JSON");
                    self.buffer.drain(..end + 4 + length);
                    return message;
                }
            }
            let mut chunk = [0u8; 65536];
            let count = self.stream.read(&mut chunk).expect("read");
            assert!(count > 0, "the adapter closed the connection");
            self.buffer.extend_from_slice(&chunk[..count]);
        }
    }
}

fn main() {
    let (sender, receiver) = mpsc::channel();
    std::thread::spawn(move || {
        gloc_dap::serve_tcp(0, |address, token| {
            let _ = sender.send((address, token.to_string()));
        })
    });
    let (address, token) = receiver.recv().expect("the adapter listens");
    let program = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fig3.gbas");
    let mut client = Client {
        stream: TcpStream::connect(address).expect("connect"),
        buffer: Vec::new(),
        seq: 0,
    };
    client.request("initialize", json!({ "adapterID": "gloc" }));
    let launched = client.request(
        "launch",
        json!({ "program": program, "stopOnEntry": true, "token": token }),
    );
    assert_eq!(launched["success"], true, "{launched}");
    client.request("configurationDone", json!({}));
    let mut times = Vec::with_capacity(ROUND_TRIPS);
    for _ in 0..ROUND_TRIPS {
        let began = Instant::now();
        let response = client.request("stackTrace", json!({ "threadId": 1 }));
        times.push(began.elapsed().as_secs_f64() * 1e3);
        assert_eq!(response["success"], true);
    }
    times.sort_by(f64::total_cmp);
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    println!(
        "stackTrace over TCP, {ROUND_TRIPS} round trips: median {:.3} ms, mean {mean:.3} ms, worst {:.3} ms",
        times[times.len() / 2],
        times[times.len() - 1]
    );
}
