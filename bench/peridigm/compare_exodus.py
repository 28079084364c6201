#!/usr/bin/python3
"""Compare an Exodus II result with a gold file under an exodiff command file (.comp).

Usage: compare_exodus.py RESULT.e GOLD.e COMMANDS.comp [--at-gold-times]

--at-gold-times: a result that holds more time steps than the gold is compared at the
gold's times (each gold time must be one of the result's, within the TIME STEPS
tolerance). The suite runner passes it for a deck copy in an npN/ folder, whose own
Output Frequency can differ from the deck its folder's gold belongs to.

Horizon's own reading of exodiff's command-file format (SEACAS exodiff: its -help file
and -help tolerance texts; exodiff is not packaged by Debian, so the suite runner cannot
call it):
  DEFAULT TOLERANCE <spec>         the variables' default (compiled: relative 1e-6 floor 0)
  COORDINATES <spec>               the nodes' reference coordinates (absolute 1e-6 floor 0,
                                   or the DEFAULT TOLERANCE given above it)
  TIME STEPS <spec>                the time values (the default tolerance)
  GLOBAL|NODAL|ELEMENT VARIABLES [(all)] <spec>
      <tab>Name [<spec>]           compare only the listed variables (with their own
      <tab>!Name                   spec, else the section's); none listed, or (all): all
                                   of the gold's but those excluded with !
  <spec> = absolute|relative|combined T [floor F] | ignore | floor F | T (a bare value:
           the enclosing kind; on a VARIABLES line exodiff refuses it)
A spec starts from what it inherits (a section from the DEFAULT TOLERANCE, a variable from
its section): a kind replaces the kind and value and keeps the floor. A value pair passes
when |a - b| <= T (absolute), |a - b| <= T max(|a|, |b|) (relative), |a - b| <
T max(1, |a|, |b|) (combined), and always when both |a| and |b| are at most the floor F.
Variable names compare case-insensitively. Sections of variables the file does not name
are not compared, as with exodiff -f; coordinates and times are always compared. Every
time step is compared; the files must hold the same number. Nodes pair by file order
when the coordinates agree within their tolerance, else by coordinates within the
tolerance (as exodiff -m); element variables of one-node (SPHERE) elements are compared
at their node. Node and side sets are not compared.

RESULT.e may be several files joined by '+' (A.e+B.e): their time steps in time order, as
SEACAS's conjoin joins the files of one run before Peridigm's scripts compare them
(Compression_QS_Explicit_MultiFreqOutput: the _QS.e and _Explicit.e files of its two
Output lists against one gold). The files must have the same nodes and variables.

Prints one line: "match" (exit 0), "differs: ..." with the largest excess over the
tolerance, its variable, node and time step (exit 1), or "error: ..." (exit 2).
"""
import sys

import numpy as np
import netCDF4


def names(ds, var):
    if var not in ds.variables:
        return []
    # latin-1: a name padded with stray bytes still reads (exodiff compares the text)
    return [str(s).strip() for s in netCDF4.chartostring(ds.variables[var][:], encoding="latin-1")]


class Spec:
    def __init__(self, kind="absolute", tol=0.0, floor=0.0):
        self.kind, self.tol, self.floor = kind, tol, floor

    def excess(self, a, b):
        """Per value: how far |a - b| exceeds the allowed difference (<= 0: passes)."""
        a = np.asarray(a, dtype=float)
        b = np.asarray(b, dtype=float)
        d = np.abs(a - b)
        big = np.maximum(np.abs(a), np.abs(b))
        if self.kind == "relative":
            allowed = self.tol * big
        elif self.kind == "combined":  # exodiff: differs when |a - b| >= T max(1, |a|, |b|)
            allowed = np.nextafter(self.tol * np.maximum(big, 1.0), -np.inf)
        else:
            allowed = np.full(d.shape, self.tol)
        out = d - allowed
        if self.kind == "ignore":
            out[:] = -1.0
        out[(np.abs(a) <= self.floor) & (np.abs(b) <= self.floor)] = -1.0
        out[np.isnan(a) != np.isnan(b)] = np.inf
        return out

    def __str__(self):
        s = f"{self.kind} {self.tol:g}"
        return s + (f" floor {self.floor:g}" if self.floor else "")


KINDS = ("absolute", "relative", "combined", "ignore")


def _kind(word):
    """The tolerance kind a word names (exodiff takes any abbreviation of 3 letters or more),
    else None."""
    w = word.lower()
    for k in KINDS:
        if len(w) >= 3 and k.startswith(w):
            return k
    return None


