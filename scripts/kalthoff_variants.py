#!/usr/bin/env python3
"""Write a Kalthoff-Winkler deck for one hypothesis of issue 34 (docs/verification.md,
"What differs from the thesis"): Tupek's plate (thesis sec. 6.2.2) with the thesis's
model (nonlinear solid, eq. 6.3-6.10) and one setting changed at a time.

    scripts/kalthoff_variants.py --delta 0.005 --ratio 5 --load projectile:16 > /tmp/kw.yaml
    build/horizon run /tmp/kw.yaml --threads 1 -q -o out/kw

The angle is summary.json fracture.crack_angles_signed_deg (the same ridge fit,
src/horizon/damage/crack_angle.cpp, for every run).
"""
import argparse


def deck(a):
    h = a.delta / a.ratio
    lines = [
        f"# scripts/kalthoff_variants.py {a.argv}",
        "dimension: 2",
        f"plane: {a.plane}",
        "thickness: 0.01",
        f"spacing: {h!r}",
        f"horizon: {a.delta!r}",
        "materials:",
        "  steel:",
        "    model: nonlinear_solid",
        f"    seth_hill_m: {a.m}",
        "    density: 8000",
        "    youngs_modulus: 190.0e9",
        "    poissons_ratio: 0.3",
        f"    damage: {{law: energy, fracture_energy: {a.gc}, broken_bonds: {a.broken},"
        f" failure_length_exponent: {a.p}}}",
    ]
    kind, _, speed = a.load.partition(":")
    speed = float(speed or 16)
    if kind == "projectile":
        lines += [
            "  striker:",
            "    model: nonlinear_solid",
            f"    seth_hill_m: {a.m}",
            "    fracture: false",
            "    density: 8000",
            "    youngs_modulus: 190.0e9",
            "    poissons_ratio: 0.3",
        ]
    lines += [
        "bodies:",
        "  - name: plate",
        "    material: steel",
        "    shape: {box: {min: [0, -0.1], max: [0.1, 0.1]}}" if not a.mesh
        else f"    shape: {{mesh: {{file: {a.mesh}}}}}",
    ]
    if kind == "projectile":
        # A block of the same steel, 50 mm wide (the projectile's diameter, thesis sec.
        # 6.2.2), a.proj_length long, one spacing from the plate (contact at 0.9 h).
        lines += [
            "  - name: projectile",
            "    material: striker",
            f"    shape: {{box: {{min: [{-a.proj_length!r}, -0.025], max: [0, 0.025]}}}}",
        ]
    lines += [
        "precracks:",
        "  - {from: [-0.001, 0.025], to: [0.05, 0.025]}",
        "  - {from: [-0.001, -0.025], to: [0.05, -0.025]}",
        "regions:",
    ]
    if kind == "projectile":
        lines += [
            f"  striker: {{box: {{min: [{-a.proj_length - 0.001!r}, -0.026], max: [-0.0001, 0.026]}}}}",
            "initial_conditions:",
            f"  - {{region: striker, velocity: [{speed}, 0]}}",
        ]
    else:  # held: the velocity prescribed on the struck edge's first column for the whole run
        lines += [
            f"  impact: {{box: {{min: [-0.001, -0.0245], max: [{h!r}, 0.0245]}}}}",
            "loads:",
            f"  - {{region: impact, velocity: [{speed}, null]}}",
        ]
    if a.contact != "none":  # none: no contact at all (crack faces pass through each other)
        lines.append(f"contact: {{short_range: {{max_distance: {a.contact}}}}}")
    lines += [
        f"solver: {{type: explicit, end_time: {a.end_time!r}, safety_factor: {a.safety},"
        " adaptive_time_step: true, adaptive_every: 10}",
        "output: {directory: out/kalthoff_variant, frames: 4, history_every: 50}",
    ]
    return "\n".join(lines) + "\n"


def main():
    import sys
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--delta", type=float, default=0.005, help="horizon [m] (thesis Table 6.2: 0.005)")
    ap.add_argument("--ratio", type=float, default=5, help="horizon / spacing")
    ap.add_argument("--plane", default="strain", choices=["strain", "stress"])
    ap.add_argument("--m", default="0", help="Seth-Hill m")
    ap.add_argument("--p", default="2", help="failure_length_exponent (thesis eq. 6.3: 2)")
    ap.add_argument("--gc", default="22000", help="fracture energy [J/m^2]")
    ap.add_argument("--broken", default="off", choices=["off", "compression_only"])
    ap.add_argument("--load", default="held:16", help="held:V (velocity V on the struck edge) or projectile:V")
    ap.add_argument("--proj-length", type=float, default=0.1, help="projectile length [m]")
    ap.add_argument("--contact", default="0.9", help="contact.short_range.max_distance [spacings], or none")
    ap.add_argument("--mesh", help="the plate from a 2-D Gmsh mesh (particles at the triangles' centroids;"
                    " scripts/kalthoff_plate.geo), instead of the square lattice; --ratio then gives"
                    " the spacing the contact and the loaded layer use")
    ap.add_argument("--end-time", type=float, default=7.0e-5)
    ap.add_argument("--safety", default="0.5", help="solver.safety_factor")
    a = ap.parse_args()
    a.argv = " ".join(sys.argv[1:])
    sys.stdout.write(deck(a))


if __name__ == "__main__":
    main()
