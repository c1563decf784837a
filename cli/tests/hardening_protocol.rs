//! Hardening: the protocol attacks of issue 19 against the real `gloc dap --port` and
//! `gloc lsp` processes, on loopback only, bounded in count and time (every wait has a
//! deadline; the largest input is 64 MB). Every DAP message received is validated
//! against the official schema.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStderr, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

#[path = "../../dap/tests/support/schema.rs"]
mod dap_schema;

/// Far longer than any case needs; only a hang reaches it.
const DEADLINE: Duration = Duration::from_secs(30);

fn fixture(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../dap/tests/fixtures")
        .join(name)
        .canonicalize()
        .expect("fixture")
        .display()
        .to_string()
}

/// A `gloc dap --port 0` process, killed when dropped.
struct Adapter {
    child: Child,
    port: u16,
    token: String,
    /// What the first read of stderr returned.
    first_read: String,
}

impl Adapter {
    fn start() -> Adapter {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gloc"))
            .args(["dap", "--port", "0"])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start gloc dap --port 0");
        let mut stderr: ChildStderr = child.stderr.take().expect("stderr");
        let mut chunk = [0u8; 4096];
        // One read: the line must arrive whole (an editor reads chunk by chunk).
        let count = stderr.read(&mut chunk).expect("read stderr");
        let first_read = String::from_utf8_lossy(&chunk[..count]).into_owned();
        // Keep draining stderr so the adapter never blocks on it.
        std::thread::spawn(move || {
            let mut sink = Vec::new();
            let _ = stderr.read_to_end(&mut sink);
        });
        let Some((port, token)) = parse_listening(&first_read) else {
            // No adapter to drop yet: leave no process behind.
            let _ = child.kill();
            let _ = child.wait();
            panic!("the first read of stderr is not the whole listening line: {first_read:?}");
        };
        Adapter {
            child,
            port,
            token,
            first_read,
        }
    }

    fn connect(&self) -> Client {
        Client::connect(self.port)
    }

    /// Peak resident memory of the adapter, in KiB.
    fn peak_rss_kib(&self) -> u64 {
        peak_rss_kib(self.child.id())
    }
}

impl Drop for Adapter {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `gloc dap: listening on 127.0.0.1:PORT token TOKEN\n` → (PORT, TOKEN).
fn parse_listening(text: &str) -> Option<(u16, String)> {
    let line = text.strip_suffix('\n')?;
    let rest = line.strip_prefix("gloc dap: listening on 127.0.0.1:")?;
    let (port, token) = rest.split_once(" token ")?;
    Some((port.parse().ok()?, token.to_string()))
}

fn peak_rss_kib(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).expect("/proc status");
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmHWM:"))
        .and_then(|value| value.trim().trim_end_matches("kB").trim().parse().ok())
        .expect("VmHWM")
}

/// A DAP client over TCP.
struct Client {
    stream: TcpStream,
    buffer: Vec<u8>,
    next_seq: i64,
    schema: dap_schema::Schema,
    received: Vec<Value>,
}

impl Client {
    fn connect(port: u16) -> Client {
        let stream = TcpStream::connect(("127.0.0.1", port)).expect("connect");
        stream
            .set_read_timeout(Some(Duration::from_millis(200)))
            .expect("timeout");
        Client {
            stream,
            buffer: Vec::new(),
            next_seq: 1,
            schema: dap_schema::Schema::dap(),
            received: Vec::new(),
        }
    }

    fn send(&mut self, command: &str, arguments: Value) -> i64 {
        let seq = self.next_seq;
        self.next_seq += 1;
        let body =
            json!({ "seq": seq, "type": "request", "command": command, "arguments": arguments })
                .to_string();
        let frame = format!("Content-Length: {}\r\n\r\n{body}", body.len());
        self.stream.write_all(frame.as_bytes()).expect("send");
        seq
    }

