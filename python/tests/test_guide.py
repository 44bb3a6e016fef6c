"""Every Python code block of docs/guide/python.md, README.md and
python/README.md runs and its asserts hold: the examples are tests (each
in a fresh temporary folder, with the L-system file the guide opens)."""

import os
import pathlib
import re
import shutil

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide" / "python.md"
PAGES = [GUIDE, ROOT / "README.md", ROOT / "python" / "README.md"]
BLOCKS = [
    (page, code)
    for page in PAGES
    for code in re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)
]


def test_the_pages_have_their_python_blocks():
    # the guide: noise, terrain, L-systems, ecosystems, ocean, volumes,
    # smoke, textures and sky, the GIT texture and filter, render; one in
    # each README
    assert [p.name for p, _ in BLOCKS].count("python.md") == 11
    assert len(BLOCKS) == 13


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_block_runs(index, tmp_path, monkeypatch):
    lsystems = tmp_path / "examples" / "lsystems"
    lsystems.mkdir(parents=True)
    shutil.copy(ROOT / "examples" / "lsystems" / "fig1_25.l", lsystems)
    monkeypatch.chdir(tmp_path)
    page, text = BLOCKS[index]
    code = compile(text, f"{page.relative_to(ROOT)} block {index + 1}", "exec")
    exec(code, {"__name__": "guide"})
    assert os.getcwd() == str(tmp_path)
