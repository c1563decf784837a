"""gloc lsp at scale and the navigation features, through pytest-lsp (pygls + lsprotocol): completion
ranked and cut on the server with documentation on resolve, semantic tokens range and delta, pull
diagnostics, code lens, workspace symbols, selection ranges, document links and range formatting.
Run from tests/e2e/run (GLOC_BIN is the binary under test)."""

import asyncio
import os
from pathlib import Path

import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

REPO = Path(__file__).resolve().parents[3]
GLOC = os.environ.get("GLOC_BIN", str(REPO / "target" / "debug" / "gloc"))
FIG3 = (REPO / "examples" / "fig3.gbas").read_text()
CONFIG = ClientServerConfig(server_command=[GLOC, "lsp"])


def editor():
    """VS Code's capabilities, plus pull diagnostics and the two code lens commands the gloc
    extension runs (declared as rust-analyzer does, in experimental.commands)."""
    capabilities = client_capabilities("visual-studio-code")
    capabilities.text_document.diagnostic = types.DiagnosticClientCapabilities(dynamic_registration=False)
    capabilities.experimental = {"commands": {"commands": ["gloc.runMission", "gloc.debugScript"]}}
    return capabilities


async def start(client: LanguageClient, capabilities, tmp_path: Path, options=None):
    client.feature(types.CLIENT_REGISTER_CAPABILITY)(lambda params: None)
    return await client.initialize_session(
        types.InitializeParams(
            capabilities=capabilities,
            root_uri=tmp_path.as_uri(),
            workspace_folders=[types.WorkspaceFolder(uri=tmp_path.as_uri(), name="w")],
            initialization_options=options,
        )
    )


def open_document(client: LanguageClient, path: Path, language: str, text: str, write=True) -> str:
    if write:
        path.write_text(text, newline="")
    uri = path.as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id=language, version=1, text=text)
        )
    )
    return uri


def doc(uri):
    return types.TextDocumentIdentifier(uri=uri)


def at(line, character):
    return types.Position(line=line, character=character)


async def complete(client, uri, line, character):
    return await client.text_document_completion_async(types.CompletionParams(text_document=doc(uri), position=at(line, character)))


@pytest_lsp.fixture(config=CONFIG)
async def vscode(lsp_client: LanguageClient, tmp_path):
    lsp_client.initialize_result = await start(lsp_client, editor(), tmp_path)
    yield
    await lsp_client.shutdown_session()


@pytest_lsp.fixture(config=CONFIG)
async def plain(lsp_client: LanguageClient, tmp_path):
    """A client that says nothing: no resolve, no pull, no commands; a completion limit of 5."""
    await start(lsp_client, types.ClientCapabilities(), tmp_path, {"completionLimit": 5})
    yield
    await lsp_client.shutdown_session()


async def test_completion_is_ranked_cut_and_resolved(vscode, tmp_path):
    client = vscode
    options = client.initialize_result.capabilities.completion_provider
    assert " " not in options.trigger_characters and options.resolve_provider
    # Nothing typed at the start of a statement: the first 100 of about 1,400, cut.
    uri = open_document(client, tmp_path / "a.gbas", "gbasic", "\n")
    result = await complete(client, uri, 0, 0)
    assert result.is_incomplete and len(result.items) == 100
    assert all(item.documentation is None for item in result.items), "documentation waits for resolve"
    # `m_dep` where a store goes: m_depth is read-only, yet offered first (every m_ sensor is
    # read-only, so the shortest prefix match wins) and marked.
    uri = open_document(client, tmp_path / "b.gbas", "gbasic", "m_dep\n")
    result = await complete(client, uri, 0, 5)
    first = result.items[0]
    assert first.label == "m_depth" and first.detail == "sensor 444 (m), read-only: cannot be stored"
    assert all(item.label.startswith("m_dep") for item in result.items[:5]), [i.label for i in result.items[:5]]
    assert [item.sort_text for item in result.items] == sorted(item.sort_text for item in result.items)
    resolved = await client.completion_item_resolve_async(first)
    assert resolved.documentation.kind == types.MarkupKind.Markdown
    assert "Measured depth" in resolved.documentation.value


