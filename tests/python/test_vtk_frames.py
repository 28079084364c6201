# Output faults read back with VTK's own XML reader (vtkXMLUnstructuredGridReader, the
# reader ParaView uses for .vtu), not only with Horizon's: after a clean run, a run
# stopped by a file-size limit (exit 5), a SIGKILL in the middle of writing and a
# SIGTERM (exit 143), every frame that frames.pvd lists opens without a reader error and
# holds every particle with its fields (docs/reliability.md, "Output faults").
import os
import resource
import signal
import subprocess
import time
import xml.etree.ElementTree as ET

import pytest

vtk = pytest.importorskip("vtk")

BINARY = os.environ.get("HORIZON_BINARY", "horizon")

# A 1-D bar of 20 particles with a frame every step or two (as in
# tests/regression/test_output_faults.cpp): many small frames, so that faults land
# while frames are being written.
BAR = """\
dimension: 1
area: 1.0e-6
spacing: 1.0e-3
horizon_factor: 3
materials:
  steel: {model: pmb, density: 7800, youngs_modulus: 200.0e9}
bodies:
  - {name: bar, material: steel, shape: {box: {min: [0], max: [0.02]}}}
initial_conditions:
  - {velocity: ["x/0.02"]}
solver: {type: explicit, end_time: END}
output: {frames: FRAMES, history_every: 10}
"""


def deck(tmp_path, end=1.0e-4, frames=400):
    p = tmp_path / "bar.yaml"
    p.write_text(BAR.replace("END", repr(end)).replace("FRAMES", str(frames)))
    return p


def listed_frames(out):
    root = ET.parse(out / "frames.pvd").getroot()
    return [(float(d.get("timestep")), out / d.get("file")) for d in root.iter("DataSet")]


def open_with_vtk(path):
    """Reads one .vtu with VTK; returns (points, array names). Fails on any reader error."""
    errors = vtk.vtkStringOutputWindow()
    vtk.vtkOutputWindow.SetInstance(errors)
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    assert reader.GetErrorCode() == 0, f"{path}: VTK error code {reader.GetErrorCode()}"
    text = errors.GetOutput()
    assert "ERROR" not in text, f"{path}: {text}"
    grid = reader.GetOutput()
    data = grid.GetPointData()
    names = [data.GetArrayName(k) for k in range(data.GetNumberOfArrays())]
    for k in range(data.GetNumberOfArrays()):
        assert data.GetArray(k).GetNumberOfTuples() == grid.GetNumberOfPoints(), (path, names[k])
    return grid.GetNumberOfPoints(), names


def expect_frames_open(out, minimum):
    frames = listed_frames(out)
    assert len(frames) >= minimum
    for _, path in frames:
        points, names = open_with_vtk(path)
        assert points == 20, path
        assert "displacement" in names and "damage" in names, (path, names)
    return len(frames)


def run(deck_path, out, limit=None):
    def child():
        if limit:
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.run([BINARY, "run", str(deck_path), "-o", str(out), "-q", "--threads", "1"],
                          preexec_fn=child, capture_output=True, text=True, timeout=300)


def test_clean_run_frames_open_in_vtk(tmp_path):
    r = run(deck(tmp_path, frames=20), tmp_path / "out")
    assert r.returncode == 0, r.stderr
    assert expect_frames_open(tmp_path / "out", 21) == 21


def test_file_size_limit_leaves_frames_vtk_opens(tmp_path):
    r = run(deck(tmp_path), tmp_path / "out", limit=16 << 10)
    assert r.returncode == 5, r.stderr
    assert "File too large" in r.stderr
    n = expect_frames_open(tmp_path / "out", 100)
    assert f"frames.pvd lists the {n} complete frames" in r.stderr


@pytest.mark.parametrize("delay", [0.15, 0.3, 0.6])
def test_sigkill_while_writing_leaves_frames_vtk_opens(tmp_path, delay):
    out = tmp_path / "out"
    p = subprocess.Popen([BINARY, "run", str(deck(tmp_path, end=0.5, frames=20000)), "-o", str(out), "-q",
                          "--threads", "1"], stderr=subprocess.DEVNULL)
    for _ in range(400):  # wait for the first index
        if (out / "frames.pvd").exists():
            break
        time.sleep(0.025)
    time.sleep(delay)
    p.send_signal(signal.SIGKILL)
    assert p.wait(timeout=60) == -signal.SIGKILL
    expect_frames_open(out, 1)


def test_sigterm_final_frame_opens_in_vtk(tmp_path):
    out = tmp_path / "out"
    p = subprocess.Popen([BINARY, "run", str(deck(tmp_path, end=0.5, frames=200)), "-o", str(out), "-q",
                          "--threads", "1"], stderr=subprocess.PIPE, text=True)
    for _ in range(400):
        if (out / "frames.pvd").exists():
            break
        time.sleep(0.025)
    time.sleep(0.2)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 143, err
    assert "SIGTERM" in err
    expect_frames_open(out, 2)
