//! `# sensors: CRC` through the protocol: the language server reports every index
//! whose name differs from the stated list (E0113), one W0114 without the line, and
//! finds a third list beside the document. Names read by hand from
//! `data/cac/1f35be3b.cac` (444 `m_certainly_at_surface`, 459 `m_depth`,
//! 1387 `sci_whfctd_ref_lo`).

mod support;

use serde_json::{json, Value};
use support::TestClient;

const FIG2: &str = include_str!("../../examples/fig2.gloc");

fn comet_cac() -> String {
    gloc_testsupport::data_arg("cac/1f35be3b.cac")
}

fn range(line: u32, start: u32, end: u32) -> Value {
    json!({ "start": { "line": line, "character": start }, "end": { "line": line, "character": end } })
}

/// (code, range, first line of the message: the server appends the help) of each
/// diagnostic.
fn summary(published: &Value) -> Vec<(String, Value, String)> {
    published["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|diagnostic| {
            (
                diagnostic["code"].as_str().unwrap_or("").to_string(),
                diagnostic["range"].clone(),
                diagnostic["message"]
                    .as_str()
                    .unwrap_or("")
                    .lines()
                    .next()
                    .unwrap_or("")
                    .to_string(),
            )
        })
        .collect()
}

#[tokio::test]
async fn a_stated_list_checked_against_comets_list_reports_each_index() {
    let mut client =
        TestClient::initialized_with(json!({}), json!({ "gloc": { "masterdata": comet_cac() } }))
            .await;
    let uri = "file:///nowhere/stated.gloc";
    let text = format!("# sensors: 813b137d\n{FIG2}");
    let published = client.open(uri, "gloc", &text).await;
    let depth = "index 444 is `m_depth` in 813b137d but `m_certainly_at_surface` in 1f35be3b";
    let behs = "index 1387 is `sci_ruhp_behs` in 813b137d but `sci_whfctd_ref_lo` in 1f35be3b";
    assert_eq!(
        summary(&published),
        [
            ("E0113".to_string(), range(5, 6, 9), depth.to_string()),
            ("E0113".to_string(), range(11, 10, 14), behs.to_string()),
            ("E0113".to_string(), range(17, 6, 9), depth.to_string()),
            ("E0113".to_string(), range(23, 10, 14), behs.to_string()),
        ]
    );
    // Deleting the line: one warning at the first index.
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": uri, "version": 2 },
                    "contentChanges": [{ "range": { "start": { "line": 0, "character": 0 },
                                                    "end": { "line": 1, "character": 0 } },
                                         "text": "" }] }),
        )
        .await;
    let latest = client.latest_diagnostics(uri).await;
    let found = summary(&latest);
    assert_eq!(found.len(), 1, "{latest}");
    assert_eq!(
        (found[0].0.as_str(), &found[0].1),
        ("W0114", &range(4, 6, 9))
    );
}

#[tokio::test]
async fn a_third_list_beside_the_document_is_found() {
    let folder = gloc_testsupport::scratch_dir("lsp-identity");
    std::fs::create_dir_all(&folder).expect("dir");
    let mut client = TestClient::initialized().await;
    let uri = format!("file://{}/comet.gloc", folder.display());
    let text = format!("# sensors: 1f35be3b\n{}", FIG2.replace("444,", "459,"));
    // Not there yet: W0115 on the CRC.
    let published = client.open(&uri, "gloc", &text).await;
    let found = summary(&published);
    assert_eq!(found.len(), 1, "{published}");
    assert_eq!(
        (found[0].0.as_str(), &found[0].1),
        ("W0115", &range(0, 11, 19))
    );
    // Beside it: each differing index (459 is `f_ocean_pressure_max` in 813b137d.cac).
    std::fs::copy(comet_cac(), folder.join("1f35be3b.cac")).expect("copy");
    client
        .notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": uri, "version": 2 },
                    "contentChanges": [{ "text": text.clone() + "\n" }] }),
        )
        .await;
    let latest = client.latest_diagnostics(&uri).await;
    let found = summary(&latest);
    assert_eq!(found.len(), 4, "{latest}");
    assert_eq!(
        found[0],
        (
            "E0113".to_string(),
            range(5, 6, 9),
            "index 459 is `m_depth` in 1f35be3b but `f_ocean_pressure_max` in 813b137d".to_string()
        )
    );
    std::fs::remove_dir_all(&folder).expect("cleanup");
}
