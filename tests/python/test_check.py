"""gloc.check and gloc.compile against the command line: the same codes, lines and
columns as `gloc check` prints for every fixture script, and the GLOC `gloc compile`
writes."""

import glob
import os
import re
import subprocess

import pytest

import gloc

from conftest import ROOT

SCRIPTS = sorted(
    glob.glob(os.path.join(ROOT, "tests/fixtures/gloc/*/*.gloc"))
    + glob.glob(os.path.join(ROOT, "tests/fixtures/gbasic/*/*.gbas"))
    + glob.glob(os.path.join(ROOT, "examples/*.gloc"))
    + glob.glob(os.path.join(ROOT, "examples/*.gbas"))
)

# `path:line:col: severity[CODE]: message`, as `gloc check` renders a diagnostic.
RENDERED = re.compile(r"^.*:(\d+):(\d+): (error|warning|info)\[(\w+)\]: ", re.MULTILINE)


def cli_findings(gloc_bin, path):
    result = subprocess.run([gloc_bin, "check", path], capture_output=True, text=True)
    if "note: " in result.stdout:
        return None  # a language hint: the CLI shows only the first few
    return [
        (code, severity, int(line), int(column))
        for line, column, severity, code in RENDERED.findall(result.stdout)
    ]


def test_there_are_fixtures_with_errors_and_without():
    assert len(SCRIPTS) > 20
    assert any("/err/" in path for path in SCRIPTS)


@pytest.mark.parametrize("path", SCRIPTS, ids=lambda path: os.path.relpath(path, ROOT))
def test_check_gives_the_codes_gloc_check_prints(gloc_bin, path):
    expected = cli_findings(gloc_bin, path)
    if expected is None:
        pytest.skip("the CLI shows this script's first findings only (a language note)")
    found = [(d.code, d.severity, d.line, d.column) for d in gloc.check(path)]
    assert found == expected
    if "/err/" in path:
        assert gloc.check(path), "a fixture under err/ has findings"


def test_check_of_text_finds_the_error_on_its_line():
    # tests/fixtures/gloc/err/duplicate_label.gloc as text: the second `label 0` is on
    # line 7, its number at column 7.
    text = "nregs 1\nnblbs 2\nninstr 5\nlabel 0\nyield\njumpi 0\nlabel 0\njumpi 0\n"
    found = gloc.check(text)
    assert [(d.code, d.line, d.column) for d in found] == [("E0103", 7, 7)]
    assert found[0].message == "label 0 is defined twice"
    assert found[0].severity == "error"


def test_compile_writes_what_gloc_compile_writes(gloc_bin, tmp_path):
    source = os.path.join(ROOT, "examples/thermocline.gbas")
    for optimize, flags in ((False, []), (True, ["-O"])):
        out = tmp_path / f"out-{optimize}.gloc"
        subprocess.run([gloc_bin, "compile", source, "-o", str(out), *flags], check=True, capture_output=True)
        assert gloc.compile(source, optimize=optimize) == out.read_text()


def test_compile_of_a_bad_script_raises_with_its_diagnostics():
    with pytest.raises(gloc.CompileError) as caught:
        gloc.compile("x = \n", optimize=False)
    assert caught.value.diagnostics
    assert all(d.line == 1 for d in caught.value.diagnostics if d.severity == "error")


def test_a_mission_is_not_taken_for_a_script():
    with pytest.raises(ValueError, match="gloc check"):
        gloc.check(os.path.join(ROOT, "examples/fig2.mi"))
