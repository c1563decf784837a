"""gloc lsp through pytest-lsp (pygls + lsprotocol's types): a third language-server client,
besides Neovim and VS Code's. pytest-lsp checks every answer against the capabilities the client
announced (no snippet to a client without snippet support); the tests check the rest: markdown,
symbol shapes, UTF-16 positions, CRLF documents and GLOC label renames.
Run from tests/e2e/run (GLOC_BIN is the binary under test)."""

import os
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

REPO = Path(__file__).resolve().parents[3]
GLOC = os.environ.get("GLOC_BIN", str(REPO / "target" / "debug" / "gloc"))
FIG2 = (REPO / "examples" / "fig2.gloc").read_text()
FIG3 = (REPO / "examples" / "fig3.gbas").read_text()

# A client that shows neither snippets nor markdown and wants the flat symbol list: what the
# protocol assumes of a client that says nothing more.
RESTRICTED = types.ClientCapabilities(
    text_document=types.TextDocumentClientCapabilities(
        completion=types.CompletionClientCapabilities(
            completion_item=types.ClientCompletionItemOptions(
                snippet_support=False, documentation_format=[types.MarkupKind.PlainText]
            )
        ),
        hover=types.HoverClientCapabilities(content_format=[types.MarkupKind.PlainText]),
        document_symbol=types.DocumentSymbolClientCapabilities(hierarchical_document_symbol_support=False),
    )
)

CONFIG = ClientServerConfig(server_command=[GLOC, "lsp"])


async def start(client: LanguageClient, capabilities, tmp_path: Path):
    # VS Code's capabilities allow dynamic registration: the server registers its file watchers.
    client.feature(types.CLIENT_REGISTER_CAPABILITY)(lambda params: None)
    await client.initialize_session(
        types.InitializeParams(capabilities=capabilities, root_uri=tmp_path.as_uri(), workspace_folders=None)
    )


def open_document(client: LanguageClient, path: Path, language: str, text: str) -> str:
    path.write_text(text, newline="")
    uri = path.as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id=language, version=1, text=text)
        )
    )
    return uri


def utf16_column(line: str, index: int) -> int:
    """The UTF-16 column of the character at `index` of `line` (what LSP positions count)."""
    return len(line[:index].encode("utf-16-le")) // 2


@pytest_lsp.fixture(config=CONFIG)
async def restricted(lsp_client: LanguageClient, tmp_path):
    await start(lsp_client, RESTRICTED, tmp_path)
    yield
    await lsp_client.shutdown_session()


@pytest_lsp.fixture(config=CONFIG)
async def vscode(lsp_client: LanguageClient, tmp_path):
    await start(lsp_client, client_capabilities("visual-studio-code"), tmp_path)
    yield
    await lsp_client.shutdown_session()


def items_of(result):
    return result.items if isinstance(result, types.CompletionList) else result


async def test_restricted_client_gets_plain_completions(restricted, tmp_path):
    lsp_client = restricted
    uri = open_document(lsp_client, tmp_path / "a.gbas", "gbasic", "dim x as float\nx = ab\n")
    result = await lsp_client.text_document_completion_async(
        types.CompletionParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=1, character=6))
    )
    items = {item.label: item for item in items_of(result)}
    assert "abs" in items, sorted(items)[:20]
    assert all(item.insert_text_format != types.InsertTextFormat.Snippet for item in items.values())
    # `abs($1)` as a snippet; without snippets the call with its tab stop removed, inserted
    # through a text edit over the typed `ab` (line 1, characters 4-6), never `insertText`.
    assert items["abs"].insert_text is None
    assert items["abs"].text_edit.new_text == "abs()"
    assert items["abs"].text_edit.range == types.Range(
        start=types.Position(line=1, character=4), end=types.Position(line=1, character=6)
    )
    for item in items.values():
        if isinstance(item.documentation, types.MarkupContent):
            assert item.documentation.kind == types.MarkupKind.PlainText, item


async def test_vscode_client_gets_snippets_and_markdown(vscode, tmp_path):
    lsp_client = vscode
    uri = open_document(lsp_client, tmp_path / "a.gbas", "gbasic", "dim x as float\nx = ab\n")
    result = await lsp_client.text_document_completion_async(
        types.CompletionParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=1, character=6))
    )
    items = {item.label: item for item in items_of(result)}
    assert items["abs"].text_edit.new_text == "abs($1)"
    assert items["abs"].insert_text_format == types.InsertTextFormat.Snippet


async def test_restricted_client_gets_plaintext_hover(restricted, tmp_path):
    lsp_client = restricted
    uri = open_document(lsp_client, tmp_path / "fig3.gbas", "gbasic", FIG3)
    hover = await lsp_client.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=1, character=5))
    )
    assert hover.contents.kind == types.MarkupKind.PlainText
    assert "m_depth" in hover.contents.value
    assert "`" not in hover.contents.value and "**" not in hover.contents.value, hover.contents.value


async def test_vscode_client_gets_markdown_hover(vscode, tmp_path):
    lsp_client = vscode
    uri = open_document(lsp_client, tmp_path / "fig3.gbas", "gbasic", FIG3)
    hover = await lsp_client.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=1, character=5))
    )
    assert hover.contents.kind == types.MarkupKind.Markdown


