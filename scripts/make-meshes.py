#!/usr/bin/env python3
"""Writes binary STL files of closed, outward-oriented surfaces (test and benchmark meshes).

    python3 scripts/make-meshes.py OUTDIR [--only NAME ...] [shape options] [--check]

sphere.stl: an icosphere (--sphere-radius, --sphere-subdivisions; or --triangles N: the fewest
  subdivisions giving at least N triangles, 20 * 4^k, e.g. 200000 -> 327680 ... use it for a
  benchmark); torus.stl (--torus-R, --torus-r, --torus-segments); box.stl (--box-min, --box-max);
  wigley.stl: a Wigley hull y = B/2 (1 - (2x/L)^2)(1 - (z/T)^2), x in [-L/2, L/2], z in [-T, 0],
  both half-hulls and the deck z = 0 closing it (--wigley-L, -B, -T, --wigley-segments);
  pier.stl: a bridge pier, a column of round-nosed (stadium) section, its length along x, its
  bottom's centre at the origin (--pier-length, --pier-width, --pier-height, --pier-segments
  per round nose) (cases/pier3d.json's: the defaults);
  test2: SPHERIC Test 2's tank and box from its case file's numbers (--test2-case, default
  cases/dambreak3d.json, at --test2-dx, default the case's): tank.stl, the tank's walls as one
  solid, `layers` dx thick (the case's boundary.layers) outside its inner faces (bottom and four
  sides, open top), and box.stl, the obstacle; not written by default.
--check: reads each file written back and prints its triangles and enclosed volume against the
exact one (the sphere's and torus' are those of the smooth shape: the faceted one is smaller).
Needs python3 and numpy only.
"""
import argparse
import math
import os
import sys

import numpy as np

SHAPES = ("sphere", "torus", "box", "wigley", "pier", "test2")


