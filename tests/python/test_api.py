# The Python module's calls: decks from files, text and dicts; editing; stepping with a
# callback; NumPy views; history and summary; errors with line:column; the GIL.
import gc
import os
import subprocess
import threading

import numpy as np
import pytest

import horizon
from conftest import ROOT


def test_load_from_string_dict_and_file(plate_text, tmp_path):
    d = horizon.loads(plate_text, name="plate.yaml")
    assert d.name == "plate.yaml" and not d.is_peridigm
    assert d.get("materials.glass.density") == 2440
    assert d.get("loads[0].velocity") == [0, 5.0]
    as_dict = d.to_dict()
    assert as_dict["bodies"][0]["name"] == "plate"
    d2 = horizon.from_dict(as_dict)
    assert d2.to_dict() == as_dict
    p = tmp_path / "plate.yaml"
    p.write_text(d.to_yaml())
    d3 = horizon.load(p)
    assert d3.to_dict() == as_dict
    report = d3.check()
    assert report["particles"] == 800 and report["bonds"] > 0 and report["steps"] > 0
    assert "particles       800" in report["report"]


def test_set_changes_the_run(plate_text, tmp_path):
    d = horizon.loads(plate_text)
    d.set("materials.glass.density", 4880.0)        # twice the density: the stable step grows by sqrt(2)
    d.set(["solver", "end_time"], 1.0e-5)
    d.set("output.history_every", 5)
    base = horizon.loads(plate_text).check()["stable_dt"]
    assert d.check()["stable_dt"] == pytest.approx(base * np.sqrt(2), rel=1e-12)
    sim = horizon.Simulation(d, output_dir=tmp_path / "o")
    assert sim.total_steps == int(np.ceil(1.0e-5 / sim.dt - 1e-9))
    with pytest.raises(KeyError):
        d.get("materials.steel")


def test_deck_error_carries_line_and_column(plate_text):
    text = plate_text.replace("spacing: 1.0e-3", "spacing: -1.0")
    with pytest.raises(horizon.DeckError) as e:
        horizon.Simulation(horizon.loads(text, name="bad.yaml"))
    assert (e.value.file, e.value.line, e.value.column) == ("bad.yaml", 4, 10)
    assert str(e.value).startswith("bad.yaml:4:10: error: spacing")
    assert isinstance(e.value, horizon.Error) and isinstance(e.value, RuntimeError)


def test_unknown_key_suggests(plate_text):
    with pytest.raises(horizon.DeckError) as e:
        horizon.Simulation(horizon.loads(plate_text.replace("density:", "densty:"), name="p.yaml"))
    assert e.value.line == 9 and "densty" in str(e.value) and "density" in str(e.value)


def test_yaml_syntax_error_has_position():
    with pytest.raises(horizon.DeckError) as e:
        horizon.loads("a: [1, 2\nb: 3\n", name="s.yaml")
    assert e.value.line >= 1 and "YAML syntax error" in str(e.value)


def test_step_and_views_without_copy(plate_text, tmp_path):
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "o")
    u = sim.displacement
    assert u.shape == (sim.particles, 3) and u.dtype == np.float64
    assert np.shares_memory(u, sim.displacement)          # a view of the run's array, not a copy
    assert not sim.positions.flags.writeable and u.flags.writeable
    assert sim.step(10) == 10 and sim.steps == 10
    assert sim.time == pytest.approx(10 * sim.dt, rel=1e-12)
    assert np.abs(u).max() > 0                            # the old view sees the new state
    frame = sim.frame()
    assert set(["displacement", "velocity", "damage", "volume"]) <= set(frame["fields"])
    np.testing.assert_array_equal(frame["fields"]["displacement"], u)
    assert sim.volume.sum() == pytest.approx(0.04 * 0.02 * 1e-3, rel=1e-9)
    assert set(sim.energy()) >= {"kinetic", "strain", "external_work"}
    assert len(sim.reactions()) == 2


def test_views_outlive_the_simulation(plate_text, tmp_path):
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "o")
    sim.run()
    u, dmg = sim.displacement, sim.damage
    expected_u, expected_d = u.copy(), dmg.copy()
    del sim
    gc.collect()
    np.testing.assert_array_equal(u, expected_u)          # the view keeps the run alive
    np.testing.assert_array_equal(dmg, expected_d)
    assert dmg.max() > 0


def test_run_with_callback_history_and_summary(plate_text, tmp_path):
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "o")
    seen = []
    summary = sim.run(callback=lambda s: seen.append((s.steps, float(s.damage.max()))), every=25)
    total = sim.total_steps
    assert [k for k, _ in seen] == list(range(25, total, 25)) + [total]
    assert summary["status"] == "completed" and summary["steps"] == total
    assert summary["damage"]["max"] == pytest.approx(seen[-1][1], abs=1e-12)
    h = sim.history
    assert h["step"][0] == 0 and h["step"][-1] == total
    assert h["damage_max"][-1] == pytest.approx(summary["damage"]["max"], abs=1e-6)
    assert horizon.read_summary(tmp_path / "o") == summary
    np.testing.assert_array_equal(horizon.read_history(tmp_path / "o")["time"], h["time"])


