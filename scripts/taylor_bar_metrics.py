#!/usr/bin/env python3
"""Taylor-bar figures from the last frame of a run (standard library only).

usage: taylor_bar_metrics.py RUN_DIR_OR_VTU [--axis y] [--length 0.0324] [--radius 0.0032] [--volume]

Reads the Horizon VTU (raw appended Float64 arrays; Points are reference positions, the
current position is Points + displacement) and prints, for a bar along `axis` that hit a
wall at `wall` from above:
  final length  = the current axial extent of the particles plus what the lattice leaves
                  out of the bar at its ends (length - reference extent) [mm]
  face radius   = max radial distance of the particles within one spacing of the lowest
                  one, plus what the lattice leaves out at the mantle (radius - largest
                  reference radial distance) [mm]
  attached face radius = the same over the bar's body alone: the largest set of particles
                  connected through current distances <= 1.5 spacings; particles the rim
                  ejects (detached, further than 1.5 spacings from every particle of the
                  body) are left out [mm]
  peak plastic  = max equivalent_plastic_strain (and its 99th percentile)
  --volume: the volume ratio J = det F of each particle (F the classical nonlocal
            deformation gradient over its lattice neighbours within 3.01 spacings, all
            weights 1): volume-weighted mean and minimum, and the mean in the lowest 3 mm.
"""
import glob
import os
import re
import struct
import sys


def read_vtu(path):
    data = open(path, "rb").read()
    head_end = data.index(b"<AppendedData")
    head = data[:head_end].decode()
    start = data.index(b"_", head_end) + 1
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="([^"]+)" NumberOfComponents="(\d+)" '
                         r'NumberOfTuples="(\d+)" format="appended" offset="(\d+)"', head):
        typ, name, comp, tup, off = m.group(1), m.group(2), int(m.group(3)), int(m.group(4)), int(m.group(5))
        if typ != "Float64":
            continue
        at = start + off
        (count,) = struct.unpack_from("<Q", data, at)
        vals = struct.unpack_from("<%dd" % (count // 8), data, at + 8)
        arrays[name] = (comp, vals)
    return arrays


def last_frame(path):
    if os.path.isdir(path):
        frames = sorted(glob.glob(os.path.join(path, "**", "*.vtu"), recursive=True),
                        key=lambda p: [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", p)])
        if not frames:
            sys.exit("no .vtu frame under " + path)
        return frames[-1]
    return path


def main():
    args = sys.argv[1:]
    axis, length, radius = 1, 0.0324, 0.0032
    if "--axis" in args:
        axis = "xyz".index(args[args.index("--axis") + 1])
    if "--length" in args:
        length = float(args[args.index("--length") + 1])
    if "--radius" in args:
        radius = float(args[args.index("--radius") + 1])
    path = last_frame(args[0])
    a = read_vtu(path)
    X = a["Points"][1]
    U = a["displacement"][1]
    n = len(X) // 3
    cur = [[X[3 * i + k] + U[3 * i + k] for k in range(3)] for i in range(n)]
    ref = [[X[3 * i + k] for k in range(3)] for i in range(n)]
    others = [k for k in range(3) if k != axis]
    # spacing: the smallest reference distance along the axis between distinct layers
    zs = sorted(set(round(p[axis], 12) for p in ref))
    h = min(b - a_ for a_, b in zip(zs, zs[1:]))
    top = max(p[axis] for p in cur)
    low = min(p[axis] for p in cur)
    face = [p for p in cur if p[axis] < low + h]
    rad = lambda p: (p[others[0]] ** 2 + p[others[1]] ** 2) ** 0.5
    r_gap = radius - max(rad(p) for p in ref)
    l_gap = length - (max(p[axis] for p in ref) - min(p[axis] for p in ref))
    r_face = max(rad(p) for p in face) + r_gap
    body = attached(cur, 1.5 * h)
    blow = min(cur[i][axis] for i in body)
    r_att = max(rad(cur[i]) for i in body if cur[i][axis] < blow + h) + r_gap
    ep = a.get("equivalent_plastic_strain", (1, [0.0]))[1]
    eps = sorted(ep)
    print("frame %s: %d particles, spacing %.4g mm" % (path, n, h * 1e3))
    print("final length %.2f mm" % ((top - low + l_gap) * 1e3))
    print("impact-face radius %.2f mm" % (r_face * 1e3))
    print("attached face radius %.2f mm (%d detached particles left out)" % (r_att * 1e3, n - len(body)))
    print("peak equivalent plastic strain %.3f (99th percentile %.3f)" % (eps[-1], eps[int(0.99 * (len(eps) - 1))]))

    if "--volume" in args:
        volume_ratio(ref, cur, h, axis, low)


def attached(cur, link):
    """Indices of the largest set of particles joined by current distances <= link."""
    cell = lambda p: tuple(int(c // link) for c in p)
    cells = {}
    for i, p in enumerate(cur):
        cells.setdefault(cell(p), []).append(i)
    seen = [False] * len(cur)
    best = []
    for s0 in range(len(cur)):
        if seen[s0]:
            continue
        seen[s0] = True
        comp, stack = [], [s0]
        while stack:
            i = stack.pop()
            comp.append(i)
            c = cell(cur[i])
            for a in (-1, 0, 1):
                for b in (-1, 0, 1):
                    for d in (-1, 0, 1):
                        for j in cells.get((c[0] + a, c[1] + b, c[2] + d), ()):
                            if not seen[j] and sum((cur[j][k] - cur[i][k]) ** 2 for k in range(3)) <= link * link:
                                seen[j] = True
                                stack.append(j)
        if len(comp) > len(best):
            best = comp
    return best


def det3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def volume_ratio(ref, cur, h, axis, low):
    key = lambda p: tuple(int(round(c / h)) for c in p)
    index = {key(p): i for i, p in enumerate(ref)}
    reach = 3
    offsets = [(a, b, c) for a in range(-reach, reach + 1) for b in range(-reach, reach + 1)
               for c in range(-reach, reach + 1) if 0 < a * a + b * b + c * c <= 9.06]
    Js, low_Js = [], []
    for i, p in enumerate(ref):
        k0 = key(p)
        K = [[0.0] * 3 for _ in range(3)]
        N = [[0.0] * 3 for _ in range(3)]
        for o in offsets:
            j = index.get((k0[0] + o[0], k0[1] + o[1], k0[2] + o[2]))
            if j is None:
                continue
            xi = [ref[j][c] - p[c] for c in range(3)]
            Y = [cur[j][c] - cur[i][c] for c in range(3)]
            for r in range(3):
                for c in range(3):
                    K[r][c] += xi[r] * xi[c]
                    N[r][c] += Y[r] * xi[c]
        dk = det3(K)
        if abs(dk) < 1e-30:
            continue
        J = det3(N) / dk
        Js.append(J)
        if cur[i][axis] < low + 3e-3:
            low_Js.append(J)
    print("volume ratio det F: mean %.3f, min %.3f; mean in the lowest 3 mm %.3f" %
          (sum(Js) / len(Js), min(Js), sum(low_Js) / max(len(low_Js), 1)))


if __name__ == "__main__":
    main()