async def test_a_client_without_resolve_gets_documentation_inline_and_its_limit(plain, tmp_path):
    client = plain
    uri = open_document(client, tmp_path / "a.gbas", "gbasic", "x = m_dep\n")
    result = await complete(client, uri, 0, 9)
    assert len(result.items) == 5 and result.is_incomplete
    assert result.items[0].label == "m_depth"
    assert "Measured depth" in result.items[0].documentation.value


def absolute(data):
    """Semantic tokens as (line, start, length, type, modifiers) from the relative encoding."""
    tokens, line, start = [], 0, 0
    for index in range(0, len(data), 5):
        delta_line, delta_start, length, kind, modifiers = data[index : index + 5]
        line += delta_line
        start = start + delta_start if delta_line == 0 else delta_start
        tokens.append((line, start, length, kind, modifiers))
    return tokens


def apply_edits(data, edits):
    data = list(data)
    for edit in sorted(edits, key=lambda e: e.start, reverse=True):
        data[edit.start : edit.start + edit.delete_count] = edit.data or []
    return data


async def test_semantic_tokens_range_and_delta_agree_with_full(vscode, tmp_path):
    client = vscode
    provider = client.initialize_result.capabilities.semantic_tokens_provider
    assert provider.range and provider.full.delta
    uri = open_document(client, tmp_path / "fig3.gbas", "gbasic", FIG3)
    full = await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=doc(uri)))
    assert full.result_id
    # Range: exactly the full answer's tokens on lines 7 to 11.
    ranged = await client.text_document_semantic_tokens_range_async(
        types.SemanticTokensRangeParams(text_document=doc(uri), range=types.Range(start=at(7, 0), end=at(12, 0)))
    )
    expected = [token for token in absolute(full.data) if 7 <= token[0] <= 11]
    assert expected and absolute(ranged.data) == expected
    # An edit in the middle: the delta applied to the previous data gives a fresh full answer,
    # and is smaller than it.
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[types.TextDocumentContentChangePartial(range=types.Range(start=at(8, 0), end=at(8, 0)), text="x = 1\n")],
        )
    )
    delta = await client.text_document_semantic_tokens_full_delta_async(
        types.SemanticTokensDeltaParams(text_document=doc(uri), previous_result_id=full.result_id)
    )
    assert isinstance(delta, types.SemanticTokensDelta), delta
    fresh = await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=doc(uri)))
    assert apply_edits(full.data, delta.edits) == list(fresh.data)
    assert sum(len(edit.data or []) for edit in delta.edits) < len(fresh.data) / 2
    # An unknown previous id gets every token.
    again = await client.text_document_semantic_tokens_full_delta_async(
        types.SemanticTokensDeltaParams(text_document=doc(uri), previous_result_id="no such id")
    )
    assert isinstance(again, types.SemanticTokens) and list(again.data) == list(fresh.data)


async def test_pull_diagnostics_replace_push_for_a_client_that_pulls(vscode, tmp_path):
    client = vscode
    assert client.initialize_result.capabilities.diagnostic_provider is not None
    uri = open_document(client, tmp_path / "bad.gbas", "gbasic", "m_depth = 1\nyield\n")
    report = await client.text_document_diagnostic_async(types.DocumentDiagnosticParams(text_document=doc(uri)))
    assert report.kind == "full"
    # E2105: a store to a read-only sensor (GBASIC's code; the message names m_depth).
    assert [item.code for item in report.items] == ["E2105"], report.items
    assert "m_depth" in report.items[0].message
    assert report.items[0].range.start == at(0, 0)
    # Nothing is pushed for it (the server publishes within a message or two of an edit).
    await asyncio.sleep(1.0)
    assert uri not in client.diagnostics