    /// The next message, or `None` when the adapter closed the connection.
    fn next_message(&mut self) -> Option<Value> {
        let deadline = Instant::now() + DEADLINE;
        loop {
            if let Some(message) = self.take_frame() {
                let errors = self.schema.validate_message(&message);
                assert!(
                    errors.is_empty(),
                    "schema: {message}\n{}",
                    errors.join("\n")
                );
                self.received.push(message.clone());
                return Some(message);
            }
            assert!(Instant::now() < deadline, "no message within {DEADLINE:?}");
            let mut chunk = [0u8; 65536];
            match self.stream.read(&mut chunk) {
                Ok(0) => return None,
                Ok(count) => self.buffer.extend_from_slice(&chunk[..count]),
                Err(error)
                    if matches!(
                        error.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) => {}
                Err(_) => return None,
            }
        }
    }

    fn take_frame(&mut self) -> Option<Value> {
        let end = self
            .buffer
            .windows(4)
            .position(|window| window == b"\r\n\r\n")?;
        let header = std::str::from_utf8(&self.buffer[..end]).expect("ASCII header");
        let length: usize = header
            .strip_prefix("Content-Length: ")
            .expect("Content-Length")
            .parse()
            .expect("number");
        let body = self.buffer.get(end + 4..end + 4 + length)?.to_vec();
        self.buffer.drain(..end + 4 + length);
        Some(serde_json::from_slice(&body).expect("JSON"))
    }

    fn response(&mut self, seq: i64) -> Value {
        loop {
            let message = self
                .next_message()
                .unwrap_or_else(|| panic!("connection closed before the response to {seq}"));
            if message["type"] == "response" && message["request_seq"] == json!(seq) {
                return message;
            }
        }
    }

    fn request(&mut self, command: &str, arguments: Value) -> Value {
        let seq = self.send(command, arguments);
        self.response(seq)
    }

    /// True when the adapter closes the connection within the deadline (messages
    /// before the end are read and validated).
    fn closed(&mut self) -> bool {
        let deadline = Instant::now() + DEADLINE;
        while Instant::now() < deadline {
            if self.next_message().is_none() {
                return true;
            }
        }
        false
    }

    fn everything_received(&self) -> String {
        self.received
            .iter()
            .map(Value::to_string)
            .collect::<Vec<_>>()
            .join("\n")
    }
}

fn initialize(client: &mut Client) {
    let response = client.request("initialize", json!({ "adapterID": "gloc" }));
    assert_eq!(response["success"], true, "{response}");
}

fn launch(client: &mut Client, token: &str, program: &str) -> Value {
    client.request(
        "launch",
        json!({ "program": program, "stopOnEntry": true, "token": token }),
    )
}

#[test]
fn the_listening_line_comes_in_one_write_with_the_port_and_a_token() {
    let adapter = Adapter::start();
    assert!(adapter.port > 0);
    assert_eq!(adapter.token.len(), 32, "{}", adapter.first_read);
    assert!(adapter.token.bytes().all(|byte| byte.is_ascii_hexdigit()));
    // A fresh token per process.
    let other = Adapter::start();
    assert_ne!(adapter.token, other.token);
}

#[test]
fn without_the_token_nothing_but_initialize_is_answered() {
    let adapter = Adapter::start();
    let mut client = adapter.connect();
    initialize(&mut client);
    let refused = client.request("threads", json!({}));
    assert_eq!(refused["success"], false, "{refused}");
    assert!(refused["message"]
        .as_str()
        .is_some_and(|text| text.contains("token")));
    // A launch without the token is refused and the connection closed.
    let refused = client.request("launch", json!({ "program": fixture("fig3.gbas") }));
    assert_eq!(refused["success"], false, "{refused}");
    assert!(client.closed(), "the connection stays open");
    // A wrong token: the same.
    let mut client = adapter.connect();
    initialize(&mut client);
    let refused = launch(
        &mut client,
        "0123456789abcdef0123456789abcdef",
        &fixture("fig3.gbas"),
    );
    assert_eq!(refused["success"], false, "{refused}");
    assert!(client.closed(), "the connection stays open");
    // The right token works.
    let mut client = adapter.connect();
    initialize(&mut client);
    let launched = launch(&mut client, &adapter.token, &fixture("fig3.gbas"));
    assert_eq!(launched["success"], true, "{launched}");
}

