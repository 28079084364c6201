#!/usr/bin/python3
"""The Peridigm suite comparer's reading of exodiff command files (bench/peridigm/compare_exodus.py)
against exodiff's documented rules (its -help file and -help tolerance texts): the compiled
defaults, what a section and a variable line inherit, the tolerance kinds and the floor.
Exit 0: pass; 1: a failure (printed); 77: python3-netcdf4 or numpy missing (skipped)."""
import os
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "bench", "peridigm"))
try:
    import numpy as np
    import compare_exodus as ce
except ImportError as e:
    print(f"skipped: {e}")
    sys.exit(77)

failures = []


def check(what, got, want):
    if got != want:
        failures.append(f"{what}: got {got!r}, want {want!r}")


def spec(s):
    return (s.kind, s.tol, s.floor)


def parse(text):
    fd, path = tempfile.mkstemp(suffix=".comp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    try:
        return ce.parse_comp(path)
    finally:
        os.remove(path)


# No DEFAULT TOLERANCE: variables relative 1e-6 floor 0, coordinates absolute 1e-6, times
# the variables' default; a section line with no spec takes the default.
s = parse("NODAL VARIABLES\n\tDisplacementX\n")
check("default section", spec(s["nodal"][0]), ("relative", 1e-6, 0.0))
check("default variable", spec(s["nodal"][1]["DisplacementX"]), ("relative", 1e-6, 0.0))
check("default coordinates", spec(s["coordinates"][0]), ("absolute", 1e-6, 0.0))
check("default times", spec(s["time"][0]), ("relative", 1e-6, 0.0))
check("unnamed sections compare nothing", "element" in s, False)

# A section starts from the DEFAULT TOLERANCE and keeps its floor; a variable line from its
# section; a bare value keeps the kind; `floor` alone keeps the value.
s = parse("DEFAULT TOLERANCE relative 1.0E-8 floor 1.0E-14\n"
          "COORDINATES absolute 1.0E-12\n"
          "TIME STEPS absolute 1.0E-14\n"
          "NODAL VARIABLES absolute 1.0E-8\n"
          "\tA\n\tB absolute 1.0E-6\n\tC relative 1.0E-6 floor 1.0E-10\n\tD 1.0E-3\n\tE floor 0.5\n"
          "ELEMENT VARIABLES (all) combined 1.0E-5\n\t!Damage\n")
check("coordinates inherit the default's floor", spec(s["coordinates"][0]), ("absolute", 1e-12, 1e-14))
check("times", spec(s["time"][0]), ("absolute", 1e-14, 1e-14))
check("section", spec(s["nodal"][0]), ("absolute", 1e-8, 1e-14))
listed = s["nodal"][1]
check("A", spec(listed["A"]), ("absolute", 1e-8, 1e-14))
check("B", spec(listed["B"]), ("absolute", 1e-6, 1e-14))
check("C", spec(listed["C"]), ("relative", 1e-6, 1e-10))
check("D (bare value)", spec(listed["D"]), ("absolute", 1e-3, 1e-14))
check("E (floor only)", spec(listed["E"]), ("absolute", 1e-8, 0.5))
check("(all)", s["element"][3], True)
check("!Damage", s["element"][2], {"damage"})

# DEFAULT TOLERANCE with a bare value keeps the compiled kind (relative).
s = parse("DEFAULT TOLERANCE 1.0E-4\nGLOBAL VARIABLES\n")
check("bare default", spec(s["global"][0]), ("relative", 1e-4, 0.0))

# A bare value on a VARIABLES line is exodiff's parse error.
try:
    parse("NODAL VARIABLES 1.0E-8\n")
    failures.append("a bare value on a VARIABLES line was accepted")
except ValueError:
    pass

# The tests a pair must pass (exodiff's Tolerance::Diff): absolute |a - b| <= T, relative
# |a - b| <= T max(|a|, |b|), combined |a - b| < T max(1, |a|, |b|), both within the floor.
S = ce.Spec
check("absolute at T", bool(S("absolute", 1e-3).excess([1.0], [1.0 + 1e-3 / 2])[0] <= 0), True)
check("absolute over T", bool(S("absolute", 1e-3).excess([1.0], [1.002])[0] <= 0), False)
check("relative", bool(S("relative", 1e-6).excess([1e6], [1e6 + 0.5])[0] <= 0), True)
check("relative over", bool(S("relative", 1e-6).excess([1e6], [1e6 + 2])[0] <= 0), False)
check("combined small", bool(S("combined", 1e-6).excess([1e-3], [1e-3 + 2e-6])[0] <= 0), False)
check("combined large", bool(S("combined", 1e-6).excess([1e3], [1e3 + 5e-4])[0] <= 0), True)
check("floor", bool(S("absolute", 0.0, 1e-10).excess([1e-11], [-1e-11])[0] <= 0), True)
check("floor one beyond", bool(S("absolute", 0.0, 1e-10).excess([1e-9], [0.0])[0] <= 0), False)
check("ignore", bool(S("ignore", 0.0).excess([1.0], [2.0])[0] <= 0), True)

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("compare_exodus.py reads .comp files as exodiff does: pass")
