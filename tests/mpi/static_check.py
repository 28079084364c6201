#!/usr/bin/env python3
"""Checks of tests/mpi/static.cmake on the last frames of static runs (raw appended VTU,
UInt64 headers, as output/vtu.cpp writes them; the reader of bench/static/compare_frames.py).
Usage: static_check.py SERIAL_FRAME RANKS_FRAME... ; prints the figures, exits 1 on a miss:
  - every RANKS_FRAME's displacement field is bit-identical to the first's;
  - max |u_ranks - u_serial| / max |u_serial| <= 1e-8;
  - the mean x-displacement of the particles at x = 19.5 mm minus that at x = 0.5 mm
    against sigma (19 mm) / E = 1.9e-6 m, within 3 %."""
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

    return array(r'<DataArray type="Float64" Name="Points"'), array(r'Name="displacement"')


def main():
    serial_x, serial_u = fields(sys.argv[1])
    runs = [fields(p)[1] for p in sys.argv[2:]]
    ok = True
    for p, u in zip(sys.argv[3:], runs[1:]):
        same = u == runs[0]
        print(f"{p}: {'bit-identical to' if same else 'DIFFERS from'} {sys.argv[2]}")
        ok = ok and same
    u = runs[0]
    scale = max(abs(v) for v in serial_u)
    diff = max(abs(a - b) for a, b in zip(u, serial_u)) / scale
    print(f"max |u_ranks - u_serial| / max |u_serial| = {diff:.3e} (max |u| = {scale:.4e} m)")
    ok = ok and diff <= 1e-8
    n = len(serial_x) // 3
    # The end layers by their reference x (the frame's points).
    left = [u[3 * i] for i in range(n) if abs(serial_x[3 * i] - 0.0005) < 1e-4]
    right = [u[3 * i] for i in range(n) if abs(serial_x[3 * i] - 0.0195) < 1e-4]
    elong = sum(right) / len(right) - sum(left) / len(left)
    analytic = 2.0e7 * 0.019 / 200.0e9
    err = elong / analytic - 1
    print(f"end layers ({len(left)}, {len(right)} particles): elongation {elong:.6e} m, analytic {analytic:.6e} m, "
          f"error {100 * err:+.2f} %")
    ok = ok and abs(err) <= 0.03
    return 0 if ok else 1


sys.exit(main())