async def test_restricted_client_gets_flat_symbols(restricted, tmp_path):
    lsp_client = restricted
    uri = open_document(lsp_client, tmp_path / "fig3.gbas", "gbasic", FIG3)
    symbols = await lsp_client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=types.TextDocumentIdentifier(uri=uri))
    )
    assert symbols and all(isinstance(symbol, types.SymbolInformation) for symbol in symbols), symbols
    labels = {symbol.name: symbol.location for symbol in symbols}
    assert set(labels) == {"state1", "state2", "state3"}
    # `label: state2` is line 8 (0-based 7); the name starts at column 7.
    assert labels["state2"].uri == uri
    assert labels["state2"].range.start == types.Position(line=7, character=7)


async def test_vscode_client_gets_nested_symbols(vscode, tmp_path):
    lsp_client = vscode
    uri = open_document(lsp_client, tmp_path / "fig3.gbas", "gbasic", FIG3)
    symbols = await lsp_client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=types.TextDocumentIdentifier(uri=uri))
    )
    assert symbols and all(isinstance(symbol, types.DocumentSymbol) for symbol in symbols), symbols


async def test_utf16_positions_after_astral_characters(vscode, tmp_path):
    lsp_client = vscode
    # Two waves (each two UTF-16 code units, four UTF-8 bytes) before the sensor on the line.
    line = 'print "🌊🌊 depth", m_depth, nosuch_sensor'
    uri = open_document(lsp_client, tmp_path / "u.gbas", "gbasic", line + "\nyield\n")
    await lsp_client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    start = utf16_column(line, line.index("m_depth"))
    assert start == line.index("m_depth") + 2
    hover = await lsp_client.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=0, character=start + 1))
    )
    assert hover is not None and "m_depth" in hover.contents.value
    assert hover.range == types.Range(start=types.Position(line=0, character=start), end=types.Position(line=0, character=start + 7))
    diagnostics = lsp_client.diagnostics[uri]
    bad = utf16_column(line, line.index("nosuch_sensor"))
    assert any(d.range.start == types.Position(line=0, character=bad) for d in diagnostics), diagnostics


async def test_formatting_a_canonical_crlf_document_changes_nothing(vscode, tmp_path):
    lsp_client = vscode
    options = types.FormattingOptions(tab_size=2, insert_spaces=True)
    # The canonical form, from the server itself on the LF text, must be a fixed point there too.
    lf_uri = open_document(lsp_client, tmp_path / "lf.gloc", "gloc", FIG2)
    edits = await lsp_client.text_document_formatting_async(
        types.DocumentFormattingParams(text_document=types.TextDocumentIdentifier(uri=lf_uri), options=options)
    )
    assert not edits, "examples/fig2.gloc is in canonical form"
    crlf_uri = open_document(lsp_client, tmp_path / "crlf.gloc", "gloc", FIG2.replace("\n", "\r\n"))
    edits = await lsp_client.text_document_formatting_async(
        types.DocumentFormattingParams(text_document=types.TextDocumentIdentifier(uri=crlf_uri), options=options)
    )
    assert not edits, edits
    # A CRLF document that needs formatting keeps CRLF in the edit.
    messy = FIG2.replace("loads 444,r0", "loads   444 , r0").replace("\n", "\r\n")
    messy_uri = open_document(lsp_client, tmp_path / "messy.gloc", "gloc", messy)
    edits = await lsp_client.text_document_formatting_async(
        types.DocumentFormattingParams(text_document=types.TextDocumentIdentifier(uri=messy_uri), options=options)
    )
    assert len(edits) == 1, edits
    assert "loads 444,r0" in edits[0].new_text
    assert "\n" not in edits[0].new_text.replace("\r\n", ""), repr(edits[0].new_text)


async def test_renaming_a_gloc_label_past_nblbs_is_refused(vscode, tmp_path):
    lsp_client = vscode
    uri = open_document(lsp_client, tmp_path / "fig2.gloc", "gloc", FIG2)
    lines = FIG2.splitlines()
    line = lines.index("label 3")
    position = types.Position(line=line, character=6)
    # fig2.gloc says `nblbs 7`: labels 0 to 6, all defined. 7 would break the program (E0102).
    for taken_or_out_of_range in ("7", "100", "5"):
        with pytest.raises(Exception) as refused:
            await lsp_client.text_document_rename_async(
                types.RenameParams(text_document=types.TextDocumentIdentifier(uri=uri), position=position, new_name=taken_or_out_of_range)
            )
        assert "nblbs" in str(refused.value) or "already exists" in str(refused.value), str(refused.value)
    # Raising nblbs first makes 7 a free label number.
    raised = FIG2.replace("nblbs 7", "nblbs 8")
    uri = open_document(lsp_client, tmp_path / "raised.gloc", "gloc", raised)
    edit = await lsp_client.text_document_rename_async(
        types.RenameParams(text_document=types.TextDocumentIdentifier(uri=uri), position=position, new_name="7")
    )
    assert edit is not None and len(edit.changes[uri]) == 2  # `label 3` and `cbr r2,3,4`
