"""The centre deflection of a plate run (the thin-plate benchmarks, plate_decks.sh): the
mean downward z displacement of the particles on the vertical line nearest the plate's
centre (a, a the plate's side), read from the run's last VTU frame (appended raw data)."""
import glob
import re
import struct


def centre_w(out, a):
    f = sorted(glob.glob(out + "/frames/*.vtu"))[-1]
    data = open(f, "rb").read()
    he = data.index(b"<AppendedData")
    start = data.index(b"_", he) + 1
    head = data[:he].decode()

    def arr(name, nc):
        m = re.search(r'Name="%s" NumberOfComponents="%d"[^>]*offset="(\d+)"' % (name, nc), head)
        off = int(m.group(1))
        nb = struct.unpack_from("<Q", data, start + off)[0]
        v = struct.unpack_from("<%dd" % (nb // 8), data, start + off + 8)
        return [v[i:i + nc] for i in range(0, len(v), nc)]

    X = arr("Points", 3)
    u = arr("displacement", 3)
    best = min(range(len(X)), key=lambda i: (X[i][0] - a / 2)**2 + (X[i][1] - a / 2)**2)
    xc, yc = X[best][0], X[best][1]
    ws = [u[i][2] for i in range(len(X)) if abs(X[i][0] - xc) < 1e-9 and abs(X[i][1] - yc) < 1e-9]
    return -sum(ws) / len(ws)