async def test_code_lens_figures_and_commands(vscode, tmp_path):
    client = vscode
    uri = open_document(client, tmp_path / "fig3.gbas", "gbasic", FIG3)
    lenses = await client.text_document_code_lens_async(types.CodeLensParams(text_document=doc(uri)))
    commands = [(lens.command.title, lens.command.command, list(lens.command.arguments)) for lens in lenses if lens.command.command]
    assert commands == [("▶ Run in simulator", "gloc.runMission", [uri]), ("Debug", "gloc.debugScript", [uri])]
    figures = {lens.range.start.line: lens.command.title for lens in lenses if not lens.command.command}
    # Counted by hand on the compiled program (the paper's Fig. 2): state1 holds the first cycle
    # (15) and the one after its yield (jumpi 0, then 4 + 3 + 4 + 3 instructions and the yield:
    # 16); state2's yield: jumpi 1, 4, 3, yield = 9; state3's: jumpi 2, yield = 2.
    assert figures == {
        0: "≤ 16 instr per cycle (2 cycles start here)",
        7: "≤ 9 instr per cycle (1 cycle starts here)",
        14: "≤ 2 instr per cycle (1 cycle starts here)",
    }


async def test_no_run_or_debug_lens_for_a_client_without_those_commands(plain, tmp_path):
    client = plain
    uri = open_document(client, tmp_path / "fig3.gbas", "gbasic", FIG3)
    lenses = await client.text_document_code_lens_async(types.CodeLensParams(text_document=doc(uri)))
    assert len(lenses) == 3 and all(lens.command.command == "" for lens in lenses)


async def test_workspace_symbols_from_disk_and_open_documents(vscode, tmp_path):
    client = vscode
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "on_disk.gbas").write_text("label: alpha_state\nyield\ngoto alpha_state\n")
    (tmp_path / "node_modules").mkdir()
    (tmp_path / "node_modules" / "skipped.gbas").write_text("label: alpha_hidden\nyield\ngoto alpha_hidden\n")
    # Open with unsaved text: the editor's text wins over the file's.
    (tmp_path / "open.gbas").write_text("label: old_name\nyield\ngoto old_name\n")
    uri = open_document(client, tmp_path / "open.gbas", "gbasic", "dim beta_count as integer\nlabel: beta_open\nyield\ngoto beta_open\n", write=False)
    found = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="alpha"))
    assert [(s.name, s.location.uri) for s in found] == [("alpha_state", (tmp_path / "sub" / "on_disk.gbas").as_uri())]
    found = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="beta"))
    assert sorted((s.name, s.kind, s.location.uri, s.location.range.start.line) for s in found) == [
        ("beta_count", types.SymbolKind.Variable, uri, 0),
        ("beta_open", types.SymbolKind.Function, uri, 1),
    ]
    assert not await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="old_name"))


async def test_selection_ranges_grow_from_the_word(vscode, tmp_path):
    client = vscode
    text = "dim x as float\nif x > 1 then\n  c_pitch = max(-0.4, min(0.4, m_pitch))\nendif\nyield\n"
    uri = open_document(client, tmp_path / "s.gbas", "gbasic", text)
    line = text.splitlines()[2]
    column = line.index("m_pitch") + 2
    [selection] = await client.text_document_selection_range_async(
        types.SelectionRangeParams(text_document=doc(uri), positions=[at(2, column)])
    )
    lines = text.split("\n")
    pieces = []
    while selection:
        r = selection.range
        if r.start.line == r.end.line:
            pieces.append(lines[r.start.line][r.start.character : r.end.character])
        else:
            pieces.append((r.start.line, r.end.line))
        selection = selection.parent
    assert pieces[:4] == ["m_pitch", "(0.4, m_pitch)", "(-0.4, min(0.4, m_pitch))", line.strip()]
    assert pieces[4] == (1, 3), pieces  # the if block
    assert pieces[-1] == (0, 5), pieces  # the document


