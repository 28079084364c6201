# Peridigm decks through the importer: Peridigm's verification problems written from
# the survey (../shared/reference/notes/peridigm.md, sec. 3.4), each checked against
# its closed form to round-off and against Peridigm's gold values within the
# tolerances of Peridigm's own comparison files (displacement, velocity and force
# 1e-9 absolute; damage 1e-3).
import math
import os
import subprocess

import numpy as np
import pytest

import horizon

K, MU, RHO = 130.0e9, 78.0e9, 7800.0


def sim(peridigm_dir, name, tmp_path, **kw):
    return horizon.Simulation(os.path.join(peridigm_dir, name + ".yaml"), output_dir=tmp_path / name, **kw)


def verlet_two_points(u0, v0, dt, steps, stiffness):
    """Velocity Verlet for u'' = -stiffness u (survey P1's recurrence)."""
    u, v, a, out = u0, v0, -stiffness * u0, []
    for _ in range(steps):
        v_half = v + 0.5 * dt * a
        u = u + dt * v_half
        a = -stiffness * u
        v = v_half + 0.5 * dt * a
        out.append((u, v, a))
    return out


def test_compression_2x1x1_closed_form(peridigm_dir, tmp_path):
    # P1: m = 8, alpha = 15 mu/m; node 1 feels 2 alpha e V = -1.17e12 u, a = -1.5e8 u.
    s = sim(peridigm_dir, "compression_2x1x1", tmp_path)
    m = 2.0 ** 2 * 2.0                          # omega |xi|^2 V
    alpha = 15 * MU / m
    stiffness = 2 * alpha * 2 * 2.0 / RHO       # force density 2 alpha e V with e = -2u, V = 2
    assert stiffness == pytest.approx(1.5e8, rel=1e-15)
    expected = verlet_two_points(0.0, 1.0, 1e-5, 5, stiffness)
    left = int(np.argmin(s.positions[:, 0]))
    for u, v, a in expected:
        s.step(1)
        assert s.displacement[left, 0] == pytest.approx(u, rel=1e-12)
        assert s.velocity[left, 0] == pytest.approx(v, rel=1e-12)
        assert s.force_density[left, 0] / RHO == pytest.approx(a, rel=1e-9)
    # Peridigm's gold: force at step 5 = -1.10089934e8 N, u1 = 4.70469805e-5.
    assert s.force_density[left, 0] * s.volume[left] == pytest.approx(-1.10089934e8, abs=1.0)
    assert s.displacement[left, 0] == pytest.approx(4.70469805e-5, abs=1e-13)
    s.finish()


def test_compression_init_disp_2x1x1_closed_form(peridigm_dir, tmp_path):
    s = sim(peridigm_dir, "compression_init_disp_2x1x1", tmp_path)
    left = int(np.argmin(s.positions[:, 0]))
    assert s.displacement[left, 0] == 1e-5
    for u, v, _ in verlet_two_points(1e-5, 0.0, 1e-5, 5, 1.5e8):
        s.step(1)
        assert s.displacement[left, 0] == pytest.approx(u, rel=1e-12)
        assert s.velocity[left, 0] == pytest.approx(v, rel=1e-11, abs=1e-17)
    s.finish()


def test_compression_implicit_2x1x1_gold(peridigm_dir, tmp_path):
    # P1b: Newmark beta = 1/4: u1 = 1e-5/(1 + w^2 dt^2/4); gold u(5) = 4.68820316e-5, v(5) = 0.8187254.
    s = sim(peridigm_dir, "compression_implicit_2x1x1", tmp_path)
    s.run()
    frames = sorted(os.listdir(tmp_path / "compression_implicit_2x1x1" / "frames"))
    first = horizon.read_frame(tmp_path / "compression_implicit_2x1x1" / "frames" / frames[1])
    last = horizon.read_frame(tmp_path / "compression_implicit_2x1x1")
    left = int(np.argmin(last["points"][:, 0]))
    # The average-acceleration recurrence for u'' = -k u, solved exactly.
    k, dt, u, v, a = 1.5e8, 1e-5, 0.0, 1.0, 0.0
    for _ in range(5):
        u_new = (u + dt * v + dt * dt / 4 * a) / (1 + k * dt * dt / 4)
        a_new = -k * u_new
        v = v + dt / 2 * (a + a_new)
        u, a = u_new, a_new
        if _ == 0:
            assert first["fields"]["displacement"][left, 0] == pytest.approx(u, rel=1e-9)
    assert last["fields"]["displacement"][left, 0] == pytest.approx(u, rel=1e-9)
    assert last["fields"]["velocity"][left, 0] == pytest.approx(v, rel=1e-9)
    # Peridigm's gold (its .comp tolerance: 1e-9 absolute).
    assert first["fields"]["displacement"][left, 0] == pytest.approx(9.9626401e-6, abs=1e-9)
    assert last["fields"]["displacement"][left, 0] == pytest.approx(4.68820316e-5, abs=1e-9)
    assert last["fields"]["velocity"][left, 0] == pytest.approx(0.8187254, abs=1e-7)


