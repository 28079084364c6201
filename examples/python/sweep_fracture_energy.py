"""Crack speed against fracture energy for the glass plate (examples/glass_branching.yaml)
at reduced size: four runs from Python, one figure.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sweep_fracture_energy.py [--coarsen 2]

Writes out/python_sweep/crack_speed.png and prints one line per run. Each run is the
deck with materials.glass.damage.fracture_energy changed; everything else as in the
deck, coarsened (spacing and horizon times --coarsen) to keep the sweep short.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import horizon  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--coarsen", type=float, default=2.0)
    p.add_argument("--energies", type=float, nargs="+", default=[2.0, 3.8, 6.0, 9.0])
    p.add_argument("--out", default="out/python_sweep")
    a = p.parse_args()
    deck_path = os.path.join(ROOT, "examples", "glass_branching.yaml")
    speeds, tips = [], []
    for g in a.energies:
        deck = horizon.load(deck_path)
        deck.set("materials.glass.damage.fracture_energy", g)
        sim = horizon.Simulation(deck, coarsen=a.coarsen, output_dir=os.path.join(a.out, "G_%g" % g))
        crack = sim.run()["crack"]
        speeds.append(crack["speed_before_branching"])
        tips.append(crack["length"])
        print("G_c = %5.2f J/m^2: crack speed %7.1f m/s, crack length %.4f m, branch at %s" % (
            g, speeds[-1], tips[-1], crack["branch_distance"]))
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(a.energies, speeds, "o-")
    ax.set_xlabel("fracture energy G_c [J/m²]")
    ax.set_ylabel("crack speed before branching [m/s]")
    ax.set_title("glass plate, spacing x %g" % a.coarsen)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    png = os.path.join(a.out, "crack_speed.png")
    fig.savefig(png, dpi=120)
    print("wrote", png)


if __name__ == "__main__":
    main()
