//! gloc-framing: the `Content-Length` framing that `gloc lsp` and `gloc dap` share
//! (both protocols use the same base protocol: header lines, a blank line, a body).
//!
//! [`Decoder`] is a byte-level state machine without IO: each server feeds it what its own
//! reader got (tokio for the language server, `std::io` for the debug adapter) and gets
//! whole bodies or framing errors back. Everything it buffers is bounded by [`Limits`]:
//! a header line, a header block and a body. After a framing error (a line that is not a
//! header, a `Content-Length` that is not a number or too large, a line or block over its
//! limit) it reports the error once and resynchronises by discarding bytes up to the
//! next `Content-Length:` (matched case-insensitively anywhere, so a body cut short by a
//! wrong length still finds the header glued to its tail), never holding more than a
//! few bytes while it searches.

// Only the engine's interpreter may use `unsafe` (ARCHITECTURE.md, invariants).
#![forbid(unsafe_code)]

use std::collections::VecDeque;
use std::io::{self, Read};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// What the decoder may buffer. The same limits serve both servers (`LIMITS`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The longest header line, without its line break.
    pub max_header_line: usize,
    /// The largest header block (all its lines).
    pub max_header_block: usize,
    /// The largest body a `Content-Length` may announce.
    pub max_body: usize,
}

/// The limits of both servers: real clients send two short header lines; the largest
/// body is a whole document in `didOpen` (scripts are capped at 16 MB, E0013, and
/// JSON escaping rarely adds more than a few percent).
pub const LIMITS: Limits = Limits {
    max_header_line: 8 * 1024,
    max_header_block: 16 * 1024,
    max_body: 64 * 1024 * 1024,
};

/// One thing the decoder found in the stream.
#[derive(Debug, PartialEq, Eq)]
pub enum Event {
    /// A complete body, exactly `Content-Length` bytes.
    Message(Vec<u8>),
    /// The framing was broken; the decoder is resynchronising (or, for a header block
    /// without `Content-Length`, simply reading the next block).
    Error(FrameError),
}

/// A framing error: what was wrong and where (the byte offset in the stream of the
/// line or block at fault).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameError {
    pub offset: u64,
    pub message: String,
}

impl std::fmt::Display for FrameError {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(formatter, "at byte {}: {}", self.offset, self.message)
    }
}

/// The case-insensitive pattern a resynchronisation looks for.
const RESYNC_PATTERN: &[u8] = b"content-length:";

#[derive(Debug)]
enum State {
    /// Reading header lines; `line` holds the current one.
    Headers,
    /// Reading `remaining` more body bytes into `body`.
    Body { remaining: usize },
    /// Discarding bytes; `matched` bytes of `RESYNC_PATTERN` have been seen.
    Resync { matched: usize },
}

/// The framing state machine. Feed it bytes in any chunking; it returns what they
/// completed.
#[derive(Debug)]
pub struct Decoder {
    limits: Limits,
    state: State,
    /// The current header line (at most `max_header_line` bytes).
    line: Vec<u8>,
    /// Offset of the current line's first byte.
    line_start: u64,
    /// Bytes of header lines seen in the current block.
    block_bytes: usize,
    /// Whether the current block has a non-blank line.
    block_started: bool,
    /// Offset of the current block's first line.
    block_start: u64,
    content_length: Option<usize>,
    body: Vec<u8>,
    /// Bytes consumed so far.
    offset: u64,
}

impl Decoder {
    pub fn new(limits: Limits) -> Decoder {
        Decoder {
            limits,
            state: State::Headers,
            line: Vec::new(),
            line_start: 0,
            block_bytes: 0,
            block_started: false,
            block_start: 0,
            content_length: None,
            body: Vec::new(),
            offset: 0,
        }
    }

    /// Changes the limits for what is read from now on (e.g. larger once a client has
    /// authenticated).
    pub fn set_limits(&mut self, limits: Limits) {
        self.limits = limits;
    }