def test_callback_returning_false_stops_cleanly(plate_text, tmp_path):
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "o")
    summary = sim.run(callback=lambda s: s.steps < 40, every=20)
    assert sim.steps == 40 and summary["status"] == "stopped" and summary["steps"] == 40
    assert "stopped by the callback" in summary["message"]
    h = horizon.read_history(tmp_path / "o")
    assert h["step"][-1] == 40                             # the final row is the stop
    last = horizon.read_frame(tmp_path / "o")
    assert last["step"] == 40
    np.testing.assert_array_equal(last["fields"]["displacement"], sim.displacement)
    with pytest.raises(horizon.Error):
        sim.step(1)


def test_callback_numpy_false_stops_and_none_goes_on(plate_text, tmp_path):
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "a")
    sim.run(callback=lambda s: np.float64(s.steps) < 30, every=10)   # numpy.bool_
    assert sim.steps == 30 and sim.status == "stopped"
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "b")
    sim.run(callback=lambda s: None, every=10)
    assert sim.status == "completed" and sim.steps == sim.total_steps


def test_exception_in_callback_ends_run_and_propagates(plate_text, tmp_path):
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "o")

    def boom(s):
        raise ValueError("from the callback")

    with pytest.raises(ValueError, match="from the callback"):
        sim.run(callback=boom, every=10)
    assert sim.finished and sim.summary["status"] == "stopped" and sim.summary["steps"] == 10


def test_gil_is_released_during_steps(plate_text, tmp_path):
    d = horizon.loads(plate_text)
    d.set("solver.end_time", 3.0e-4)                       # about 1,500 steps
    sim = horizon.Simulation(d, output_dir=tmp_path / "o", threads=1)
    worker = threading.Thread(target=lambda: sim.step(10**9))
    ticks = 0
    worker.start()
    while worker.is_alive():
        ticks += 1
    worker.join()
    assert sim.done
    # With the GIL held for the whole call the loop could run only between the
    # interpreter's switch interval checks before the call started.
    assert ticks > 1000


def test_static_deck_runs_to_the_end(tmp_path):
    sim = horizon.Simulation(os.path.join(ROOT, "tests", "peridigm", "compression_implicit_2x1x1.yaml"),
                             output_dir=tmp_path / "o")
    assert not sim.is_explicit
    with pytest.raises(horizon.Error):
        sim.step(1)
    summary = sim.run()
    assert summary["status"] == "completed"
    assert horizon.read_frame(tmp_path / "o")["step"] == 5


def test_render_and_models(plate_text, tmp_path):
    sim = horizon.Simulation(horizon.loads(plate_text), output_dir=tmp_path / "o")
    sim.run()
    png = horizon.render(str(tmp_path / "o"), field="damage", width=200)
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    out = horizon.render(str(tmp_path / "o"), field="displacement_y", output=str(tmp_path / "u.png"), width=200)
    assert out == str(tmp_path / "u.png") and os.path.getsize(out) > 0
    assert "lps" in horizon.models() and "pmb" in horizon.models()
    with pytest.raises(horizon.Error):
        horizon.render(str(tmp_path / "missing"))


def test_sweep_matches_the_command_line(plate_text, tmp_path, horizon_binary):
    # A two-point sweep over the pull velocity: each Python run writes the same
    # history.csv, byte for byte, as `horizon run` of the same deck.
    for v in (3.0, 6.0):
        d = horizon.loads(plate_text)
        d.set("loads[0].velocity", [0, v])
        d.set("loads[1].velocity", [0, -v])
        d.set("solver.end_time", 1.5e-5)
        deck = tmp_path / ("plate_%g.yaml" % v)
        deck.write_text(d.to_yaml())
        py_dir, cli_dir = tmp_path / ("py_%g" % v), tmp_path / ("cli_%g" % v)
        sim = horizon.run(horizon.load(deck), output_dir=py_dir, callback=lambda s: None, every=7)
        subprocess.run([horizon_binary, "run", str(deck), "-q", "-o", str(cli_dir)], check=True)
        assert (py_dir / "history.csv").read_bytes() == (cli_dir / "history.csv").read_bytes()
        for name in os.listdir(cli_dir / "frames"):
            assert (py_dir / "frames" / name).read_bytes() == (cli_dir / "frames" / name).read_bytes()
        cli = horizon.read_summary(cli_dir)
        assert sim.summary["damage"] == cli["damage"] and sim.summary["energy"] == cli["energy"]