async def test_gloc_toml_paths_are_links(vscode, tmp_path):
    client = vscode
    text = 'masterdata = "config/masterdata.mi"\ncycle_budget = 2000\nmission = "missions/yo.mi"\n'
    uri = open_document(client, tmp_path / "gloc.toml", "toml", text)
    links = await client.text_document_document_link_async(types.DocumentLinkParams(text_document=doc(uri)))
    got = [(link.range.start.line, link.range.start.character, link.range.end.character, link.target) for link in links]
    assert got == [
        (0, 14, 34, (tmp_path / "config" / "masterdata.mi").as_uri()),
        (2, 11, 25, (tmp_path / "missions" / "yo.mi").as_uri()),
    ]


async def test_range_formatting_touches_only_the_range(vscode, tmp_path):
    client = vscode
    uri = open_document(client, tmp_path / "f.gbas", "gbasic", "if 1 then\nx = 1\ny = 2\nendif\nyield\n")
    options = types.FormattingOptions(tab_size=2, insert_spaces=True)
    edits = await client.text_document_range_formatting_async(
        types.DocumentRangeFormattingParams(text_document=doc(uri), range=types.Range(start=at(2, 0), end=at(2, 3)), options=options)
    )
    assert [(e.range.start, e.range.end, e.new_text) for e in edits] == [(at(2, 0), at(2, 5), "  y = 2")]


async def test_args_from_file_lines_link_to_their_ma_files(vscode, tmp_path):
    client = vscode
    (tmp_path / "missions").mkdir()
    (tmp_path / "mafiles").mkdir()
    # `surface` + 10 is `surfac10.ma` (the glider's 8.3 names), beside the missions folder.
    (tmp_path / "mafiles" / "surfac10.ma").write_text("behavior_name=surface\n<start:b_arg>\n<end:b_arg>\n")
    text = "behavior: surface\n  b_arg: args_from_file(enum) 10\n"
    uri = open_document(client, tmp_path / "missions" / "m.mi", "slocum_mission", text)
    links = await client.text_document_document_link_async(types.DocumentLinkParams(text_document=doc(uri)))
    assert [(link.range.start.line, link.target) for link in links] == [(1, (tmp_path / "mafiles" / "surfac10.ma").resolve().as_uri())]


async def test_a_mission_file_gets_no_run_or_debug_lens(vscode, tmp_path):
    client = vscode
    uri = open_document(client, tmp_path / "m.mi", "slocum_mission", "behavior: surface\n  b_arg: start_when(enum) 9\n")
    lenses = await client.text_document_code_lens_async(types.CodeLensParams(text_document=doc(uri)))
    assert not lenses


@pytest_lsp.fixture(config=CONFIG)
async def refreshing(lsp_client: LanguageClient, tmp_path):
    """A client that pulls diagnostics and accepts workspace/diagnostic/refresh."""
    capabilities = editor()
    capabilities.workspace.diagnostics = types.DiagnosticWorkspaceClientCapabilities(refresh_support=True)
    # Settings come from didChangeConfiguration only (this client has no workspace/configuration
    # answer that would replace them).
    capabilities.workspace.configuration = False
    await start(lsp_client, capabilities, tmp_path)
    yield
    await lsp_client.shutdown_session()


async def test_changed_settings_ask_a_pulling_client_to_pull_again(refreshing, tmp_path):
    client = refreshing
    uri = open_document(client, tmp_path / "a.gbas", "gbasic", "yield\n")
    await client.text_document_diagnostic_async(types.DocumentDiagnosticParams(text_document=doc(uri)))
    missing = str(tmp_path / "no-such-masterdata")
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(settings={"gloc": {"masterdata": missing}}))
    # pytest-lsp counts the refresh requests it answers.
    for _ in range(200):
        if client.diagnostic_refresh_count:
            break
        await asyncio.sleep(0.05)
    assert client.diagnostic_refresh_count >= 1
    # And the pulled report follows the new settings: a masterdata file that cannot be
    # loaded is an E0903 on the script (README, "Project settings").
    report = await client.text_document_diagnostic_async(types.DocumentDiagnosticParams(text_document=doc(uri)))
    assert [item.code for item in report.items] == ["E0903"], report