def parse_spec(words, base, bare="kind"):
    """A tolerance spec read after a keyword, starting from `base` (what it inherits):
    [kind T] [floor F]. A kind replaces the base's kind and value and keeps its floor;
    `floor F` replaces the floor. A bare number: bare="kind" keeps the base's kind and
    takes the value (a variable line, DEFAULT TOLERANCE); bare="ignore" leaves the base
    as it is (COORDINATES and TIME STEPS read a kind word first, exodiff skips a number);
    bare="error" refuses it (a VARIABLES line, where exodiff stops on it)."""
    spec = Spec(base.kind, base.tol, base.floor)
    k = 0
    if k < len(words) and _kind(words[k]):
        spec.kind = _kind(words[k])
        k += 1
        if spec.kind == "ignore":
            spec.tol = 0.0
        else:
            if k >= len(words) or words[k].lower() == "floor":
                raise ValueError(f"tolerance kind '{words[k - 1]}' without a value")
            spec.tol = float(words[k])
            k += 1
    elif k < len(words) and words[k].lower() != "floor" and not words[k].startswith("#"):
        if bare == "error":
            raise ValueError(f"unrecognized keyword '{words[k]}'")
        if bare == "kind":
            spec.tol = float(words[k])
        k += 1
    if k < len(words) and words[k].lower().startswith("flo"):
        if k + 1 >= len(words):
            raise ValueError("floor without a value")
        spec.floor = float(words[k + 1])
    return spec


def parse_comp(path):
    """Sections as exodiff reads its command file (-f): {key: (spec, {name: spec}, excluded, all)}.

    exodiff's compiled defaults: variables relative 1e-6 floor 0, coordinates absolute 1e-6
    floor 0, time steps the variables' default. DEFAULT TOLERANCE replaces the variables'
    default (and, given before them, the COORDINATES and TIME STEPS lines' base); a section
    line starts from that default, so its floor is the default's unless it names one; a
    variable line starts from its section's spec. Coordinates and times are always compared;
    a section the file does not name compares no variables of its kind."""
    default = Spec("relative", 1e-6, 0.0)
    default_given = False
    sections = {"coordinates": (Spec("absolute", 1e-6, 0.0), {}, set(), False),
                "time": (Spec("relative", 1e-6, 0.0), {}, set(), False)}
    current = None
    with open(path) as f:
        for raw in f:
            line = raw.split("#", 1)[0].rstrip()
            if not line.strip():
                continue
            words = line.split()
            # A variable name starts with a tab (exodiff); spaces are read the same here.
            if raw[0] in " \t" and current is not None:
                spec, listed, excluded, _ = sections[current]
                name = words[0]
                if name.startswith("!"):
                    excluded.add(name[1:].lower())
                elif len(words) > 1:
                    listed[name] = parse_spec(words[1:], spec)
                else:
                    listed[name] = spec
                continue
            current = None
            upper = [w.upper() for w in words]
            if len(upper) >= 2 and upper[0].startswith("DEF") and upper[1].startswith("TOL"):
                if len(words) < 3:
                    raise ValueError(f"{path}: DEFAULT TOLERANCE without a value")
                default = parse_spec(words[2:], default)
                default_given = True
            elif upper[0].startswith("COOR"):
                base = default if default_given else Spec("absolute", 1e-6, 0.0)
                sections["coordinates"] = (parse_spec(words[1:], base, bare="ignore"), {}, set(), False)
            elif upper[:1] == ["TIME"] and len(upper) >= 2 and upper[1].startswith("STEP"):
                sections["time"] = (parse_spec(words[2:], default, bare="ignore"), {}, set(), False)
            elif len(upper) >= 2 and upper[1].startswith("VAR") and upper[0] in ("GLOBAL", "NODAL", "ELEMENT"):
                current = upper[0].lower()
                rest = words[2:]
                every = bool(rest) and rest[0].lower() in ("(all)", "all")
                if every:
                    rest = rest[1:]
                sections[current] = (parse_spec(rest, default, bare="error"), {}, set(), every)
            else:
                raise ValueError(f"{path}: cannot read the line '{line.strip()}'")
    return sections


def coords(ds):
    n = ds.dimensions["num_nodes"].size
    cols = [ds.variables[c][:] if c in ds.variables else np.zeros(n) for c in ("coordx", "coordy", "coordz")]
    if "coord" in ds.variables:
        c = ds.variables["coord"][:]
        cols = [c[k] if k < c.shape[0] else np.zeros(n) for k in range(3)]
    return np.stack([np.asarray(c, dtype=float) for c in cols], axis=1)


def element_values(ds, index, steps):
    """Element variable `index` (1-based) at its elements' first nodes: [step][node]."""
    n = ds.dimensions["num_nodes"].size
    out = np.full((steps, n), np.nan)
    nblk = ds.dimensions["num_el_blk"].size if "num_el_blk" in ds.dimensions else 0
    for b in range(1, nblk + 1):
        name = f"vals_elem_var{index}eb{b}"
        if name not in ds.variables or f"connect{b}" not in ds.variables:
            continue
        first = np.asarray(ds.variables[f"connect{b}"][:])[:, 0] - 1
        out[:, first] = np.asarray(ds.variables[name][:steps], dtype=float)
    return out


