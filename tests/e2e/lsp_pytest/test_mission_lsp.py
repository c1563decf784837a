"""Mission files (.mi) and mission argument files (.ma) through pytest-lsp: the diagnostics
gloc lsp publishes are the ones `gloc run` prints for the same mission (compared with the real
CLI), completion of behaviors' arguments with units, defaults and docs, hover, go to the .ma file
an args_from_file loads, behaviors as symbols and folds, and formatting that keeps the layout of
comet's real mission files. Run from tests/e2e/run (GLOC_BIN is the binary under test)."""

import asyncio
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from test_gloc_lsp import GLOC, REPO, open_document, vscode  # noqa: F401 (vscode is a fixture)

COMET = REPO / "data" / "comet"
CAC = REPO / "data" / "813b137d.cac"

MISSION = """\
# a hand-made mission: a yo from a .ma file, an abend with a bad value
behavior: abend
    b_arg: overdepth(m)    deep    # not a number
    b_arg: overtime(s)     -1

behavior: yo
    b_arg: args_from_file(enum) 10   # mafiles/yo10.ma
"""

YO10 = """\
behavior_name=Yo
<start:b_arg>
\tb_arg: d_target_depth(m) 25
\tb_arg: c_target_depth(m) shallow
\tb_arg: bogus(m) 1
<end:b_arg>
"""


def write_mission(tmp_path: Path) -> Path:
    (tmp_path / "missions").mkdir()
    (tmp_path / "mafiles").mkdir()
    (tmp_path / "mafiles" / "yo10.ma").write_text(YO10)
    return tmp_path / "missions" / "t.mi"


async def diagnostics_of(client: LanguageClient, uri: str):
    for _ in range(200):
        if uri in client.diagnostics:
            return client.diagnostics[uri]
        await asyncio.sleep(0.05)
    raise AssertionError(f"no diagnostics for {uri}")


def gloc_run_problems(mission: Path):
    """(file name, line, column, code, message) of every problem `gloc run` prints."""
    run = subprocess.run(
        [GLOC, "run", "--mission", str(mission), "--cycles", "1", str(REPO / "examples" / "fig2.gloc")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    found = re.findall(r"^(\S+?):(\d+):(\d+): (?:error|warning)\[(S\d{4})\]: (.*)$", run.stderr, re.M)
    assert found, run.stderr
    return [(Path(path).name, int(line), int(column), code, message) for path, line, column, code, message in found]


async def test_diagnostics_are_what_gloc_run_prints(vscode, tmp_path):  # noqa: F811
    path = write_mission(tmp_path)
    uri = open_document(vscode, path, "slocum_mission", MISSION)
    published = await diagnostics_of(vscode, uri)
    expected = gloc_run_problems(path)
    # Three problems: `deep` on t.mi's line 3, `shallow` and `bogus` on yo10.ma's lines 4 and 5.
    assert sorted((name, line, code) for name, line, _, code, _ in expected) == [
        ("t.mi", 3, "S0015"),
        ("yo10.ma", 4, "S0015"),
        ("yo10.ma", 5, "S0103"),
    ]
    load_line = MISSION.splitlines().index("    b_arg: args_from_file(enum) 10   # mafiles/yo10.ma")
    got = sorted((d.code, d.range.start.line, d.range.start.character, d.message.split("\nhelp:")[0]) for d in published)
    want = []
    for name, line, column, code, message in expected:
        if name == "t.mi":
            want.append((code, line - 1, column - 1, message.split(" (help:")[0]))
        else:
            # A .ma file's problem sits on the args_from_file line that loaded it, named.
            want.append((code, load_line, 4, f"{name}:{line}:{column}: {message.split(' (help:')[0]}"))
    assert got == sorted(want)


async def test_a_ma_file_alone_gets_its_own_diagnostics(vscode, tmp_path):  # noqa: F811
    uri = open_document(vscode, tmp_path / "yo10.ma", "slocum_ma", YO10)
    published = await diagnostics_of(vscode, uri)
    assert sorted((d.code, d.range.start.line) for d in published) == [("S0015", 3), ("S0103", 4)]


async def test_argument_completion_has_units_default_and_doc(vscode, tmp_path):  # noqa: F811
    text = "behavior: yo\n    b_arg: d_ta"
    uri = open_document(vscode, tmp_path / "c.mi", "slocum_mission", text)
    result = await vscode.text_document_completion_async(
        types.CompletionParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            position=types.Position(line=1, character=len("    b_arg: d_ta")),
        )
    )
    items = result.items if isinstance(result, types.CompletionList) else result
    depth = next(item for item in items if item.label == "d_target_depth")
    assert depth.detail == "(m) default 12"
    assert depth.text_edit.new_text == "d_target_depth(m) ${1:12}"
    assert depth.insert_text_format == types.InsertTextFormat.Snippet
    documentation = depth.documentation
    if documentation is None:  # deferred to completionItem/resolve
        documentation = (await vscode.completion_item_resolve_async(depth)).documentation
    assert "Dive: turn at this depth." in documentation.value
    behaviors = await vscode.text_document_completion_async(
        types.CompletionParams(
            # Right after `behavior: ` (nothing typed): the server filters by the typed word.
            text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=0, character=10)
        )
    )
    labels = {item.label for item in (behaviors.items if isinstance(behaviors, types.CompletionList) else behaviors)}
    assert {"abend", "surface", "yo", "goto_list", "sample", "hook", "gloc"} <= labels


