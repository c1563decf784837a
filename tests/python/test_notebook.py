"""The example notebook (examples/python/comet.ipynb) runs clean from the fresh venv:
nbclient executes every cell on an ipykernel, matplotlib headless (Agg); a cell that
raises fails the test. Its figures are written as PNG to a temporary folder."""

import os

import pytest

from conftest import ROOT

import nbformat  # pinned: missing is a failure, not a skip
import nbclient

NOTEBOOK = os.path.join(ROOT, "examples", "python", "comet.ipynb")
FIGURES = [
    "comet-logs.png",
    "comet-map.png",
    "comet-simulated-vs-real.png",
    "comet-glide-compared.png",
    "comet-forecast.png",
]


def test_the_comet_notebook_runs_and_draws_its_figures(tmp_path, monkeypatch):
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("GLOC_PLOTS", str(tmp_path))
    monkeypatch.setenv("GLOC_ROOT", ROOT)
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        notebook,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": os.path.dirname(NOTEBOOK)}},
    )
    client.execute()  # raises CellExecutionError, naming the cell, when one fails
    errors = [
        output
        for cell in notebook.cells
        if cell.cell_type == "code"
        for output in cell.get("outputs", [])
        if output.get("output_type") == "error"
    ]
    assert errors == []
    for name in FIGURES:
        path = tmp_path / name
        assert path.is_file(), name
        with open(path, "rb") as handle:
            assert handle.read(8) == b"\x89PNG\r\n\x1a\n", name
        assert path.stat().st_size > 10_000, name
    text = "".join(
        output.get("text", "")
        for cell in notebook.cells
        if cell.cell_type == "code"
        for output in cell.get("outputs", [])
    )
    # The tracker ran in comet's water and the comparison printed the CTD's layer.
    assert "the tracker printed:" in text and "comet's CTD:" in text
