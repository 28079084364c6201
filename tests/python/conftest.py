# pytest set-up for the Python module's tests (run by ctest: tests/CMakeLists.txt).
import os
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# A small 2-D plate with a precrack, pulled apart at its top and bottom edges: 800
# particles, 150 steps; it breaks bonds, so damage and history both move.
PLATE = """\
dimension: 2
plane: stress
thickness: 1.0e-3
spacing: 1.0e-3
horizon: 3.0e-3
materials:
  glass:
    model: pmb
    density: 2440
    youngs_modulus: 72.0e9
    damage: {critical_stretch: 2.0e-3}
bodies:
  - {name: plate, material: glass, shape: {box: {min: [0, 0], max: [0.04, 0.02]}}}
precracks:
  - {from: [0, 0.01], to: [0.015, 0.01]}
regions:
  top: {box: {min: [0, 0.0185], max: [0.04, 0.02]}}
  bottom: {box: {min: [0, 0], max: [0.04, 0.0015]}}
loads:
  - {region: top, velocity: [0, 5.0]}
  - {region: bottom, velocity: [0, -5.0]}
solver: {type: explicit, end_time: 3.0e-5, safety_factor: 0.8}
output: {directory: out/plate, frames: 3, history_every: 10}
"""


@pytest.fixture
def plate_text():
    return PLATE


@pytest.fixture
def horizon_binary():
    path = os.environ.get("HORIZON_BINARY", os.path.join(ROOT, "build", "horizon"))
    if not os.path.exists(path):
        pytest.skip("the horizon binary is not built")
    return path


@pytest.fixture
def peridigm_dir():
    return os.path.join(ROOT, "tests", "peridigm")
