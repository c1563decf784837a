//! The end of the client's input ends the server (found by the protocol abuse
//! tests in cli/tests/protocol_abuse.rs: `gloc lsp` hung forever once stdin
//! closed, because the sanitizer's pipe was never closed).

use std::time::Duration;

#[tokio::test]
async fn end_of_input_ends_the_session_without_shutdown() {
    let initialize =
        r#"{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}"#;
    for input in [
        String::new(),
        format!("Content-Length: {}\r\n\r\n{initialize}", initialize.len()),
        // A truncated frame, then nothing.
        "Content-Length: 200\r\n\r\n{\"jsonrpc\":".to_string(),
    ] {
        let (output, _keep_open) = tokio::io::duplex(1 << 20);
        let ending = tokio::time::timeout(
            Duration::from_secs(20),
            gloc_lsp::serve(std::io::Cursor::new(input.clone().into_bytes()), output),
        )
        .await
        .unwrap_or_else(|_| panic!("the server hung after its input ended: {input:?}"));
        assert_eq!(ending, gloc_lsp::Ending::WithoutShutdown, "{input:?}");
    }
}