def test_compression_3x1x1_gold(peridigm_dir, tmp_path):
    # P2: m = (1, 2, 1); a1 = -2250 at step 1 (v1 = 0.98875); gold at step 5.
    s = sim(peridigm_dir, "compression_3x1x1", tmp_path)
    left = int(np.argmin(s.positions[:, 0]))
    s.step(1)
    assert s.velocity[left, 0] == pytest.approx(0.98875, rel=1e-12)
    s.step(4)
    assert s.displacement[left, 0] == pytest.approx(4.56054038e-5, abs=1e-13)
    assert s.velocity[left, 0] == pytest.approx(0.731208193, abs=1e-9)
    s.finish()


def test_compression_3x1x1_influence_function_gold(peridigm_dir, tmp_path):
    # P2 with omega = 1/|xi|, horizon 2.1: force at step 1 = -1.755e6 N; gold at step 5.
    s = sim(peridigm_dir, "compression_3x1x1_influence", tmp_path)
    left = int(np.argmin(s.positions[:, 0]))
    s.step(1)
    assert s.force_density[left, 0] * s.volume[left] == pytest.approx(-1.755e6, rel=1e-9)
    s.step(4)
    assert s.displacement[left, 0] == pytest.approx(4.99550106e-6, abs=1e-14)
    assert s.velocity[left, 0] == pytest.approx(0.997188765, abs=1e-9)
    s.finish()


def critical_velocity(k, mu, rho, volume, length, s_c):
    # Survey P4 (Peridigm's CriticalInitialVelocityForBondBreaking.py, re-derived): one
    # bond, omega = 1, m = |xi|^2 V; the bond's energy at stretch s_c against the kinetic
    # energy of the pair.
    m = length ** 2 * volume
    c = (9 * k - 15 * mu) * length ** 2 * volume / m ** 2 + 15 * mu / m
    work = 2 * volume ** 2 * c * (s_c * length) ** 2 / 2
    return math.sqrt(work / (rho * volume))


@pytest.mark.parametrize("name", ["bond_breaking_initial_velocity", "bond_breaking_initial_velocity_ep",
                                  "bond_breaking_interface_aware", "bond_breaking_box_neighbourhood"])
def test_bond_breaking_initial_velocity(peridigm_dir, tmp_path, name):
    v_c = critical_velocity(130.0e9, 60.0e9, 7800.0, 1.05, 1.0, 0.02)
    assert v_c == pytest.approx(244.949, abs=5e-4)
    assert 244.939 < v_c < 244.959
    # interface_aware: blocks of critical stretch 0.02 and 0.05 meet in every bond; the
    # smaller one rules (with 0.05 neither pair would break).
    assert critical_velocity(130.0e9, 60.0e9, 7800.0, 1.05, 1.0, 0.05) > 600
    s = sim(peridigm_dir, name, tmp_path)
    if name.endswith("interface_aware"):
        assert s.block_names == ["block_1", "block_2"]
    order = np.lexsort((s.positions[:, 0], s.positions[:, 1]))   # Peridigm's ids 1..4
    s.step(6000)                                                 # t = 6e-5
    uy = s.displacement[order, 1]
    assert uy[0] == pytest.approx(-0.00994852992, abs=1e-9)
    assert uy[1] == pytest.approx(-0.00994934225, abs=1e-9)
    s.step(1000)                                                 # t = 7e-5
    np.testing.assert_allclose(s.damage[order], [0, 1, 0, 1], atol=1e-3)
    s.step(1000)                                                 # t = 8e-5
    vy = s.velocity[order, 1]
    assert vy[0] == pytest.approx(92.8500214, abs=1e-6)          # below critical: rebounds
    assert vy[1] == pytest.approx(-2.23500857, abs=1e-8)         # above: separates
    assert vy[2] == pytest.approx(-vy[0], rel=1e-12) and vy[3] == pytest.approx(-vy[1], rel=1e-12)
    s.finish()