def write_stl(path, tris, name):
    """tris: (n, 3, 3) float array; binary STL, normals from the winding."""
    tris = np.asarray(tris, dtype=np.float64)
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    ln = np.linalg.norm(n, axis=1)
    n = n / np.where(ln > 0, ln, 1)[:, None]
    rec = np.zeros(len(tris), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = n
    rec["v"] = tris
    with open(path, "wb") as f:
        f.write(name.encode()[:80].ljust(80, b" "))
        f.write(np.uint32(len(tris)).tobytes())
        f.write(rec.tobytes())


def read_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    n = int(np.frombuffer(data, "<u4", 1, 80)[0])
    rec = np.frombuffer(data, dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")],
                        count=n, offset=84)
    return rec["v"].astype(np.float64)


def volume(tris):
    c = tris.reshape(-1, 3).mean(axis=0)
    a, b, d = tris[:, 0] - c, tris[:, 1] - c, tris[:, 2] - c
    return float(np.einsum("ij,ij->i", a, np.cross(b, d)).sum() / 6.0)


def icosphere(radius, subdivisions):
    t = (1.0 + math.sqrt(5.0)) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = np.array(v, dtype=np.float64)
    v /= np.linalg.norm(v, axis=1)[:, None]
    f = np.array(f, dtype=np.int64)
    for _ in range(subdivisions):
        # one midpoint per edge, shared by the two faces on it
        e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        key = np.minimum(e[:, 0], e[:, 1]) * len(v) + np.maximum(e[:, 0], e[:, 1])
        uniq, inv = np.unique(key, return_inverse=True)
        a, b = uniq // len(v), uniq % len(v)
        mid = v[a] + v[b]
        mid /= np.linalg.norm(mid, axis=1)[:, None]
        m = inv.reshape(3, -1) + len(v)
        m01, m12, m20 = m[0], m[1], m[2]
        v = np.concatenate([v, mid])
        f = np.concatenate([np.stack([f[:, 0], m01, m20], 1), np.stack([f[:, 1], m12, m01], 1),
                            np.stack([f[:, 2], m20, m12], 1), np.stack([m01, m12, m20], 1)])
    return (radius * v)[f]


def torus(R, r, segments):
    nu, nv = segments, max(3, segments // 2)
    u = 2 * math.pi * np.arange(nu) / nu
    w = 2 * math.pi * np.arange(nv) / nv
    U, W = np.meshgrid(u, w, indexing="ij")
    p = np.stack([(R + r * np.cos(W)) * np.cos(U), (R + r * np.cos(W)) * np.sin(U),
                  r * np.sin(W)], -1)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    i1, j1 = (i + 1) % nu, (j + 1) % nv
    a, b, c, d = p[i, j], p[i1, j], p[i1, j1], p[i, j1]
    t = np.concatenate([np.stack([a, b, c], 2).reshape(-1, 3, 3),
                        np.stack([a, c, d], 2).reshape(-1, 3, 3)])
    return t


def box(lo, hi):
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    corner = np.array([[lo[0] if i & 1 == 0 else hi[0], lo[1] if i & 2 == 0 else hi[1],
                        lo[2] if i & 4 == 0 else hi[2]] for i in range(8)])
    f = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4), (2, 6, 7), (2, 7, 3),
         (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    return corner[np.array(f)]


def wigley(L, B, T, nx, nz):
    """Both half-hulls (y >= 0 and its mirror) and the deck z = 0. The hull's stem and stern
    (x = +-L/2) and keel (z = -T) have y = 0: the two half-hulls meet there, sharing vertices."""
    x = np.linspace(-L / 2, L / 2, nx + 1)
    z = np.linspace(-T, 0.0, nz + 1)
    X, Z = np.meshgrid(x, z, indexing="ij")
    Y = B / 2 * (1 - (2 * X / L) ** 2) * (1 - (Z / T) ** 2)
    Y[0, :] = Y[-1, :] = 0.0  # exactly: the halves share these vertices
    Y[:, 0] = 0.0
    P = np.stack([X, Y, Z], -1)
    Q = P * np.array([1.0, -1.0, 1.0])
    Q[..., 1] = np.where(Y == 0.0, 0.0, Q[..., 1])  # +0, so that welding is exact
    i, j = np.meshgrid(np.arange(nx), np.arange(nz), indexing="ij")
    tris = []
    for S, out in ((P, True), (Q, False)):
        a, b, c, d = S[i, j], S[i + 1, j], S[i + 1, j + 1], S[i, j + 1]
        t1, t2 = np.stack([a, c, b], 2), np.stack([a, d, c], 2)
        if not out:
            t1, t2 = np.stack([a, b, c], 2), np.stack([a, c, d], 2)
        for t in (t1, t2):
            t = t.reshape(-1, 3, 3)
            # the quads at stem, stern and keel have corners on y = 0 in both halves: a triangle
            # of zero area goes, and one wholly on y = 0 (at the corners keel-stem and
            # keel-stern) too, since its mirror image is the same triangle turned over
            keep = np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1) > 0
            keep &= ~np.all(t[:, :, 1] == 0.0, axis=1)
            tris.append(t[keep])
    # the deck z = 0: strips between the two halves' top edges (normal +z)
    top, bot = P[:, -1], Q[:, -1]
    for k in range(nx):
        a, b, c, d = bot[k], bot[k + 1], top[k + 1], top[k]
        for t in ((a, b, c), (a, c, d)):
            t = np.array(t)
            if np.linalg.norm(np.cross(t[1] - t[0], t[2] - t[0])) > 0:
                tris.append(t[None])
    t = np.concatenate(tris)
    if volume(t) < 0:  # orientation of the hull quads chosen above; make sure
        t = t[:, [0, 2, 1]]
    return t


def pier(length, width, height, segments):
    """A column whose section is a rectangle of (length - width) x width with a half disc at
    each end, from z = 0 to height; the section's centre at x = y = 0."""
    r, half = width / 2, (length - width) / 2
    ring = []
    for end, sx in ((half, 1.0), (-half, -1.0)):  # the nose at +x, then the one at -x
        for k in range(segments + 1):
            a = -math.pi / 2 + math.pi * k / segments
            ring.append((end + sx * r * math.cos(a), sx * r * math.sin(a)))
    ring = np.array(ring)  # counter-clockwise seen from +z
    n = len(ring)
    tris = []
    for k in range(n):
        a, b = ring[k], ring[(k + 1) % n]
        p0, p1 = [a[0], a[1], 0.0], [b[0], b[1], 0.0]
        q0, q1 = [a[0], a[1], height], [b[0], b[1], height]
        tris += [(p0, p1, q1), (p0, q1, q0)]  # the side, outward
        if 0 < k < n - 1:  # fans from vertex 0: the top (+z) and the bottom (-z)
            c = ring[0]
            tris.append(([c[0], c[1], height], q0, q1))
            tris.append(([c[0], c[1], 0.0], p1, p0))
    t = np.array(tris, dtype=float)
    if volume(t) < 0:
        t = t[:, [0, 2, 1]]
    return t


def quad_box(lo, hi, skip_top=False, inward=False):
    """A box's faces as triangles (outward, or turned inward), with or without its top."""
    t = box(lo, hi)
    if skip_top:
        t = t[~np.all(np.isclose(t[:, :, 2], hi[2]), axis=1)]
    return t[:, [0, 2, 1]] if inward else t


def tank_cup(lo, hi, w):
    """The walls of an open tank as one closed solid: the box grown by w (but at the top) less
    the tank's inside, the rim at the top joining the two."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    olo, ohi = lo - w, hi + w
    olo[2], ohi[2] = lo[2] - w, hi[2]
    tris = [quad_box(olo, ohi, skip_top=True), quad_box(lo, hi, skip_top=True, inward=True)]
    z = hi[2]
    o = [(olo[0], olo[1]), (ohi[0], olo[1]), (ohi[0], ohi[1]), (olo[0], ohi[1])]
    i = [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])]
    rim = []
    for k in range(4):  # the rim, facing up: outer edge k, inner edge k
        a, b = o[k], o[(k + 1) % 4]
        c, d = i[(k + 1) % 4], i[k]
        P = [np.array([p[0], p[1], z]) for p in (a, b, c, d)]
        rim += [(P[0], P[1], P[2]), (P[0], P[2], P[3])]
    rim = np.array(rim)
    n = np.cross(rim[:, 1] - rim[:, 0], rim[:, 2] - rim[:, 0])
    rim[n[:, 2] < 0] = rim[n[:, 2] < 0][:, [0, 2, 1]]
    return np.concatenate(tris + [rim])


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outdir")
    ap.add_argument("--only", nargs="+", choices=SHAPES, default=list(SHAPES[:-1]))
    ap.add_argument("--check", action="store_true", help="print triangles and volume of each file")
    ap.add_argument("--sphere-radius", type=float, default=1.0)
    ap.add_argument("--sphere-subdivisions", type=int, default=3)
    ap.add_argument("--triangles", type=int, help="sphere: at least this many triangles")
    ap.add_argument("--torus-R", type=float, default=1.0)
    ap.add_argument("--torus-r", type=float, default=0.25)
    ap.add_argument("--torus-segments", type=int, default=64)
    ap.add_argument("--box-min", type=float, nargs=3, default=[0.0, 0.0, 0.0])
    ap.add_argument("--box-max", type=float, nargs=3, default=[1.0, 1.0, 1.0])
    ap.add_argument("--wigley-L", type=float, default=2.5)
    ap.add_argument("--wigley-B", type=float, default=0.25)
    ap.add_argument("--wigley-T", type=float, default=0.15)
    ap.add_argument("--wigley-segments", type=int, default=80, help="along the length (depth: 1/4)")
    ap.add_argument("--pier-length", type=float, default=0.2)
    ap.add_argument("--pier-width", type=float, default=0.06)
    ap.add_argument("--pier-height", type=float, default=0.5)
    ap.add_argument("--pier-segments", type=int, default=16)
    ap.add_argument("--test2-case", default=os.path.join(os.path.dirname(__file__), "..", "cases",
                                                         "dambreak3d.json"))
    ap.add_argument("--test2-dx", type=float, help="the spacing (default: the case's dx)")
    a = ap.parse_args(argv)
    os.makedirs(a.outdir, exist_ok=True)
    for name in a.only:
        if name == "sphere":
            k = a.sphere_subdivisions
            if a.triangles:
                k = 0
                while 20 * 4**k < a.triangles:
                    k += 1
            t = icosphere(a.sphere_radius, k)
            exact = 4.0 / 3.0 * math.pi * a.sphere_radius**3
        elif name == "torus":
            t = torus(a.torus_R, a.torus_r, a.torus_segments)
            exact = 2 * math.pi**2 * a.torus_R * a.torus_r**2
        elif name == "box":
            t = box(a.box_min, a.box_max)
            exact = float(np.prod(np.subtract(a.box_max, a.box_min)))
        elif name == "test2":
            import json
            c = json.load(open(a.test2_case))
            dx = a.test2_dx or c["dx"]
            b = c["boundary"]
            w = b.get("layers", 3) * dx
            for fname, t, exact in (
                    ("tank", tank_cup(b["tank"]["min"], b["tank"]["max"], w), None),
                    ("box", box(b["obstacles"][0]["box"]["min"], b["obstacles"][0]["box"]["max"]),
                     None)):
                path = os.path.join(a.outdir, fname + ".stl")
                write_stl(path, t, fname)
                if a.check:
                    r = read_stl(path)
                    print(f"{fname}.stl: {len(r)} triangles, volume {volume(r):.6g}")
            continue
        elif name == "pier":
            t = pier(a.pier_length, a.pier_width, a.pier_height, a.pier_segments)
            w = a.pier_width
            exact = ((a.pier_length - w) * w + math.pi * w * w / 4) * a.pier_height
        else:
            L, B, T = a.wigley_L, a.wigley_B, a.wigley_T
            t = wigley(L, B, T, a.wigley_segments, max(2, a.wigley_segments // 4))
            exact = 4.0 / 9.0 * L * B * T  # 2 * int B/2 (1-(2x/L)^2) dx * int (1-(z/T)^2) dz
        path = os.path.join(a.outdir, name + ".stl")
        write_stl(path, t, name)
        if a.check:
            r = read_stl(path)
            vol = volume(r)
            print(f"{name}.stl: {len(r)} triangles, volume {vol:.6g} (exact {exact:.6g}, "
                  f"{100 * (vol - exact) / exact:+.3f}%)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