def variable(ds, kind, name, steps):
    """[step][item] values of a variable, or None when the file lacks it."""
    if kind == "global":
        vars_ = [n.lower() for n in names(ds, "name_glo_var")]
        if name.lower() not in vars_:
            return None
        return np.asarray(ds.variables["vals_glo_var"][:steps], dtype=float)[:, vars_.index(name.lower())][:, None]
    if kind == "nodal":
        vars_ = [n.lower() for n in names(ds, "name_nod_var")]
        if name.lower() not in vars_:
            return None
        k = vars_.index(name.lower()) + 1
        if f"vals_nod_var{k}" in ds.variables:
            return np.asarray(ds.variables[f"vals_nod_var{k}"][:steps], dtype=float)
        return np.asarray(ds.variables["vals_nod_var"][:steps, k - 1, :], dtype=float)
    vars_ = [n.lower() for n in names(ds, "name_elem_var")]
    if name.lower() not in vars_:
        return None
    return element_values(ds, vars_.index(name.lower()) + 1, steps)


def node_pairing(xr, xg, spec):
    """Index into the result's nodes for each gold node, or None."""
    if xr.shape == xg.shape and np.all(spec.excess(xr, xg) <= 0):
        return np.arange(len(xg))
    if xr.shape != xg.shape:
        return None
    # By coordinates: sort both lexicographically and require agreement.
    order_r = np.lexsort((xr[:, 2], xr[:, 1], xr[:, 0]))
    order_g = np.lexsort((xg[:, 2], xg[:, 1], xg[:, 0]))
    if np.all(spec.excess(xr[order_r], xg[order_g]) <= 0):
        pair = np.empty(len(xg), dtype=int)
        pair[order_g] = order_r
        return pair
    # Coordinates that agree within the tolerance but not exactly sort differently (a tie
    # in x broken by 1e-15): match each gold node to an unused result node within the
    # tolerance, searching a window of x (exodiff -m matches within its tolerance too).
    width = spec.tol * max(1.0, float(np.abs(xg).max(initial=0.0)), float(np.abs(xr).max(initial=0.0)))
    by_x = np.argsort(xr[:, 0], kind="stable")
    xs = xr[by_x, 0]
    used = np.zeros(len(xr), dtype=bool)
    pair = np.empty(len(xg), dtype=int)
    for g, p in enumerate(xg):
        lo = np.searchsorted(xs, p[0] - width, "left")
        hi = np.searchsorted(xs, p[0] + width, "right")
        cand = by_x[lo:hi]
        cand = cand[~used[cand]]
        ok = cand[np.all(spec.excess(xr[cand], np.broadcast_to(p, (len(cand), 3))) <= 0, axis=1)] if len(cand) else cand
        if len(ok) == 0:
            return None
        pair[g] = ok[0]
        used[ok[0]] = True
    return pair


def link_target(path):
    """A git symbolic link checked out as a plain file holds its target's relative path
    (BondBreakingInitialVelocity-EP's gold is "../BondBreakingInitialVelocity/..._gold.e"
    in a snapshot without links): the file it names, else the path itself."""
    import os
    if os.path.getsize(path) < 1024:
        with open(path, "rb") as f:
            text = f.read().decode("latin-1").strip()
        target = os.path.normpath(os.path.join(os.path.dirname(path), text))
        if text and "\n" not in text and os.path.isfile(target):
            return target
    return path


def conjoin(files, out):
    """Writes the time steps of `files` in turn into `out` (one layout: the first file's)."""
    src = [netCDF4.Dataset(f) for f in files]
    # In time order (conjoin's output is; the runner passes the files by name).
    src.sort(key=lambda ds: float(ds.variables["time_whole"][0]) if ds.variables["time_whole"].size else 0.0)
    first = src[0]
    dst = netCDF4.Dataset(out, "w", format=first.data_model)
    dst.setncatts({a: first.getncattr(a) for a in first.ncattrs()})
    for name, dim in first.dimensions.items():
        dst.createDimension(name, None if dim.isunlimited() else dim.size)
    for name, var in first.variables.items():
        v = dst.createVariable(name, var.datatype, var.dimensions)
        v.setncatts({a: var.getncattr(a) for a in var.ncattrs()})
        if var.dimensions and first.dimensions[var.dimensions[0]].isunlimited():
            parts = []
            for ds in src:
                if name not in ds.variables:
                    raise ValueError(f"{name} is not in every file to join")
                parts.append(np.asarray(ds.variables[name][:]))
            v[:] = np.concatenate(parts, axis=0)
        else:
            v[:] = var[:]
    dst.close()
    for ds in src:
        ds.close()