#[test]
fn disconnect_closes_the_connection_and_sessions_run_side_by_side() {
    let adapter = Adapter::start();
    let mut first = adapter.connect();
    initialize(&mut first);
    assert_eq!(
        launch(&mut first, &adapter.token, &fixture("fig3.gbas"))["success"],
        true
    );
    // A second session while the first is open: both answer.
    let mut second = adapter.connect();
    initialize(&mut second);
    assert_eq!(
        launch(&mut second, &adapter.token, &fixture("loop.gbas"))["success"],
        true
    );
    assert_eq!(first.request("threads", json!({}))["success"], true);
    assert_eq!(second.request("threads", json!({}))["success"], true);
    let response = first.request("disconnect", json!({}));
    assert_eq!(response["success"], true, "{response}");
    assert!(first.closed(), "the connection stays open after disconnect");
    assert_eq!(second.request("threads", json!({}))["success"], true);
}

#[test]
fn five_hundred_idle_connections_do_not_block_a_real_client() {
    let adapter = Adapter::start();
    let idle: Vec<TcpStream> = (0..500)
        .map(|_| TcpStream::connect(("127.0.0.1", adapter.port)).expect("idle connection"))
        .collect();
    let mut client = adapter.connect();
    initialize(&mut client);
    let launched = launch(&mut client, &adapter.token, &fixture("fig3.gbas"));
    assert_eq!(launched["success"], true, "{launched}");
    assert_eq!(client.request("disconnect", json!({}))["success"], true);
    drop(idle);
}

#[test]
fn a_huge_header_without_newline_is_refused_in_bounded_memory() {
    const SENT: usize = 64 << 20;
    let adapter = Adapter::start();
    let mut client = adapter.connect();
    initialize(&mut client);
    let before = adapter.peak_rss_kib();
    let chunk = vec![b'a'; 1 << 20];
    for _ in 0..SENT / chunk.len() {
        client.stream.write_all(&chunk).expect("send");
    }
    // The adapter reported the broken framing once and resynchronises at the next
    // header: the session goes on.
    client.stream.write_all(b"\r\n").expect("send");
    let threads = client.request("threads", json!({}));
    assert!(threads["success"].is_boolean(), "{threads}");
    let report = client.everything_received();
    assert!(report.contains("longer than the limit"), "{report}");
    let grown = adapter.peak_rss_kib().saturating_sub(before);
    // 64 MB went through; a buffered line would have grown the peak by as much.
    assert!(grown < 16 * 1024, "peak RSS grew by {grown} KiB");
}

/// One message of the language server: its `Content-Length` header, then the body.
fn read_lsp_message(reader: &mut impl std::io::BufRead) -> String {
    let mut length = None;
    loop {
        let mut line = String::new();
        assert!(
            reader.read_line(&mut line).expect("header") > 0,
            "no answer"
        );
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(value) = line.strip_prefix("Content-Length: ") {
            length = value.parse::<usize>().ok();
        }
    }
    let mut body = vec![0; length.expect("Content-Length")];
    reader.read_exact(&mut body).expect("body");
    String::from_utf8(body).expect("UTF-8")
}