    /// Consumes `bytes`, appending every completed message or error to `events`.
    pub fn feed(&mut self, mut bytes: &[u8], events: &mut VecDeque<Event>) {
        while !bytes.is_empty() {
            let used = match self.state {
                State::Headers => self.feed_headers(bytes, events),
                State::Body { remaining } => {
                    let take = remaining.min(bytes.len());
                    self.body.extend_from_slice(&bytes[..take]);
                    if take == remaining {
                        events.push_back(Event::Message(std::mem::take(&mut self.body)));
                        self.start_block(take);
                    } else {
                        self.state = State::Body {
                            remaining: remaining - take,
                        };
                    }
                    take
                }
                State::Resync { matched } => self.feed_resync(bytes, matched),
            };
            self.offset += used as u64;
            bytes = &bytes[used..];
        }
    }

    /// Whether the input ended cleanly (between messages), for a caller that wants to
    /// tell a truncated frame from a closed stream.
    pub fn is_between_messages(&self) -> bool {
        matches!(self.state, State::Headers) && !self.block_started && self.line.is_empty()
    }

    /// Reads one header line's worth of `bytes`; returns how many it used.
    fn feed_headers(&mut self, bytes: &[u8], events: &mut VecDeque<Event>) -> usize {
        let (chunk, complete) = match bytes.iter().position(|&byte| byte == b'\n') {
            Some(end) => (&bytes[..end], true),
            None => (bytes, false),
        };
        if self.line.len() + chunk.len() > self.limits.max_header_line {
            let offset = self.line_start;
            self.error(
                events,
                offset,
                format!(
                    "a header line is longer than the limit of {} bytes",
                    self.limits.max_header_line
                ),
            );
            // The rest of this chunk is discarded by the resynchronisation.
            return 0;
        }
        self.line.extend_from_slice(chunk);
        if !complete {
            return chunk.len();
        }
        let used = chunk.len() + 1;
        let mut line = std::mem::take(&mut self.line);
        if line.last() == Some(&b'\r') {
            line.pop();
        }
        let line_start = self.line_start;
        self.line_start = self.offset + used as u64;
        if line.is_empty() {
            if self.block_started {
                match self.content_length.take() {
                    Some(length) => {
                        self.body = Vec::with_capacity(length.min(1 << 20));
                        self.state = State::Body { remaining: length };
                        if length == 0 {
                            events.push_back(Event::Message(Vec::new()));
                            self.start_block(used);
                        }
                    }
                    None => {
                        events.push_back(Event::Error(FrameError {
                            offset: self.block_start,
                            message: "a header block has no Content-Length".into(),
                        }));
                        self.start_block(used);
                    }
                }
            }
            // A blank line between messages is noise (some clients add a CRLF).
            self.line = line;
            self.line.clear();
            return used;
        }
        if !self.block_started {
            self.block_started = true;
            self.block_start = line_start;
        }
        self.block_bytes += line.len();
        if self.block_bytes > self.limits.max_header_block {
            let offset = self.block_start;
            self.error(
                events,
                offset,
                format!(
                    "a header block is larger than the limit of {} bytes",
                    self.limits.max_header_block
                ),
            );
            return used;
        }
        match parse_header(&line) {
            Header::ContentLength(Ok(length)) if length <= self.limits.max_body => {
                self.content_length = Some(length);
            }
            Header::ContentLength(Ok(length)) => self.error(
                events,
                line_start,
                format!(
                    "Content-Length {length} is larger than the limit of {} bytes",
                    self.limits.max_body
                ),
            ),
            Header::ContentLength(Err(value)) => self.error(
                events,
                line_start,
                format!("Content-Length `{value}` is not a number"),
            ),
            Header::Other => {}
            Header::Malformed => {
                let message = format!("`{}` is not a header line (`Name: value`)", preview(&line));
                // A body cut short by a wrong length leaves its tail glued to the next
                // header: start again at a `Content-Length:` inside this very line.
                match find_pattern(&line[1..]) {
                    Some(index) => {
                        events.push_back(Event::Error(FrameError {
                            offset: line_start,
                            message,
                        }));
                        // The rest starts with `content-length:`, so it is read as a
                        // header line of a new block (no deeper recursion).
                        let mut rest = line[1 + index..].to_vec();
                        rest.push(b'\n');
                        let rest_start = line_start + 1 + index as u64;
                        self.block_bytes = 0;
                        self.block_started = false;
                        self.content_length = None;
                        self.line.clear();
                        self.line_start = rest_start;
                        let saved_offset = self.offset;
                        self.offset = rest_start;
                        self.feed_headers(&rest, events);
                        self.offset = saved_offset;
                    }
                    None => self.error(events, line_start, message),
                }
                self.line_start = self.offset + used as u64;
                return used;
            }
        }
        self.line = line;
        self.line.clear();
        used
    }

