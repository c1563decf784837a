//! `cancel` requests, noted by the reader thread as they arrive: a reverse run holds the
//! main thread until it ends, so it cannot read the queue, but it can ask between steps
//! whether its request (or its progress) was cancelled. Forward runs hear `cancel`
//! through the queue between slices and ask the same list.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

use serde_json::Value;

/// What a `cancel` named: a request by its `seq`, or a progress by its id.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Cancelled {
    Request(i64),
    Progress(String),
}

/// The cancellations seen so far, the latest `KEPT` of them (older ones name runs long
/// over; the list stays bounded whatever a client sends).
#[derive(Clone, Debug, Default)]
pub struct Cancellations {
    seen: Arc<Mutex<VecDeque<Cancelled>>>,
}

const KEPT: usize = 64;
/// The longest progress id kept (the adapter's own ids are short).
const MAX_PROGRESS_ID: usize = 256;

impl Cancellations {
    /// Notes the `arguments` of a `cancel` request (`requestId`, `progressId`).
    pub fn note(&self, arguments: &Value) {
        let mut noted = Vec::new();
        if let Some(seq) = arguments.get("requestId").and_then(Value::as_i64) {
            noted.push(Cancelled::Request(seq));
        }
        if let Some(id) = arguments.get("progressId").and_then(Value::as_str) {
            if id.len() <= MAX_PROGRESS_ID {
                noted.push(Cancelled::Progress(id.to_string()));
            }
        }
        let mut seen = self
            .seen
            .lock()
            .unwrap_or_else(|poison| poison.into_inner());
        for cancelled in noted {
            if seen.len() == KEPT {
                seen.pop_front();
            }
            seen.push_back(cancelled);
        }
    }

    /// True when the request `seq`, or the progress `progress_id`, was cancelled.
    pub fn cancelled(&self, seq: i64, progress_id: Option<&str>) -> bool {
        let seen = self
            .seen
            .lock()
            .unwrap_or_else(|poison| poison.into_inner());
        seen.iter().any(|cancelled| match cancelled {
            Cancelled::Request(cancelled) => *cancelled == seq,
            Cancelled::Progress(id) => progress_id == Some(id.as_str()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn requests_and_progresses_are_noted_and_bounded() {
        let cancellations = Cancellations::default();
        assert!(!cancellations.cancelled(7, Some("run-7")));
        cancellations.note(&json!({ "requestId": 7 }));
        assert!(cancellations.cancelled(7, None));
        assert!(!cancellations.cancelled(8, Some("run-8")));
        cancellations.note(&json!({ "progressId": "run-8" }));
        assert!(cancellations.cancelled(8, Some("run-8")));
        // A clone shares the list (the reader thread notes, the session asks).
        let reader = cancellations.clone();
        for seq in 100..300 {
            reader.note(&json!({ "requestId": seq }));
        }
        assert!(cancellations.cancelled(299, None));
        assert!(!cancellations.cancelled(7, None), "the oldest are dropped");
        cancellations.note(&json!({ "progressId": "x".repeat(10_000) }));
        cancellations.note(&json!("not an object"));
        assert!(cancellations.cancelled(299, None));
    }
}