#[test]
fn the_language_server_holds_a_huge_header_in_bounded_memory() {
    const SENT: usize = 64 << 20;
    let mut child = Command::new(env!("CARGO_BIN_EXE_gloc"))
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start gloc lsp");
    let pid = child.id();
    let mut stdin = child.stdin.take().expect("stdin");
    // The baseline is the server's peak once it has started and answered `initialize`:
    // measured straight after the spawn, it held the server's own start-up (about 15 MB,
    // more on a busy machine), and the bound below measured that rather than the header.
    let body = r#"{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}"#;
    write!(stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("initialize");
    stdin.flush().expect("flush");
    let mut stdout = std::io::BufReader::new(child.stdout.take().expect("stdout"));
    let answer = read_lsp_message(&mut stdout);
    assert!(answer.contains("\"capabilities\""), "{answer}");
    // Whatever else the server writes is drained, so that it never blocks on the pipe.
    let drain = std::thread::spawn(move || std::io::copy(&mut stdout, &mut std::io::sink()));
    let before = peak_rss_kib(pid);
    let chunk = vec![b'a'; 1 << 20];
    for _ in 0..SENT / chunk.len() {
        stdin.write_all(&chunk).expect("send");
    }
    stdin.flush().expect("flush");
    // Give the server the time to read what is in the pipe (it reads as we write;
    // the last chunk is at most a pipe buffer behind).
    std::thread::sleep(Duration::from_millis(300));
    let grown = peak_rss_kib(pid).saturating_sub(before);
    drop(stdin);
    let deadline = Instant::now() + DEADLINE;
    while child.try_wait().expect("wait").is_none() {
        assert!(Instant::now() < deadline, "gloc lsp did not exit");
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = drain.join();
    assert!(grown < 16 * 1024, "peak RSS grew by {grown} KiB");
}

/// A private folder with a file of secret lines under several names.
fn secrets() -> (PathBuf, Vec<String>) {
    let folder = gloc_testsupport::scratch_dir("hardening-protocol");
    std::fs::create_dir_all(&folder).expect("folder");
    let text: String = (1..=40)
        .map(|line| format!("SECRET{line} = `hunter{line}` \"pass word\" {line}\n"))
        .collect();
    // A well-formed mission whose sensor names are the secret: it launches, with a
    // warning about each unknown sensor.
    let mission: String = (1..=40)
        .map(|line| format!("sensor: SECRET{line}hunter(m) {line}\n"))
        .collect::<String>()
        + "behavior: gloc\nbehavior: surface\n";
    let mut paths = Vec::new();
    for (name, text) in [
        ("secret.txt", &text),
        ("secret.mi", &text),
        ("secret.gloc", &text),
        ("secret.csv", &text),
        ("masterdata", &text),
        ("wellformed.mi", &mission),
    ] {
        let path = folder.join(name);
        std::fs::write(&path, text).expect("write");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).expect("chmod");
        }
        paths.push(path.display().to_string());
    }
    (folder, paths)
}