    /// Discards bytes until `content-length:`; returns how many it used.
    fn feed_resync(&mut self, bytes: &[u8], mut matched: usize) -> usize {
        for (index, &byte) in bytes.iter().enumerate() {
            let byte = byte.to_ascii_lowercase();
            if byte == RESYNC_PATTERN[matched] {
                matched += 1;
                if matched == RESYNC_PATTERN.len() {
                    let used = index + 1;
                    self.state = State::Headers;
                    self.line.clear();
                    self.line.extend_from_slice(b"Content-Length:");
                    self.line_start = self.offset + used as u64 - RESYNC_PATTERN.len() as u64;
                    self.block_bytes = 0;
                    self.block_started = false;
                    self.content_length = None;
                    return used;
                }
            } else {
                // The pattern's first byte occurs nowhere else in it.
                matched = usize::from(byte == RESYNC_PATTERN[0]);
            }
        }
        self.state = State::Resync { matched };
        bytes.len()
    }

    /// Reports a framing error and starts resynchronising.
    fn error(&mut self, events: &mut VecDeque<Event>, offset: u64, message: String) {
        events.push_back(Event::Error(FrameError { offset, message }));
        self.line.clear();
        self.block_bytes = 0;
        self.block_started = false;
        self.content_length = None;
        self.state = State::Resync { matched: 0 };
    }

    /// Back to reading headers; `used` bytes of the current chunk were consumed.
    fn start_block(&mut self, used: usize) {
        self.state = State::Headers;
        self.line.clear();
        self.line_start = self.offset + used as u64;
        self.block_bytes = 0;
        self.block_started = false;
        self.content_length = None;
    }
}

enum Header {
    ContentLength(Result<usize, String>),
    Other,
    Malformed,
}

/// Classifies one header line (`Name: value`, the name an RFC 7230 token).
fn parse_header(line: &[u8]) -> Header {
    let Some(colon) = line.iter().position(|&byte| byte == b':') else {
        return Header::Malformed;
    };
    let name = &line[..colon];
    let is_token = !name.is_empty()
        && name
            .iter()
            .all(|&byte| byte.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(&byte));
    if !is_token {
        return Header::Malformed;
    }
    if !name.eq_ignore_ascii_case(b"content-length") {
        return Header::Other;
    }
    let value = String::from_utf8_lossy(&line[colon + 1..]);
    let value = value.trim();
    let digits = !value.is_empty() && value.bytes().all(|byte| byte.is_ascii_digit());
    match value.parse::<usize>() {
        Ok(length) if digits => Header::ContentLength(Ok(length)),
        // All digits but past usize: larger than any limit.
        Err(_) if digits => Header::ContentLength(Ok(usize::MAX)),
        _ => Header::ContentLength(Err(preview(value.as_bytes()))),
    }
}

/// Where `content-length:` starts in `bytes`, case-insensitively.
fn find_pattern(bytes: &[u8]) -> Option<usize> {
    bytes
        .windows(RESYNC_PATTERN.len())
        .position(|window| window.eq_ignore_ascii_case(RESYNC_PATTERN))
}