def test_box_neighbourhood_is_converted(peridigm_dir):
    # PdQuickGrid's default box (round(0.51/1.05) = 0 and round(0.51/1.0) = 1 cells) bonds
    # the vertical pairs, which a sphere of 0.51 would not: the native deck carries the box.
    text = horizon.convert_peridigm(os.path.join(peridigm_dir, "bond_breaking_box_neighbourhood.yaml"))
    assert "family_box: [0, 1, 1]" in text


def top_grip_reaction(s):
    top = s.positions[:, 1] > 4.5
    return float((s.force_density[top, 1] * s.volume[top]).sum())


def test_tension_bar_bond_based_gold(peridigm_dir, tmp_path):
    # P7, Elastic Bond Based: gold top reaction 2.51257e8 N (printed to 6 digits).
    s = sim(peridigm_dir, "tension_bar_bond_based", tmp_path)
    s.run()
    assert s.particles == 384
    assert -top_grip_reaction(s) == pytest.approx(2.51257e8, abs=0.5e3)


def test_tension_bar_correspondence(peridigm_dir, tmp_path):
    # P7, Elastic Correspondence without hourglass control: Peridigm's rate form (stress_law
    # hypoelastic) gives sigma_yy = E sum dt D = 199880087.93 Pa over the five steps, and P_yy
    # = J sigma_yy / F_yy = sigma_yy on the 1 m^2 section: Peridigm's gold 1.99880e8 N, 0.06 %
    # below the small-strain E eps A = 2.0e8 N (docs/models/correspondence.md).
    s = sim(peridigm_dir, "tension_bar_correspondence", tmp_path)
    s.run()
    assert -top_grip_reaction(s) == pytest.approx(1.9988008793e8, rel=1e-6)


