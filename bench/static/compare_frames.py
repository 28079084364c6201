#!/usr/bin/env python3
"""max |u_a - u_b| / max |u_b| between the displacement fields of two Horizon VTU frames
(raw appended data, UInt64 headers, as output/vtu.cpp writes them). Usage:
  compare_frames.py a.vtu b.vtu"""
import re
import struct
import sys


def displacement(path):
    data = open(path, "rb").read()
    head_end = data.index(b"<AppendedData")
    start = data.index(b"_", head_end) + 1
    head = data[:head_end].decode()
    m = re.search(r'Name="displacement" NumberOfComponents="3" NumberOfTuples="(\d+)" format="appended" offset="(\d+)"', head)
    n, off = int(m.group(1)), int(m.group(2))
    nbytes = struct.unpack_from("<Q", data, start + off)[0]
    return struct.unpack_from("<%dd" % (nbytes // 8), data, start + off + 8)


a, b = displacement(sys.argv[1]), displacement(sys.argv[2])
diff = max(abs(x - y) for x, y in zip(a, b))
scale = max(abs(y) for y in b)
print(f"max |u_a - u_b| / max |u_b| = {diff / scale:.3e}  (max |u_b| = {scale:.4e} m)")
# The same after removing the mean difference (a rigid translation: explicit runs with
# mass-proportional damping relax the rigid motion of a body on statically determinate
# supports only slowly, so compare deformations).
n = len(a) // 3
mean = [sum(a[3 * i + c] - b[3 * i + c] for i in range(n)) / n for c in range(3)]
diff_t = max(abs(a[3 * i + c] - b[3 * i + c] - mean[c]) for i in range(n) for c in range(3))
print(f"without the mean translation ({mean[0]:.3e}, {mean[1]:.3e}, {mean[2]:.3e}) m: {diff_t / scale:.3e}")