/// At most 40 characters of a broken line, for an error message.
fn preview(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    let mut shown: String = text.chars().take(40).collect();
    if text.chars().nth(40).is_some() {
        shown.push('…');
    }
    shown.escape_debug().to_string()
}

/// One frame, header and body, in one buffer so that it goes out in one write (over
/// TCP, separate small writes cost a delayed-ACK round trip each).
pub fn encode(body: &[u8]) -> Vec<u8> {
    let header = format!("Content-Length: {}\r\n\r\n", body.len());
    let mut frame = Vec::with_capacity(header.len() + body.len());
    frame.extend_from_slice(header.as_bytes());
    frame.extend_from_slice(body);
    frame
}

/// A blocking reader of framed messages over any `Read`.
pub struct FrameReader<R> {
    input: R,
    decoder: Decoder,
    ready: VecDeque<Event>,
    chunk: Vec<u8>,
    /// Limits to switch to once the flag is set (checked before decoding each read).
    upgrade: Option<(Arc<AtomicBool>, Limits)>,
}

impl<R: Read> FrameReader<R> {
    pub fn new(input: R, limits: Limits) -> FrameReader<R> {
        FrameReader {
            input,
            decoder: Decoder::new(limits),
            ready: VecDeque::new(),
            chunk: vec![0; 64 * 1024],
            upgrade: None,
        }
    }

    /// Switches to `limits` for the bytes read after `flag` is set (e.g. once a client
    /// authenticated: set the flag before answering, and its next request is decoded
    /// with the new limits).
    pub fn upgrade_when(&mut self, flag: Arc<AtomicBool>, limits: Limits) {
        self.upgrade = Some((flag, limits));
    }

    /// See [`Decoder::set_limits`].
    pub fn set_limits(&mut self, limits: Limits) {
        self.decoder.set_limits(limits);
    }

    /// The next message or framing error; `Ok(None)` at end of input. A read error
    /// (e.g. a read timeout) is returned as is and loses nothing: call again.
    pub fn next_event(&mut self) -> io::Result<Option<Event>> {
        loop {
            if let Some(event) = self.ready.pop_front() {
                return Ok(Some(event));
            }
            let count = match self.input.read(&mut self.chunk) {
                Ok(count) => count,
                Err(error) if error.kind() == io::ErrorKind::Interrupted => continue,
                Err(error) => return Err(error),
            };
            if count == 0 {
                return Ok(None);
            }
            if let Some((flag, limits)) = &self.upgrade {
                if flag.load(Ordering::SeqCst) {
                    self.decoder.set_limits(*limits);
                    self.upgrade = None;
                }
            }
            self.decoder.feed(&self.chunk[..count], &mut self.ready);
        }
    }
}

/// Replaces every lone UTF-16 surrogate escape (`\ud83d` not followed by a low
/// surrogate escape, or a low one on its own) in a JSON text by `\ufffd`, which
/// `serde_json` rejects otherwise. JavaScript strings may hold lone surrogates and
/// `JSON.stringify` writes them so; U+FFFD is one UTF-16 code unit too, so every later
/// position a client computes stays right. `None` when there was nothing to replace.
pub fn replace_lone_surrogates(json: &[u8]) -> Option<Vec<u8>> {
    let mut out: Option<Vec<u8>> = None;
    let mut in_string = false;
    let mut index = 0;
    let mut copied = 0;
    while index < json.len() {
        let byte = json[index];
        if !in_string {
            in_string = byte == b'"';
            index += 1;
            continue;
        }
        match byte {
            b'"' => {
                in_string = false;
                index += 1;
            }
            b'\\' if json.get(index + 1) == Some(&b'u') => {
                let Some(unit) = hex_unit(json, index + 2) else {
                    index += 2;
                    continue;
                };
                let low_follows = json.get(index + 6) == Some(&b'\\')
                    && json.get(index + 7) == Some(&b'u')
                    && hex_unit(json, index + 8)
                        .is_some_and(|next| (0xDC00..0xE000).contains(&next));
                match unit {
                    0xD800..=0xDBFF if low_follows => index += 12,
                    0xD800..=0xDFFF => {
                        let out = out.get_or_insert_with(|| Vec::with_capacity(json.len()));
                        out.extend_from_slice(&json[copied..index]);
                        out.extend_from_slice(b"\\ufffd");
                        index += 6;
                        copied = index;
                    }
                    _ => index += 6,
                }
            }
            b'\\' => index += 2,
            _ => index += 1,
        }
    }
    let mut out = out?;
    out.extend_from_slice(&json[copied..]);
    Some(out)
}