async def test_hover_and_go_to_the_ma_file(vscode, tmp_path):  # noqa: F811
    path = write_mission(tmp_path)
    uri = open_document(vscode, path, "slocum_mission", MISSION)
    hover = await vscode.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=2, character=14))
    )
    assert hover.contents.value.startswith("**overdepth**(m) · abend · default 10000")
    assert (hover.range.start.character, hover.range.end.character) == (11, 20)
    definition = await vscode.text_document_definition_async(
        types.DefinitionParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=6, character=20))
    )
    location = definition[0] if isinstance(definition, list) else definition
    target = location.uri if isinstance(location, types.Location) else location.target_uri
    assert target == (tmp_path / "mafiles" / "yo10.ma").as_uri()


async def test_behaviors_are_symbols_and_folds(vscode, tmp_path):  # noqa: F811
    path = write_mission(tmp_path)
    uri = open_document(vscode, path, "slocum_mission", MISSION)
    symbols = await vscode.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=types.TextDocumentIdentifier(uri=uri))
    )
    assert [(s.name, s.kind, s.range.start.line, s.range.end.line) for s in symbols] == [
        ("abend", types.SymbolKind.Object, 1, 3),
        ("yo", types.SymbolKind.Object, 5, 6),
    ]
    folds = await vscode.text_document_folding_range_async(
        types.FoldingRangeParams(text_document=types.TextDocumentIdentifier(uri=uri))
    )
    assert sorted((fold.start_line, fold.end_line) for fold in folds) == [(1, 3), (5, 6)]


async def test_formatting_comets_real_mission_only_trims_line_ends(vscode, tmp_path):  # noqa: F811
    shutil.copytree(COMET / "missions", tmp_path / "missions")
    shutil.copytree(COMET / "mafiles", tmp_path / "mafiles")
    path = tmp_path / "missions" / "nsb3.mi"
    text = path.read_text()
    uri = open_document(vscode, path, "slocum_mission", text)
    # The real mission's problems with the embedded 2008 sensor list (sensors it lacks) are
    # the ones gloc run prints for it.
    published = await diagnostics_of(vscode, uri)
    expected = [problem for problem in gloc_run_problems(path) if problem[0] == "nsb3.mi"]
    assert expected
    assert sorted((d.code, d.range.start.line + 1, d.range.start.character + 1) for d in published) == sorted(
        (code, line, column) for _, line, column, code, _ in expected
    )
    edits = await vscode.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            options=types.FormattingOptions(tab_size=8, insert_spaces=False),
        )
    )
    lines = text.split("\n")
    for edit in edits:
        before = lines[: edit.range.start.line] + [lines[edit.range.start.line][: edit.range.start.character]]
        after = [lines[edit.range.end.line][edit.range.end.character :]] + lines[edit.range.end.line + 1 :]
        lines = (("\n".join(before) + edit.new_text + "\n".join(after))).split("\n")
    assert "\n".join(lines) == "\n".join(line.rstrip(" \t") for line in text.split("\n"))


async def test_a_real_cac_list_has_its_sensors_as_symbols_and_hover(vscode, tmp_path):  # noqa: F811
    text = CAC.read_text()
    uri = open_document(vscode, tmp_path / "813b137d.cac", "slocum_masterdata", text)
    symbols = await vscode.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=types.TextDocumentIdentifier(uri=uri))
    )
    lines = text.splitlines()
    sensor_lines = [number for number, line in enumerate(lines) if line.startswith("s:")]
    assert len(symbols) == len(sensor_lines) == 1385
    depth_line = next(number for number, line in enumerate(lines) if line.split()[-2:-1] == ["m_depth"])
    depth = next(symbol for symbol in symbols if symbol.name == "m_depth")
    assert depth.selection_range.start.line == depth_line
    hover = await vscode.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(line=depth_line, character=0))
    )
    # The paper's index of m_depth in this 2008 list (data README).
    assert hover.contents.value.startswith("**m_depth** (m)\n\nsensor 444")


async def test_saving_a_ma_file_checks_the_open_missions_again(vscode, tmp_path):  # noqa: F811
    path = write_mission(tmp_path)
    uri = open_document(vscode, path, "slocum_mission", MISSION)
    before = await diagnostics_of(vscode, uri)
    assert any(d.message.startswith("yo10.ma:") for d in before)
    fixed = YO10.replace("shallow", "3").replace("\tb_arg: bogus(m) 1\n", "")
    ma_uri = open_document(vscode, tmp_path / "mafiles" / "yo10.ma", "slocum_ma", fixed)
    vscode.text_document_did_save(types.DidSaveTextDocumentParams(text_document=types.TextDocumentIdentifier(uri=ma_uri)))
    for _ in range(200):
        if not any(d.message.startswith("yo10.ma:") for d in vscode.diagnostics[uri]):
            break
        await asyncio.sleep(0.05)
    # Only the mission's own problem (`deep`) is left.
    assert [d.code for d in vscode.diagnostics[uri]] == ["S0015"]
    assert not vscode.diagnostics[uri][0].message.startswith("yo10.ma:")