def compare(result, gold, comp, at_gold_times=False):
    sections = parse_comp(comp)
    gold = link_target(gold)
    if "+" in result:
        import os
        import tempfile
        fd, joined = tempfile.mkstemp(suffix=".e")
        os.close(fd)
        try:
            conjoin(result.split("+"), joined)
            return compare(joined, gold, comp, at_gold_times)
        finally:
            os.remove(joined)
    r = netCDF4.Dataset(result)
    g = netCDF4.Dataset(gold)
    tr = np.asarray(r.variables["time_whole"][:], dtype=float) if "time_whole" in r.variables else np.zeros(0)
    tg = np.asarray(g.variables["time_whole"][:], dtype=float) if "time_whole" in g.variables else np.zeros(0)
    pick = None  # result steps compared with the gold's, in order (None: all, one for one)
    if at_gold_times and len(tr) > len(tg):
        tspec = sections["time"][0]
        chosen = []
        for t in tg:
            e = tspec.excess(tr, np.full_like(tr, t))
            k = int(np.argmin(e))
            if e[k] > 0:
                chosen = None
                break
            chosen.append(k)
        if chosen is not None:
            pick = np.asarray(chosen)
            tr = tr[pick]
    if len(tr) != len(tg):
        return 1, f"differs: {len(tr)} time steps, the gold has {len(tg)} (t = {tr[-1] if len(tr) else 0:g} / {tg[-1] if len(tg) else 0:g})"
    steps = len(tg)
    if True:  # exodiff compares the times always (TIME STEPS, else the default tolerance)
        e = sections["time"][0].excess(tr, tg)
        if np.any(e > 0):
            k = int(np.argmax(e))
            return 1, f"differs: time of step {k + 1}: {tr[k]:.9g} vs gold {tg[k]:.9g} ({sections['time'][0]})"
    xr, xg = coords(r), coords(g)
    cspec = sections["coordinates"][0]
    pair = node_pairing(xr, xg, cspec)
    if pair is None:
        return 1, f"differs: the nodes ({len(xr)} vs the gold's {len(xg)}) do not pair by coordinates ({cspec})"
    worst = None  # (excess, text)
    for kind in ("global", "nodal", "element"):
        if kind not in sections:
            continue
        spec, listed, excluded, every = sections[kind]
        gold_names = names(g, {"global": "name_glo_var", "nodal": "name_nod_var", "element": "name_elem_var"}[kind])
        # Names compare case-insensitively (exodiff's default): the gold's spelling is read.
        by_lower = {n.lower(): n for n in gold_names}
        wanted = {by_lower.get(n.lower(), n): t for n, t in listed.items()}
        if every or not listed:  # (all), or no names listed: every gold variable not excluded
            for n in gold_names:
                wanted.setdefault(n, spec)
        for n in list(wanted):
            if n.lower() in excluded:
                del wanted[n]
        for name, s in wanted.items():
            vg = variable(g, kind, name, steps)
            if vg is None:
                continue  # exodiff reports a listed variable absent from both files as a warning only
            vr = variable(r, kind, name, steps if pick is None else int(pick[-1]) + 1)
            if vr is not None and pick is not None:
                vr = vr[pick]
            if vr is None:
                return 1, f"differs: no {kind} variable {name} in the result"
            if kind != "global":
                vr = vr[:, pair]
            mask = ~(np.isnan(vg) & np.isnan(vr))
            e = np.where(mask, s.excess(vr, vg), -1.0)
            k = np.unravel_index(int(np.argmax(e)), e.shape)
            if e[k] > 0:
                where = f"step {k[0] + 1}" + (f", node {k[1] + 1}" if kind != "global" else "")
                rel = e[k] / (s.tol if s.tol > 0 else 1)
                text = (f"differs: {name} {vr[k]:.6g} vs gold {vg[k]:.6g} (|diff| {abs(vr[k] - vg[k]):.3g}, "
                        f"{s}) at {where}")
                if worst is None or rel > worst[0]:
                    worst = (rel, text)
    if worst:
        return 1, worst[1]
    return 0, "match"


def main():
    args = sys.argv[1:]
    at_gold_times = "--at-gold-times" in args
    args = [a for a in args if a != "--at-gold-times"]
    if len(args) != 3:
        print(__doc__.split("\n\n")[1])
        return 2
    try:
        code, text = compare(*args, at_gold_times=at_gold_times)
    except Exception as e:  # a file that cannot be read is the runner's "error", not a crash
        print(f"error: {e}")
        return 2
    print(text)
    return code


if __name__ == "__main__":
    sys.exit(main())
