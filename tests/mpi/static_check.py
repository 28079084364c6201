#!/usr/bin/env python3
"""Checks of tests/mpi/static.cmake on the last frames of static runs (raw appended VTU,
UInt64 headers, as output/vtu.cpp writes them; the reader of bench/static/compare_frames.py).
Usage: static_check.py MODE TOLERANCE SERIAL_FRAME RANKS_FRAME...
Prints the figures and exits 1 on a miss:
  - every RANKS_FRAME's displacement field is bit-identical to the first's;
  - max |u_ranks - u_serial| / max |u_serial| <= TOLERANCE;
  - MODE bar (tests/mpi/static_bar.yaml, 1-D, sigma / E = 1e-4, tip at 99 mm from the
    held particle): the strain between x = 20.5 and 79.5 mm (more than a horizon from
    the ends) is sigma / E within 1e-6 (Newton) or 1e-4 (ADR, tolerance 1e-6) of it,
    and the tip displacement is sigma (99 mm) / E within 3 % (the softer end layers).
  - MODE field: the two checks above only."""
import re
import struct
import sys


def fields(path):
    data = open(path, "rb").read()
    head_end = data.index(b"<AppendedData")
    start = data.index(b"_", head_end) + 1
    head = data[:head_end].decode()

    def array(pattern):
        m = re.search(pattern + r' NumberOfComponents="3"[^>]*format="appended" offset="(\d+)"', head)
        off = int(m.group(1))
        nbytes = struct.unpack_from("<Q", data, start + off)[0]
        return struct.unpack_from("<%dd" % (nbytes // 8), data, start + off + 8)

    return array(r'Name="Points"'), array(r'Name="displacement"')


def main():
    mode, tolerance = sys.argv[1], float(sys.argv[2])
    serial_x, serial_u = fields(sys.argv[3])
    paths = sys.argv[4:]
    runs = [fields(p)[1] for p in paths]
    ok = True
    for p, u in zip(paths[1:], runs[1:]):
        same = u == runs[0]
        print(f"{p}: {'bit-identical to' if same else 'DIFFERS from'} {paths[0]}")
        ok = ok and same
    u = runs[0]
    scale = max(abs(v) for v in serial_u)
    diff = max(abs(a - b) for a, b in zip(u, serial_u)) / scale
    print(f"max |u_ranks - u_serial| / max |u_serial| = {diff:.3e} (limit {tolerance:.0e}; max |u| = {scale:.4e} m)")
    ok = ok and diff <= tolerance
    if mode.startswith("bar"):
        n = len(serial_x) // 3
        x = [serial_x[3 * i] for i in range(n)]
        ux = [u[3 * i] for i in range(n)]
        at = lambda x0: min(range(n), key=lambda i: abs(x[i] - x0))
        a, b = at(0.0205), at(0.0795)
        strain = (ux[b] - ux[a]) / (x[b] - x[a])
        strain_error = strain / 1.0e-4 - 1
        tip = ux[at(0.0995)]
        tip_error = tip / (1.0e-4 * 0.099) - 1
        print(f"interior strain {strain:.12e} (sigma / E = 1e-4: {strain_error:+.2e}); tip {tip:.6e} m "
              f"(sigma L / E = 9.9e-6 m: {100 * tip_error:+.2f} %)")
        ok = ok and abs(strain_error) <= (1e-4 if mode == "bar_adr" else 1e-6) and abs(tip_error) <= 0.03
    return 0 if ok else 1


sys.exit(main())
