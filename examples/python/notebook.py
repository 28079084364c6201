# %% [markdown]
# # A Horizon run from Python, cell by cell
# Run it as a script (`PYTHONPATH=build/python /usr/bin/python3 examples/python/notebook.py`)
# or open it in an editor that runs `# %%` cells. It pulls a small cracked plate apart,
# watches the crack from a callback, stops the run once the plate is split, and
# post-processes the fields with NumPy and Matplotlib.

# %%
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import horizon

deck = horizon.from_dict({
    "dimension": 2, "plane": "stress", "thickness": 1e-3,
    "spacing": 5e-4, "horizon": 1.5e-3,
    "materials": {"glass": {"model": "pmb", "density": 2440, "youngs_modulus": 72e9,
                            "damage": {"fracture_energy": 3.8}}},
    "bodies": [{"name": "plate", "material": "glass",
                "shape": {"box": {"min": [0, 0], "max": [0.04, 0.02]}}}],
    "precracks": [{"from": [0, 0.01], "to": [0.01, 0.01]}],
    "regions": {"top": {"box": {"min": [0, 0.0195], "max": [0.04, 0.02]}},
                "bottom": {"box": {"min": [0, 0], "max": [0.04, 0.0005]}}},
    "loads": [{"region": "top", "velocity": [0, 2.0]}, {"region": "bottom", "velocity": [0, -2.0]}],
    "solver": {"type": "explicit", "end_time": 1e-4},
    "output": {"directory": "out/notebook", "frames": 5},
}, name="notebook plate")
print(deck.check()["report"])

# %% Run, watching the crack; stop once it has crossed 90 % of the plate.
sim = horizon.Simulation(deck)
x = sim.positions[:, 0]          # a view: no copy
damage = sim.damage              # a view that follows the run


def watch(s):
    cracked = x[damage > 0.35]
    front = cracked.max() if cracked.size else 0.0
    print("step %5d  t = %.3e s  crack front x = %.4f m" % (s.steps, s.time, front))
    return front < 0.9 * 0.04    # False stops the run


summary = sim.run(callback=watch, every=200)
print(summary["status"], summary["steps"], "steps; mean damage", summary["damage"]["mean"])

# %% History as NumPy arrays.
h = sim.history
plt.figure(figsize=(5, 3))
plt.plot(h["time"] * 1e6, h["kinetic_energy"], label="kinetic")
plt.plot(h["time"] * 1e6, h["strain_energy"], label="strain")
plt.plot(h["time"] * 1e6, h["dissipated_energy"], label="dissipated")
plt.xlabel("t [µs]"); plt.ylabel("energy [J]"); plt.legend(); plt.tight_layout()
plt.savefig("out/notebook/energy.png", dpi=120)

# %% Damage field from the views, and Horizon's own picture.
plt.figure(figsize=(5, 2.7))
plt.scatter(sim.positions[:, 0], sim.positions[:, 1], c=sim.damage, s=2, cmap="inferno")
plt.gca().set_aspect("equal"); plt.colorbar(label="damage"); plt.tight_layout()
plt.savefig("out/notebook/damage_scatter.png", dpi=120)
print("wrote", horizon.render("out/notebook", field="damage", width=600))