def test_cli_runs_and_converts(peridigm_dir, tmp_path, horizon_binary):
    deck = os.path.join(peridigm_dir, "compression_3x1x1.yaml")
    r = subprocess.run([horizon_binary, "run", deck, "-q", "-o", str(tmp_path / "run")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    native = tmp_path / "native.yaml"
    subprocess.run([horizon_binary, "convert", deck, "-o", str(native)], check=True, capture_output=True)
    text = native.read_text()
    assert "model: lps" in text and "points:" in text and "Peridigm" not in text.split("\n", 1)[1]
    r2 = subprocess.run([horizon_binary, "run", str(native), "-q", "-o", str(tmp_path / "native_run")],
                        capture_output=True, text=True)
    assert r2.returncode == 0, r2.stderr
    # The converted deck runs to the same numbers as the Peridigm deck.
    a = horizon.read_frame(tmp_path / "run")["fields"]["displacement"]
    b = horizon.read_frame(tmp_path / "native_run")["fields"]["displacement"]
    np.testing.assert_array_equal(a, b)
    assert horizon.convert_peridigm(deck) == subprocess.run(
        [horizon_binary, "convert", deck], check=True, capture_output=True, text=True).stdout


@pytest.mark.parametrize("edit, line, column, words", [
    # A misspelled material key (Peridigm ignores it; Horizon names it).
    (("Bulk Modulus:", "Bulk Modulos:"), 23, 7, ["Bulk Modulos", "did you mean 'Bulk Modulus'"]),
    # A material model Horizon does not map.
    (('Material Model: "Elastic"', 'Material Model: "Pals"'), 21, 23, ["Pals", "Elastic Bond Based"]),
    # A boundary-condition type Horizon does not have (Peridigm's multiphysics pressure).
    (('Type: "Initial Velocity"\n      Node Set: "Left End"', 'Type: "Prescribed Fluid Pressure U"\n      Node Set: "Left End"'),
     34, 13, ["Prescribed Fluid Pressure U"]),
    # A node set that is not defined.
    (('Node Set: "Right End"', 'Node Set: "Right Ends"'), 40, 17, ["Right Ends", "Right End"]),
    # A function string that sets value on one path only: at its place inside the string.
    (('Value: "-1.0"', 'Value: "if(t<1){value=1;}"'), 42, 23, ["set on one branch"]),
    # Unsupported top-level section.
    (("  Solver:", "  Data Loader:\n    Search Radius: 1.0\n  Solver:"), 43, 3, ["Data Loader"]),
    # Multiple solvers.
    (("    Verlet:", "    QuasiStatic:\n      Number of Load Steps: 2\n    Verlet:"), 48, 5, ["QuasiStatic", "Verlet"]),
])
def test_unsupported_keys_are_errors_with_position(peridigm_dir, tmp_path, edit, line, column, words):
    text = open(os.path.join(peridigm_dir, "compression_3x1x1.yaml")).read()
    assert edit[0] in text
    deck = tmp_path / "edited.yaml"
    deck.write_text(text.replace(edit[0], edit[1], 1))
    with pytest.raises(horizon.DeckError) as e:
        horizon.Simulation(str(deck))
    assert (e.value.line, e.value.column) == (line, column), str(e.value)
    for w in words:
        assert w in str(e.value)


def test_xml_deck_runs_like_its_yaml_twin(peridigm_dir, tmp_path, horizon_binary):
    # Peridigm's XML form (Teuchos ParameterLists) of compression_3x1x1: same answers.
    for form in ("yaml", "xml"):
        deck = os.path.join(peridigm_dir, "compression_3x1x1." + form)
        subprocess.run([horizon_binary, "run", deck, "-q", "-o", str(tmp_path / form)], check=True)
    assert (tmp_path / "xml" / "history.csv").read_bytes() == (tmp_path / "yaml" / "history.csv").read_bytes()
    s = horizon.Simulation(os.path.join(peridigm_dir, "compression_3x1x1.xml"), output_dir=tmp_path / "py")
    s.step(5)
    left = int(np.argmin(s.positions[:, 0]))
    assert s.displacement[left, 0] == pytest.approx(4.56054038e-5, abs=1e-13)
    assert "model: lps" in horizon.convert_peridigm(os.path.join(peridigm_dir, "compression_3x1x1.xml"))


@pytest.mark.parametrize("edit, line, column, words", [
    # Messages point at the XML attribute: here the name of the misspelled parameter.
    (('name="Bulk Modulus"', 'name="Bulk Modulos"'), 23, 23, ["Bulk Modulos", "did you mean 'Bulk Modulus'"]),
    # ... and here its value.
    (('value="Elastic"', 'value="Pals"'), 21, 60, ["Pals"]),
    # Malformed XML.
    (('<ParameterList name="Solver">', '<ParameterList name="Solver">\n    <Oops/>'), 51, 5, ["unexpected element <Oops>"]),
])
def test_xml_errors_point_into_the_xml(peridigm_dir, tmp_path, edit, line, column, words):
    text = open(os.path.join(peridigm_dir, "compression_3x1x1.xml")).read()
    assert edit[0] in text
    deck = tmp_path / "edited.xml"
    deck.write_text(text.replace(edit[0], edit[1], 1))
    with pytest.raises(horizon.DeckError) as e:
        horizon.Simulation(str(deck))
    assert (e.value.line, e.value.column) == (line, column), str(e.value)
    for w in words:
        assert w in str(e.value)


def test_body_force_free_fall(peridigm_dir, tmp_path):
    # Body Force through a node-set file on a free cube: u_z = (b/rho) t^2/2 exactly.
    s = sim(peridigm_dir, "body_force_free_cube", tmp_path)
    assert s.particles == 27
    while not s.done:
        s.step(4)
        expected = 0.5 * (100.0 / 1000.0) * s.time ** 2
        np.testing.assert_allclose(s.displacement[:, 2], expected, rtol=1e-12)
        np.testing.assert_allclose(s.displacement[:, :2], 0, atol=1e-14)
    s.finish()
    assert len(os.listdir(tmp_path / "body_force_free_cube" / "frames")) == 1 + 20 // 5


def test_quasi_static_2x1x1_closed_form(peridigm_dir, tmp_path):
    # QuasiStatic -> Horizon's static Newton solve: u = b/(2 alpha V) at each load step.
    s = sim(peridigm_dir, "quasi_static_2x1x1", tmp_path)
    s.run()
    frames = tmp_path / "quasi_static_2x1x1" / "frames"
    names = sorted(n for n in os.listdir(frames) if n.endswith(".vtu"))
    assert len(names) == 3
    alpha = 15 * MU / 8.0
    for name, t in zip(names, (0.0, 0.5, 1.0)):
        f = horizon.read_frame(frames / name)
        right = int(np.argmax(f["points"][:, 0]))
        assert f["time"] == pytest.approx(t)
        assert f["fields"]["displacement"][right, 0] == pytest.approx(5.85e5 * t / (2 * alpha * 2.0), rel=1e-9,
                                                                      abs=1e-20)
        assert np.all(f["fields"]["displacement"][1 - right] == 0)