/// The four hex digits at `at`, if there are four.
fn hex_unit(json: &[u8], at: usize) -> Option<u32> {
    let digits = json.get(at..at + 4)?;
    let text = std::str::from_utf8(digits).ok()?;
    if !text.bytes().all(|byte| byte.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(text, 16).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: Limits = Limits {
        max_header_line: 32,
        max_header_block: 64,
        max_body: 100,
    };

    /// Feeds `input` byte by byte and whole, and checks both give the same events.
    fn decode(limits: Limits, input: &[u8]) -> Vec<Event> {
        let mut whole = VecDeque::new();
        Decoder::new(limits).feed(input, &mut whole);
        let mut single = VecDeque::new();
        let mut decoder = Decoder::new(limits);
        for byte in input {
            decoder.feed(std::slice::from_ref(byte), &mut single);
        }
        assert_eq!(whole, single, "chunking changed the result");
        whole.into()
    }

    fn message(text: &str) -> Event {
        Event::Message(text.as_bytes().to_vec())
    }

    fn error_text(event: &Event) -> String {
        match event {
            Event::Error(error) => error.to_string(),
            Event::Message(body) => panic!("a message: {}", String::from_utf8_lossy(body)),
        }
    }

    #[test]
    fn messages_with_extra_headers_and_blank_lines_between() {
        let input = b"Content-Length: 2\r\nContent-Type: x; charset=utf-8\r\n\r\n{}\r\ncontent-length:3\n\n[1]";
        assert_eq!(decode(LIMITS, input), vec![message("{}"), message("[1]")]);
    }

    #[test]
    fn a_non_numeric_length_resynchronises_at_the_next_header() {
        let input = b"Content-Length: many\r\n\r\nxx\r\nContent-Length: 2\r\n\r\n{}";
        let events = decode(LIMITS, input);
        assert_eq!(events.len(), 2, "{events:?}");
        // The bad line starts at byte 0.
        assert_eq!(
            error_text(&events[0]),
            "at byte 0: Content-Length `many` is not a number"
        );
        assert_eq!(events[1], message("{}"));
    }

    #[test]
    fn a_length_too_short_leaves_a_tail_that_resynchronises() {
        // The body is `{"a":1}` but the length says 4: the tail `:1}` is glued to the
        // next header, which the resynchronisation still finds.
        let input = b"Content-Length: 4\r\n\r\n{\"a\":1}Content-Length: 2\r\n\r\n{}";
        let events = decode(LIMITS, input);
        assert_eq!(events[0], message("{\"a\""));
        assert!(
            error_text(&events[1]).contains("is not a header line"),
            "{events:?}"
        );
        assert_eq!(events[2], message("{}"));
        assert_eq!(events.len(), 3);
    }

    #[test]
    fn limits_are_enforced_without_buffering() {
        let long_line = format!(
            "X-Long: {}\r\n\r\nContent-Length: 2\r\n\r\n{{}}",
            "y".repeat(100)
        );
        let events = decode(SMALL, long_line.as_bytes());
        assert!(error_text(&events[0]).contains("longer than the limit of 32"));
        assert_eq!(events[1], message("{}"));
        let big_block =
            "X-A: 0123456789012345678901\r\n".repeat(4) + "\r\nContent-Length: 1\r\n\r\n1";
        let events = decode(SMALL, big_block.as_bytes());
        assert!(error_text(&events[0]).contains("header block is larger"));
        assert_eq!(events[1], message("1"));
        let events = decode(
            SMALL,
            b"Content-Length: 101\r\n\r\nContent-Length: 999999999\r\n\r\n",
        );
        assert!(error_text(&events[0]).contains("101 is larger than the limit of 100"));
        assert!(error_text(&events[1]).contains("999999999 is larger than the limit"));
        let events = decode(LIMITS, b"Content-Length: 99999999999999999999999\r\n\r\n");
        assert!(error_text(&events[0]).contains("larger than the limit"));
    }

    #[test]
    fn a_header_without_newline_is_held_to_the_line_limit() {
        let mut decoder = Decoder::new(LIMITS);
        let mut events = VecDeque::new();
        let chunk = vec![b'a'; 1 << 20];
        for _ in 0..64 {
            decoder.feed(&chunk, &mut events);
        }
        assert_eq!(events.len(), 1, "one error, then silence");
        assert!(decoder.line.capacity() <= LIMITS.max_header_line * 2);
        decoder.feed(b"Content-Length: 2\r\n\r\n{}", &mut events);
        assert_eq!(events.back(), Some(&message("{}")));
    }

    #[test]
    fn a_block_without_length_and_a_line_without_colon_are_errors() {
        let events = decode(
            LIMITS,
            b"Content-Type: a\r\n\r\ngarbage\r\n\r\nContent-Length: 1\r\n\r\n1",
        );
        assert!(error_text(&events[0]).contains("has no Content-Length"));
        assert!(error_text(&events[1]).contains("`garbage` is not a header line"));
        assert_eq!(events[2], message("1"));
    }

    #[test]
    fn a_reader_switches_limits_once_the_flag_is_set() {
        /// Hands out one prepared chunk per read.
        struct Chunks(VecDeque<Vec<u8>>);
        impl Read for Chunks {
            fn read(&mut self, buffer: &mut [u8]) -> io::Result<usize> {
                let Some(chunk) = self.0.pop_front() else {
                    return Ok(0);
                };
                buffer[..chunk.len()].copy_from_slice(&chunk);
                Ok(chunk.len())
            }
        }
        let big = encode(&[b'x'; 150]);
        let mut reader = FrameReader::new(Chunks(VecDeque::from([big.clone(), big])), SMALL);
        let flag = Arc::new(AtomicBool::new(false));
        reader.upgrade_when(flag.clone(), LIMITS);
        let refused = reader.next_event().expect("read").expect("an event");
        assert!(error_text(&refused).contains("150 is larger than the limit of 100"));
        flag.store(true, Ordering::SeqCst);
        let read = reader.next_event().expect("read").expect("an event");
        assert_eq!(read, Event::Message(vec![b'x'; 150]));
    }

    #[test]
    fn encode_is_one_buffer_the_decoder_reads_back() {
        let frame = encode(b"{\"x\":1}");
        assert_eq!(frame, b"Content-Length: 7\r\n\r\n{\"x\":1}");
        assert_eq!(decode(LIMITS, &frame), vec![message("{\"x\":1}")]);
    }

    #[test]
    fn lone_surrogates_become_replacement_characters() {
        assert_eq!(replace_lone_surrogates(br#"{"a":"\ud83d\ude00 ok"}"#), None);
        assert_eq!(
            replace_lone_surrogates(br#"{"a":"x\ud83dy","b":"\uDE00","c":"\\ud83d"}"#).as_deref(),
            Some(br#"{"a":"x\ufffdy","b":"\ufffd","c":"\\ud83d"}"#.as_slice())
        );
        assert_eq!(
            replace_lone_surrogates(br#"["\ud83d\u0041"]"#).as_deref(),
            Some(br#"["\ufffd\u0041"]"#.as_slice())
        );
    }
}
