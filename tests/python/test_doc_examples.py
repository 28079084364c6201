# The first example of the docs runs as written (doctest-style): the Python module's
# docstring, docs/python.md's first run, docs/input.md's complete deck and the first deck
# fragment of each model page. Each runs in a scratch folder that sees the checkout's
# examples/ (the examples name decks by relative path and write under out/), and the runs
# are the docs' own: coarsened (--coarsen 4, a few hundred steps), so seconds each.
# Pages whose first example is not a Horizon run are listed in NOT_RUN with the reason.
import os
import re

import pytest

import horizon
from conftest import ROOT

# The first examples this test does not run, and why.
NOT_RUN = {
    "README.md": "`make demo` and `make test` (the lead measures both on a clean clone)",
    "docs/benchmarks.md": "bench/ scripts: timing runs of minutes, not tests",
    "docs/design.md": "a drawing of the data flow, not code",
    "docs/peridigm.md": "error messages quoted from decks the Peridigm tests check (tests/python/test_peridigm.py)",
    "docs/reliability.md": "the fuzzer (clang and libFuzzer, an hour)",
    "docs/verification.md": "the whole verification suite (ctest -L verification runs it)",
}


def code_blocks(path, language):
    """The fenced code blocks of a Markdown file in `language`, in order."""
    with open(os.path.join(ROOT, path), encoding="utf-8") as f:
        text = f.read()
    return re.findall(r"^```" + language + r"\n(.*?)^```", text, flags=re.S | re.M)


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    os.symlink(os.path.join(ROOT, "examples"), tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_module_docstring_example_runs(scratch, capsys):
    lines = [l[4:] for l in horizon.__doc__.splitlines() if l.startswith("    ")]
    assert lines and "horizon.Simulation" in lines[1], horizon.__doc__
    exec("\n".join(lines), {})
    printed = capsys.readouterr().out.split()
    mean = float(printed[-1])  # sim.summary["damage"]["mean"]
    assert 0 < mean < 1


def test_python_md_first_run(scratch, capsys):
    code = code_blocks("docs/python.md", "python")[0]
    assert "horizon.Simulation" in code
    exec(code, {})
    speed = float(capsys.readouterr().out.split()[-1])  # the crack's speed before branching
    assert 0 < speed < 3058  # below the Rayleigh speed of glass
    assert (scratch / "out" / "py" / "damage.png").stat().st_size > 0


def test_input_md_complete_example_checks(scratch):
    deck = horizon.loads(code_blocks("docs/input.md", "yaml")[0], name="input.md")
    report = deck.check(coarsen=4)
    assert report["particles"] == 4000 and report["bonds"] > 0 and report["steps"] > 0


# A block of the model's material, for the pages whose first example is a materials map.
BLOCK = """dimension: 3
spacing: 1.0e-3
horizon: 3.0e-3
{materials}bodies:
  - {{name: block, material: {name}, shape: {{box: {{min: [0, 0, 0], max: [0.006, 0.006, 0.006]}}}}}}
solver: {{end_time: 1.0e-7}}
"""


@pytest.mark.parametrize("page", sorted(f for f in os.listdir(os.path.join(ROOT, "docs", "models"))
                                        if f.endswith(".md")))
def test_model_page_first_deck_fragment_checks(page):
    blocks = code_blocks(os.path.join("docs", "models", page), "yaml")
    if not blocks or not blocks[0].startswith("materials:"):
        pytest.skip(page + ": its first example is not a materials map")
    name = re.search(r"^  (\w+):", blocks[0], flags=re.M).group(1)
    deck = horizon.loads(BLOCK.format(materials=blocks[0], name=name), name=page)
    assert deck.check()["bonds"] > 0
