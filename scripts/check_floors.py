#!/usr/bin/env python3
"""Checks that Horizon's includes follow the floors (docs/design.md, "Floors").

Every `#include "horizon/..."` in src/horizon/, app/ and python/ must go from a room to
a room on a lower floor, or stay in its own room. Rooms on one floor may not include
each other. Prints every violation as `file:line: from-room -> to-room (include)` and
exits 1 if there is any, 0 otherwise. Usage: python3 scripts/check_floors.py [repo root]
"""
import os
import re
import sys

# The floors, lowest first; the rooms of a floor are alternatives beside each other.
# Why each room sits where it does (docs/design.md, "Floors"):
#   kernels        the device-portable per-bond and per-particle functions (HORIZON_HD)
#                  over plain doubles and flat arrays: the host's passes and the CUDA
#                  backend call them, so they stand on core alone.
#   cuda           the CUDA backend (cuda_backend.cu, built with -DHORIZON_CUDA=ON): a
#                  backend of the explicit solver beside it; it includes only kernels and
#                  core, so that the device machine builds it without the Debian libraries.
#   parallel       the rank decomposition's declarations (parallel/*.hpp, over core types
#                  only), so that every room can sum over ranks (GridSum) and ask which
#                  particles a rank holds.
#   deck.config    deck/config.hpp, the typed deck: plain data over shapes and bond kinds.
#   state          the run's particle and bond arrays (System), which every model reads.
#   contact        contact forces; state holds the contact's pair list (state/short_range.hpp).
#   damage         measurements of the damage field (crack fronts, edge cracks).
#   loading        boundary and initial conditions; indenters and projectiles are loads,
#                  so loading stands on contact.
#   thermal, fe    the heat conduction selects its boundary layers with loading's regions;
#                  the FE regions implement state's FeCoupling.
#   output         frame, checkpoint, truss and picture writers: they read state.
#   solver         the builder of the state and the integrators; the deck reader (the
#                  rest of deck/: it reads what the models and contact declare) and the
#                  rank decomposition's implementation (parallel/*.cpp: it splits a whole
#                  System, its FE regions and its checkpoints) sit beside it.
FLOORS = [
    ["core"],
    ["kernels"],
    ["parallel"],
    ["geometry"],
    ["family"],
    ["deck.config"],
    ["state"],
    ["material"],
    ["contact", "damage"],
    ["loading"],
    ["thermal", "fe", "output"],
    ["solver", "deck", "parallel.run", "cuda"],
    ["driver"],
    ["app", "python"],
]
FLOOR = {room: level for level, rooms in enumerate(FLOORS) for room in rooms}

INCLUDE = re.compile(r'^\s*#\s*include\s*"horizon/([^"]+)"')
SOURCES = (".hpp", ".cpp", ".h", ".hpp.in", ".cu")


def room_of(path):
    """The room of a path under src/horizon/ (e.g. 'solver/forces.hpp')."""
    parts = path.split("/")
    top = parts[0]
    if len(parts) == 1:
        return "core"  # generated headers at the top (none today)
    if path == "deck/config.hpp":
        return "deck.config"
    if top == "parallel" and not path.endswith(".hpp"):
        return "parallel.run"
    return top


def sources(root):
    for base, prefix in (("src/horizon", None), ("app", "app"), ("python", "python")):
        top = os.path.join(root, base)
        for directory, _, files in os.walk(top):
            for name in sorted(files):
                if not name.endswith(SOURCES):
                    continue
                full = os.path.join(directory, name)
                rel = os.path.relpath(full, top).replace(os.sep, "/")
                yield full, (prefix if prefix else room_of(rel))


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    root = os.path.abspath(root)
    violations, unknown, count = [], [], 0
    for full, room in sorted(sources(root)):
        rel = os.path.relpath(full, root)
        if room not in FLOOR:
            unknown.append(f"{rel}: room '{room}' is on no floor (scripts/check_floors.py FLOORS)")
            continue
        with open(full, encoding="utf-8", errors="replace") as f:
            for line_no, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                count += 1
                target = room_of(m.group(1))
                if target not in FLOOR:
                    unknown.append(f"{rel}:{line_no}: includes room '{target}', on no floor")
                elif target != room and FLOOR[target] >= FLOOR[room]:
                    where = "beside" if FLOOR[target] == FLOOR[room] else "above"
                    violations.append(f"{rel}:{line_no}: {room} -> {target} ({where}; horizon/{m.group(1)})")
    for v in unknown + violations:
        print(v)
    order = " < ".join("(" + ", ".join(r) + ")" if len(r) > 1 else r[0] for r in FLOORS)
    print(f"floors: {order}")
    print(f"{count} includes checked, {len(violations)} against the floors, {len(unknown)} unplaced")
    return 1 if violations or unknown else 0


if __name__ == "__main__":
    sys.exit(main())