#[test]
fn no_launch_attribute_makes_the_adapter_echo_a_private_file() {
    let adapter = Adapter::start();
    let (folder, paths) = secrets();
    let program = fixture("fig3.gbas");
    let mut attempts = Vec::new();
    for path in &paths {
        attempts.push(json!({ "program": program, "mission": path }));
        attempts.push(json!({ "program": program, "masterdata": path }));
        attempts.push(json!({ "program": program, "profile": path }));
        attempts.push(json!({ "program": path }));
    }
    for mut arguments in attempts {
        arguments["token"] = json!(adapter.token);
        arguments["stopOnEntry"] = json!(true);
        let mut client = adapter.connect();
        initialize(&mut client);
        let response = client.request("launch", arguments.clone());
        if response["success"] == true {
            // Whatever it made of the file, nothing of it is shown in the session.
            client.send("configurationDone", json!({}));
            client.request("threads", json!({}));
        }
        let _ = client.request("disconnect", json!({}));
        let everything = client.everything_received();
        for secret in ["SECRET", "hunter", "pass word"] {
            assert!(
                !everything.contains(secret),
                "{arguments}\nleaked {secret}: {everything}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(folder);
}

#[test]
fn a_connection_without_token_is_never_given_a_file() {
    // Even `initialize` then `launch` with the right program but no token reads nothing:
    // the refusal names no file.
    let adapter = Adapter::start();
    let (folder, paths) = secrets();
    let mut client = adapter.connect();
    initialize(&mut client);
    let refused = client.request("launch", json!({ "program": paths[2] }));
    assert_eq!(refused["success"], false);
    assert!(!client.everything_received().contains("SECRET"));
    let _ = std::fs::remove_dir_all(folder);
}

#[test]
fn a_connection_that_does_not_send_the_token_is_closed_after_ten_seconds() {
    let adapter = Adapter::start();
    let mut client = adapter.connect();
    initialize(&mut client);
    let started = Instant::now();
    assert!(client.closed(), "still open after {DEADLINE:?}");
    // The limit is 10 s (docs/dap.md): closed by the timeout, not at once (`closed`
    // bounds it from above by its deadline).
    let waited = started.elapsed();
    assert!(waited >= Duration::from_secs(8), "closed after {waited:?}");
}

#[test]
fn trickling_bytes_does_not_extend_the_token_timeout() {
    let adapter = Adapter::start();
    let mut client = adapter.connect();
    initialize(&mut client);
    let started = Instant::now();
    // A header a byte every second: never a frame, never ten quiet seconds either.
    for byte in b"X-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa".iter() {
        if client.stream.write_all(&[*byte]).is_err() {
            break;
        }
        std::thread::sleep(Duration::from_secs(1));
        if started.elapsed() > DEADLINE {
            break;
        }
    }
    assert!(client.closed(), "still open after {:?}", started.elapsed());
    assert!(
        started.elapsed() < DEADLINE,
        "closed only after {:?}",
        started.elapsed()
    );
}

#[test]
fn sessions_beyond_the_cap_are_refused_until_one_ends() {
    // gloc_dap::limits::MAX_SESSIONS, as documented in docs/dap.md.
    const MAX_SESSIONS: usize = 16;
    let adapter = Adapter::start();
    let program = fixture("loop.gbas");
    let mut sessions: Vec<Client> = (0..MAX_SESSIONS)
        .map(|_| {
            let mut client = adapter.connect();
            initialize(&mut client);
            let launched = launch(&mut client, &adapter.token, &program);
            assert_eq!(launched["success"], true, "{launched}");
            client
        })
        .collect();
    let mut extra = adapter.connect();
    initialize(&mut extra);
    let refused = launch(&mut extra, &adapter.token, &program);
    assert_eq!(refused["success"], false, "{refused}");
    assert!(
        refused["message"]
            .as_str()
            .is_some_and(|text| text.contains("16 sessions")),
        "{refused}"
    );
    assert!(extra.closed());
    let mut first = sessions.remove(0);
    assert_eq!(first.request("disconnect", json!({}))["success"], true);
    assert!(first.closed());
    let mut next = adapter.connect();
    initialize(&mut next);
    let launched = launch(&mut next, &adapter.token, &program);
    assert_eq!(launched["success"], true, "{launched}");
}

#[test]
fn before_the_token_a_body_is_held_to_one_mebibyte() {
    let adapter = Adapter::start();
    let mut client = adapter.connect();
    initialize(&mut client);
    // 2 MiB of expression: refused unread before the token (docs/dap.md) ...
    let big = "1+".repeat(1 << 20) + "1";
    let seq = client.send("evaluate", json!({ "expression": big }));
    let threads = client.request("threads", json!({}));
    assert_eq!(threads["success"], false, "{threads}");
    let everything = client.everything_received();
    assert!(
        everything.contains("larger than the limit of 1048576"),
        "{everything}"
    );
    assert!(
        !client
            .received
            .iter()
            .any(|message| message["request_seq"] == json!(seq)),
        "the big request was read"
    );
    // ... and read once the session has the token.
    let launched = launch(&mut client, &adapter.token, &fixture("fig3.gbas"));
    assert_eq!(launched["success"], true, "{launched}");
    // Read and answered: a debugger expression is at most 64 KiB (docs/gbasic.md E2010).
    let answered = client.request("evaluate", json!({ "expression": big }));
    assert_eq!(answered["success"], false, "{answered}");
    assert!(
        answered["message"]
            .as_str()
            .is_some_and(|message| message.contains("at most 65536")),
        "{answered}"
    );
}
