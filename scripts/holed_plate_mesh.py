#!/usr/bin/env python3
"""Writes examples/meshes/holed_plate.msh: a 20 x 20 x 3 mm plate with a central hole of
radius 4 mm, meshed with hexahedra on an O-grid (48 around the hole, 6 from the hole to
the edge, 3 through the thickness), in Gmsh's MSH 4.1 ASCII format (Gmsh reference manual,
sec. 10.1). Physical groups: volume "plate"; surfaces "top" (y = +10 mm), "bottom"
(y = -10 mm) and "hole". Used by examples/meshed_plate.yaml.
Usage: python3 scripts/holed_plate_mesh.py [output path]"""
import math
import sys

A, R, T = 0.010, 0.004, 0.003      # half-width, hole radius, thickness [m]
N, M, L = 48, 6, 3                 # around, radial, through the thickness


def node(i, j, k):
    return 1 + (j % N) + N * (i + (M + 1) * k)


def main(path):
    nodes = []
    for k in range(L + 1):
        for i in range(M + 1):
            for j in range(N):
                th = 2 * math.pi * j / N
                c, s = math.cos(th), math.sin(th)
                outer = A / max(abs(c), abs(s))
                t = i / M
                r = (1 - t) * R + t * outer
                x, y = r * c, r * s
                if i == M:  # exactly on the square
                    if abs(abs(x) - A) < 1e-12: x = math.copysign(A, x)
                    if abs(abs(y) - A) < 1e-12: y = math.copysign(A, y)
                nodes.append((x, y, T * k / L))
    hexes = []
    for k in range(L):
        for i in range(M):
            for j in range(N):
                b = [node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k)]
                tp = [node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)]
                hexes.append(b + tp)

    def face(i, pick):
        quads = []
        for k in range(L):
            for j in range(N):
                a, b = node(i, j, k), node(i, j + 1, k)
                if pick(nodes[a - 1]) and pick(nodes[b - 1]):
                    quads.append([a, b, node(i, j + 1, k + 1), node(i, j, k + 1)])
        return quads
    top = face(M, lambda p: p[1] == A)
    bottom = face(M, lambda p: p[1] == -A)
    hole = face(0, lambda p: True)
    blocks = [(3, 1, 5, hexes), (2, 1, 3, top), (2, 2, 3, bottom), (2, 3, 3, hole)]
    total = sum(len(b[3]) for b in blocks)
    with open(path, "w") as f:
        f.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        f.write('$PhysicalNames\n4\n3 1 "plate"\n2 2 "top"\n2 3 "bottom"\n2 4 "hole"\n$EndPhysicalNames\n')
        f.write("$Entities\n0 0 3 1\n")
        box = "%.6g %.6g 0 %.6g %.6g %.6g" % (-A, -A, A, A, T)
        for s in (1, 2, 3):
            f.write("%d %s 1 %d 0\n" % (s, box, s + 1))
        f.write("1 %s 1 1 3 1 2 3\n$EndEntities\n" % box)
        f.write("$Nodes\n1 %d 1 %d\n3 1 0 %d\n" % (len(nodes), len(nodes), len(nodes)))
        for n in range(len(nodes)):
            f.write("%d\n" % (n + 1))
        for p in nodes:
            f.write("%.9g %.9g %.9g\n" % p)
        f.write("$EndNodes\n$Elements\n%d %d 1 %d\n" % (len(blocks), total, total))
        tag = 1
        for dim, ent, typ, elems in blocks:
            f.write("%d %d %d %d\n" % (dim, ent, typ, len(elems)))
            for e in elems:
                f.write("%d %s\n" % (tag, " ".join(map(str, e))))
                tag += 1
        f.write("$EndElements\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "examples/meshes/holed_plate.msh")
