#!/usr/bin/env python3
"""Generates vaw's bundled meshes, demo scenes and the sleeve's property file.

Dev-time tool (Python 3 standard library only); its outputs are committed, so a build never runs it.

    python3 resources/tools/make_meshes.py            # writes resources/{meshes,scenes,properties}
    python3 resources/tools/make_meshes.py --check    # regenerates in memory and only validates

Every mesh is a closed, outward-oriented (counter-clockwise seen from outside), manifold triangle mesh
with shared vertices, in millimetres. Before anything is kept, each mesh is checked as built and again
as read back from the file written (every undirected edge used by exactly two triangles, every directed
edge once, no degenerate triangles, no repeated vertex positions, positive signed volume); the script
exits non-zero on any failure. Scenes are checked against docs/scene-format.md (allowed keys, files
present, parts above the table, constraints holding at final poses).

Formats are mixed on purpose so that every importer path is exercised: binary STL, Wavefront OBJ, binary
little-endian PLY, glTF 2.0 with an embedded base64 buffer (.gltf) and binary glTF (.glb).
"""

import base64
import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
RES = os.path.dirname(HERE)
MESH_DIR = os.path.join(RES, "meshes")
SCENE_DIR = os.path.join(RES, "scenes")
PROP_DIR = os.path.join(RES, "properties")

TAU = 2.0 * math.pi


class BuildError(Exception):
    pass


# --------------------------------------------------------------------------------------------------
# Small vector helpers
# --------------------------------------------------------------------------------------------------

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def mat_vec(m, v):
    return tuple(m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2] for r in range(3))


def mat_mul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(3)) for c in range(3)] for r in range(3)]


def axis_angle(axis, degrees):
    """Rotation matrix for a rotation by `degrees` about `axis` (right-hand rule)."""
    n = norm(axis)
    x, y, z = (axis[0] / n, axis[1] / n, axis[2] / n)
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    # Snap the quarter turns so that rotated tessellations coincide exactly where they should.
    c = round(c) if abs(c - round(c)) < 1e-15 else c
    s = round(s) if abs(s - round(s)) < 1e-15 else s
    t = 1.0 - c
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]


IDENTITY = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


# --------------------------------------------------------------------------------------------------
# Mesh building
# --------------------------------------------------------------------------------------------------

class Mesh:
    def __init__(self, name):
        self.name = name
        self.v = []  # (x, y, z) in mm
        self.t = []  # (a, b, c), counter-clockwise seen from outside

    def vert(self, x, y, z):
        self.v.append((float(x), float(y), float(z)))
        return len(self.v) - 1

    def tri(self, a, b, c):
        self.t.append((a, b, c))

    def quad(self, a, b, c, d):
        self.t.append((a, b, c))
        self.t.append((a, c, d))

    def append(self, other, rot=IDENTITY, pos=(0.0, 0.0, 0.0)):
        off = len(self.v)
        for p in other.v:
            self.v.append(add(mat_vec(rot, p), pos))
        for a, b, c in other.t:
            self.t.append((a + off, b + off, c + off))

    def transformed(self, rot=IDENTITY, pos=(0.0, 0.0, 0.0)):
        m = Mesh(self.name)
        m.append(self, rot, pos)
        return m

    def bounds(self):
        lo = [min(p[k] for p in self.v) for k in range(3)]
        hi = [max(p[k] for p in self.v) for k in range(3)]
        return lo, hi


def ring(mesh, radius, z, n, centre=(0.0, 0.0), phase=0.0):
    """n vertices on a circle in the plane at height z, counter-clockwise seen from +z, the first
    at angle `phase` (the convention of vaw's primitives: vertex i at angle 2*pi*i/n)."""
    return [mesh.vert(centre[0] + radius * math.cos(phase + TAU * i / n),
                      centre[1] + radius * math.sin(phase + TAU * i / n), z) for i in range(n)]


def lathe(mesh, profile, n, closed=False, existing=None, phase=0.0):
    """Surface of revolution about z. `profile` lists (r, z) points; r == 0 is a point on the axis.
    The profile must run counter-clockwise in the (r, z) half-plane (r to the right, z up): e.g. from
    the bottom of the axis outwards, up the outside and back to the axis at the top. Then the surface
    faces outwards. `closed` joins the last point to the first (a ring-shaped solid such as a tube).
    `existing` maps a profile index to an already built ring (list of n vertex ids) to reuse."""
    existing = existing or {}
    rings = []
    for k, (r, z) in enumerate(profile):
        if k in existing:
            rings.append(existing[k])
        elif r == 0.0:
            rings.append(mesh.vert(0.0, 0.0, z))
        else:
            rings.append(ring(mesh, r, z, n, phase=phase))
    pairs = list(zip(rings[:-1], rings[1:]))
    if closed:
        pairs.append((rings[-1], rings[0]))
    for lo, hi in pairs:
        lo_axis, hi_axis = isinstance(lo, int), isinstance(hi, int)
        if lo_axis and hi_axis:
            raise BuildError("lathe: two consecutive axis points")
        for i in range(n):
            j = (i + 1) % n
            if lo_axis:
                mesh.tri(lo, hi[j], hi[i])
            elif hi_axis:
                mesh.tri(lo[i], lo[j], hi)
            else:
                mesh.quad(lo[i], lo[j], hi[j], hi[i])
    return rings


def area2(p, a, b, c):
    """Twice the signed area of triangle (a, b, c) of 2-D points p[...]."""
    pa, pb, pc = p[a], p[b], p[c]
    return (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0])


def zip_loops(pts, outer, inner):
    """Triangulates the region between an outer loop and an inner loop (a hole) around `centre`.
    Both loops are lists of indices into the 2-D points `pts`, counter-clockwise around `centre`.
    Greedy merge: start at the outer loop's first vertex and the inner vertex nearest to it, then at
    each step add the counter-clockwise triangle whose new diagonal is shorter, except that an outer
    vertex keeps taking inner edges while the next outer vertex could not see them. A triangulated annulus
    whose triangles all turn counter-clockwise covers the region exactly once (its boundary winds once
    around every point of the region and never around the hole), so checking every triangle's sign
    is a complete check. Raises when the greedy merge gets stuck."""
    o = list(outer)
    start = min(range(len(inner)), key=lambda k: (pts[inner[k]][0] - pts[o[0]][0]) ** 2 +
                (pts[inner[k]][1] - pts[o[0]][1]) ** 2)
    h = list(inner[start:]) + list(inner[:start])
    o.append(o[0])
    h.append(h[0])
    n, m = len(o) - 1, len(h) - 1

    def d2(a, b):
        return (pts[a][0] - pts[b][0]) ** 2 + (pts[a][1] - pts[b][1]) ** 2

    i = j = 0
    tris = []
    while i < n or j < m:
        ta = (o[i], o[i + 1], h[j]) if i < n else None
        tb = (o[i], h[j + 1], h[j]) if j < m else None
        ok_a = ta is not None and area2(pts, *ta) > 0.0
        ok_b = tb is not None and area2(pts, *tb) > 0.0
        # o[i] must take the inner edge h[j] -> h[j+1] now if o[i+1] would not see it.
        must_b = ok_b and (i == n or area2(pts, o[i + 1], h[j + 1], h[j]) <= 0.0)
        if ok_a and not must_b and (not ok_b or d2(o[i + 1], h[j]) <= d2(o[i], h[j + 1])):
            tris.append(ta)
            i += 1
        elif ok_b:
            tris.append(tb)
            j += 1
        else:
            raise BuildError("zip_loops: stuck (the loops are too far from star-shaped)")
    return tris


def extrude(name, pts, tris, loops, z0, z1):
    """Prism of the planar region given by 2-D points `pts`, its counter-clockwise triangulation
    `tris` and its boundary `loops` (the region on the left: outer loop counter-clockwise, holes
    clockwise), between heights z0 < z1."""
    m = Mesh(name)
    lo = [m.vert(x, y, z0) for x, y in pts]
    hi = [m.vert(x, y, z1) for x, y in pts]
    for a, b, c in tris:
        m.tri(hi[a], hi[b], hi[c])
        m.tri(lo[a], lo[c], lo[b])
    for loop in loops:
        for k in range(len(loop)):
            a, b = loop[k], loop[(k + 1) % len(loop)]
            m.quad(lo[a], lo[b], hi[b], hi[a])
    return m


def circle_pts(pts, radius, n, centre=(0.0, 0.0), phase=0.0):
    first = len(pts)
    for i in range(n):
        pts.append((centre[0] + radius * math.cos(phase + TAU * i / n),
                    centre[1] + radius * math.sin(phase + TAU * i / n)))
    return list(range(first, first + n))


def rect_pts(pts, x0, y0, x1, y1):
    first = len(pts)
    pts += [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return list(range(first, first + 4))


def hex_pts(pts, across_flats):
    first = len(pts)
    rc = across_flats / math.sqrt(3.0)
    for i in range(6):
        a = TAU * i / 6 + math.pi / 6  # flats parallel to x
        pts.append((rc * math.cos(a), rc * math.sin(a)))
    return list(range(first, first + 6))


def plate_with_hole(name, outer_fn, hole_r, hole_n, thickness, hole_centre=(0.0, 0.0)):
    pts = []
    outer = outer_fn(pts)
    hole = circle_pts(pts, hole_r, hole_n, hole_centre)
    tris = zip_loops(pts, outer, hole)
    return extrude(name, pts, tris, [outer, list(reversed(hole))], -thickness / 2, thickness / 2)


def box_mesh(name, sx, sy, sz, centre=(0.0, 0.0, 0.0)):
    pts = []
    outer = rect_pts(pts, -sx / 2, -sy / 2, sx / 2, sy / 2)
    m = extrude(name, pts, [(0, 1, 2), (0, 2, 3)], [outer], -sz / 2, sz / 2)
    return m.transformed(IDENTITY, centre)


# --------------------------------------------------------------------------------------------------
# Gears
# --------------------------------------------------------------------------------------------------

def inv(a):
    return math.tan(a) - a


def gear_region(teeth, tooth_radii, half_width, tip_pts, gap_pts, bore_r, bore_n, bore_centre):
    """2-D gear face: `teeth` teeth, each with flanks sampled at the radii `tooth_radii` (root to tip),
    the tooth's angular half width at radius r given by half_width(r), `tip_pts` extra points on the tip
    arc and `gap_pts` on the root arc between teeth, and a circular bore (radius bore_r, bore_n
    segments, vertex 0 at angle 0 around bore_centre). The gear's centre is the 2-D origin.
    Returns (pts, tris, loops)."""
    pts = []
    outline, root = [], []
    ladder = []
    rf, ra = tooth_radii[0], tooth_radii[-1]
    pitch = TAU / teeth
    for k in range(teeth):
        c = pitch * k
        right = []
        for r in tooth_radii:
            a = c - half_width(r)
            right.append(len(pts))
            pts.append((r * math.cos(a), r * math.sin(a)))
        tip = []
        w = half_width(ra)
        for s in range(1, tip_pts + 1):
            a = c - w + 2 * w * s / (tip_pts + 1)
            tip.append(len(pts))
            pts.append((ra * math.cos(a), ra * math.sin(a)))
        left = []
        for r in tooth_radii:
            a = c + half_width(r)
            left.append(len(pts))
            pts.append((r * math.cos(a), r * math.sin(a)))
        gap = []
        a0, a1 = c + half_width(rf), c + pitch - half_width(rf)
        if a1 <= a0:
            raise BuildError("gear: teeth overlap at the root")
        for s in range(1, gap_pts + 1):
            a = a0 + (a1 - a0) * s / (gap_pts + 1)
            gap.append(len(pts))
            pts.append((rf * math.cos(a), rf * math.sin(a)))
        outline += right + tip + list(reversed(left)) + gap
        root += [right[0], left[0]] + gap
        ladder.append((right, tip, left))
    tris = []
    for right, tip, left in ladder:
        for j in range(len(right) - 1):
            tris.append((right[j], right[j + 1], left[j + 1]))
            tris.append((right[j], left[j + 1], left[j]))
        fan = [right[-1]] + tip + [left[-1]]
        for s in range(1, len(fan) - 1):
            tris.append((fan[0], fan[s], fan[s + 1]))
    for t in tris:
        if area2(pts, *t) <= 0.0:
            raise BuildError("gear: a tooth triangle is not counter-clockwise")
    bore = circle_pts(pts, bore_r, bore_n, bore_centre)
    tris += zip_loops(pts, root, bore)
    return pts, tris, [outline, list(reversed(bore))]


def involute_gear(name, module, teeth, face_width, bore_r, bore_n, flank_pts=24, tip_pts=6, gap_pts=8,
                  pressure_deg=20.0):
    """Spur gear with involute flanks (standard addendum m, dedendum 1.25 m, no backlash), centred
    bore, axis z, centred on the origin."""
    rp = module * teeth / 2.0
    rb = rp * math.cos(math.radians(pressure_deg))
    ra = rp + module
    rf = rp - 1.25 * module
    w_pitch = math.pi / (2 * teeth) + inv(math.radians(pressure_deg))

    def half_width(r):
        return w_pitch - inv(math.acos(rb / r)) if r > rb else w_pitch

    if rf < rb:
        radii = [rf] + [rb + (ra - rb) * (s / (flank_pts - 1)) for s in range(flank_pts)]
    else:
        radii = [rf + (ra - rf) * (s / flank_pts) for s in range(flank_pts + 1)]
    if half_width(ra) <= 0:
        raise BuildError(f"{name}: pointed teeth")
    pts, tris, loops = gear_region(teeth, radii, half_width, tip_pts, gap_pts, bore_r, bore_n, (0.0, 0.0))
    m = extrude(name, pts, tris, loops, -face_width / 2, face_width / 2)
    m.outer_radius = ra
    return m


# --------------------------------------------------------------------------------------------------
# Checks and mass properties
# --------------------------------------------------------------------------------------------------

def check_mesh(m, label=None):
    """Raises BuildError unless m is a closed, consistently and outward oriented manifold with shared
    vertices and no degenerate triangles. Returns the volume (mm^3)."""
    label = label or m.name
    nv = len(m.v)
    problems = []
    if len(set(m.v)) != nv:
        problems.append(f"{nv - len(set(m.v))} repeated vertex positions")
    lo, hi = m.bounds()
    diag = norm(sub(hi, lo))
    min_area = 1e-9 * diag * diag
    directed = {}
    undirected = {}
    degenerate = 0
    for a, b, c in m.t:
        if not (0 <= a < nv and 0 <= b < nv and 0 <= c < nv):
            raise BuildError(f"{label}: index out of range")
        if a == b or b == c or a == c or 0.5 * norm(cross(sub(m.v[b], m.v[a]), sub(m.v[c], m.v[a]))) <= min_area:
            degenerate += 1
        for e in ((a, b), (b, c), (c, a)):
            directed[e] = directed.get(e, 0) + 1
            k = (min(e), max(e))
            undirected[k] = undirected.get(k, 0) + 1
    if degenerate:
        problems.append(f"{degenerate} degenerate triangles")
    bad_u = sum(1 for n in undirected.values() if n != 2)
    if bad_u:
        problems.append(f"{bad_u} edges not used by exactly two triangles")
    bad_d = sum(1 for n in directed.values() if n != 1)
    if bad_d:
        problems.append(f"{bad_d} directed edges used more than once")
    used = set(i for t in m.t for i in t)
    if len(used) != nv:
        problems.append(f"{nv - len(used)} unused vertices")
    vol = mass_props(m)["volume"]
    if not vol > 0:
        problems.append(f"signed volume {vol} is not positive (inside out?)")
    # Euler characteristic: a closed orientable surface of genus g has V - E + F = 2 - 2g.
    chi = nv - len(undirected) + len(m.t)
    if chi % 2 or chi > 2:
        problems.append(f"Euler characteristic {chi} impossible for a closed surface")
    if problems:
        raise BuildError(f"{label}: " + "; ".join(problems))
    return vol


def mass_props(m, density=1.0):
    """Volume, centroid and inertia tensor about the centroid (divergence theorem, tetrahedra from a
    reference point inside the bounds). Units: mm^3, mm, density * mm^5."""
    lo, hi = m.bounds()
    ref = tuple((lo[k] + hi[k]) / 2 for k in range(3))
    vol = 0.0
    first = [0.0, 0.0, 0.0]
    cov = [[0.0] * 3 for _ in range(3)]
    area = 0.0
    for a, b, c in m.t:
        pa, pb, pc = sub(m.v[a], ref), sub(m.v[b], ref), sub(m.v[c], ref)
        d = dot(pa, cross(pb, pc))
        area += 0.5 * norm(cross(sub(pb, pa), sub(pc, pa)))
        vol += d / 6.0
        for k in range(3):
            first[k] += d / 24.0 * (pa[k] + pb[k] + pc[k])
        # Covariance of the tetrahedron (0, pa, pb, pc): d/120 * (sum_i x_i x_i^T + s s^T), s = pa+pb+pc
        s = (pa[0] + pb[0] + pc[0], pa[1] + pb[1] + pc[1], pa[2] + pb[2] + pc[2])
        for r in range(3):
            for q in range(3):
                cov[r][q] += d / 120.0 * (pa[r] * pa[q] + pb[r] * pb[q] + pc[r] * pc[q] + s[r] * s[q])
    cen = [first[k] / vol for k in range(3)] if vol else [0.0, 0.0, 0.0]
    cov_c = [[cov[r][q] - vol * cen[r] * cen[q] for q in range(3)] for r in range(3)]
    tr = cov_c[0][0] + cov_c[1][1] + cov_c[2][2]
    inertia = [[density * ((tr if r == q else 0.0) - cov_c[r][q]) for q in range(3)] for r in range(3)]
    return {"volume": vol, "centroid": [cen[k] + ref[k] for k in range(3)], "inertia": inertia,
            "area": area, "mass": density * vol}


# --------------------------------------------------------------------------------------------------
# Writers and readers (readers re-check every file as written)
# --------------------------------------------------------------------------------------------------

def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def write_stl(m, path):
    out = [struct.pack("<80sI", f"vaw {m.name} mm".encode().ljust(80, b" "), len(m.t))]
    for a, b, c in m.t:
        pa, pb, pc = m.v[a], m.v[b], m.v[c]
        n = cross(sub(pb, pa), sub(pc, pa))
        ln = norm(n)
        n = (n[0] / ln, n[1] / ln, n[2] / ln)
        out.append(struct.pack("<12fH", *n, *pa, *pb, *pc, 0))
    with open(path, "wb") as f:
        f.write(b"".join(out))


def read_stl(path):
    data = open(path, "rb").read()
    (count,) = struct.unpack_from("<I", data, 80)
    if len(data) != 84 + 50 * count:
        raise BuildError(f"{path}: binary STL size does not match its triangle count")
    m = Mesh(os.path.basename(path))
    index = {}
    for k in range(count):
        vals = struct.unpack_from("<12f", data, 84 + 50 * k)
        ids = []
        for q in range(3):
            p = vals[3 + 3 * q: 6 + 3 * q]
            if p not in index:
                index[p] = len(m.v)
                m.v.append(p)
            ids.append(index[p])
        m.t.append(tuple(ids))
    return m


def write_obj(m, path):
    lines = [f"# vaw: {m.name}, millimetres, {len(m.v)} vertices, {len(m.t)} triangles",
             f"o {m.name}"]
    lines += ["v %.6f %.6f %.6f" % p for p in m.v]
    lines += ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in m.t]
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def read_obj(path):
    m = Mesh(os.path.basename(path))
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            m.v.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == "f":
            if len(w) != 4:
                raise BuildError(f"{path}: non-triangle face")
            m.t.append(tuple(int(x.split("/")[0]) - 1 for x in w[1:]))
    return m


def write_ply(m, path):
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"comment vaw {m.name}, millimetres\n"
              f"element vertex {len(m.v)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              f"element face {len(m.t)}\n"
              "property list uchar int vertex_indices\nend_header\n").encode("ascii")
    body = [struct.pack("<3f", *p) for p in m.v]
    body += [struct.pack("<B3i", 3, *t) for t in m.t]
    with open(path, "wb") as f:
        f.write(header + b"".join(body))


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").split("\n")
    nv = nf = None
    for line in header:
        w = line.split()
        if w[:2] == ["element", "vertex"]:
            nv = int(w[2])
        if w[:2] == ["element", "face"]:
            nf = int(w[2])
    if "format binary_little_endian 1.0" not in header:
        raise BuildError(f"{path}: not binary little-endian PLY")
    m = Mesh(os.path.basename(path))
    off = end
    for _ in range(nv):
        m.v.append(struct.unpack_from("<3f", data, off))
        off += 12
    for _ in range(nf):
        cnt, a, b, c = struct.unpack_from("<B3i", data, off)
        if cnt != 3:
            raise BuildError(f"{path}: non-triangle face")
        m.t.append((a, b, c))
        off += 13
    if off != len(data):
        raise BuildError(f"{path}: trailing bytes")
    return m


def gltf_document(m, bin_uri):
    """glTF 2.0 JSON and binary buffer (float32 positions, uint32 indices) for one node/mesh."""
    pos = b"".join(struct.pack("<3f", *p) for p in m.v)
    idx = b"".join(struct.pack("<3I", *t) for t in m.t)
    buf = pos + idx
    lo = [min(f32(p[k]) for p in m.v) for k in range(3)]
    hi = [max(f32(p[k]) for p in m.v) for k in range(3)]
    buffer = {"byteLength": len(buf)}
    if bin_uri is not None:
        buffer["uri"] = bin_uri
    doc = {
        "asset": {"version": "2.0", "generator": "vaw resources/tools/make_meshes.py"},
        "extras": {"units": "millimetres"},
        "scene": 0,
        "scenes": [{"name": m.name, "nodes": [0]}],
        "nodes": [{"name": m.name, "mesh": 0}],
        "meshes": [{"name": m.name, "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "buffers": [buffer],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(m.v), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": 3 * len(m.t), "type": "SCALAR"},
        ],
    }
    return doc, buf


def write_gltf(m, path):
    # Build once to know the buffer, then embed it as a data URI.
    _, buf = gltf_document(m, None)
    uri = "data:application/octet-stream;base64," + base64.b64encode(buf).decode("ascii")
    doc, _ = gltf_document(m, uri)
    with open(path, "w", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def write_glb(m, path):
    doc, buf = gltf_document(m, None)
    js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    js += b" " * (-len(js) % 4)
    buf += b"\0" * (-len(buf) % 4)
    total = 12 + 8 + len(js) + 8 + len(buf)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(js), b"JSON") + js)
        f.write(struct.pack("<I4s", len(buf), b"BIN\0") + buf)


def read_gltf(path):
    raw = open(path, "rb").read()
    if raw[:4] == b"glTF":
        magic, version, total = struct.unpack_from("<4sII", raw, 0)
        if version != 2 or total != len(raw):
            raise BuildError(f"{path}: bad GLB header")
        jl, jt = struct.unpack_from("<I4s", raw, 12)
        doc = json.loads(raw[20:20 + jl])
        bl, bt = struct.unpack_from("<I4s", raw, 20 + jl)
        if jt != b"JSON" or bt != b"BIN\0":
            raise BuildError(f"{path}: bad GLB chunks")
        buf = raw[28 + jl: 28 + jl + bl]
    else:
        doc = json.loads(raw)
        uri = doc["buffers"][0]["uri"]
        prefix = "data:application/octet-stream;base64,"
        if not uri.startswith(prefix):
            raise BuildError(f"{path}: buffer is not an embedded data URI")
        buf = base64.b64decode(uri[len(prefix):])
    if len(buf) < doc["buffers"][0]["byteLength"]:
        raise BuildError(f"{path}: buffer shorter than declared")
    prim = doc["meshes"][0]["primitives"][0]
    pa = doc["accessors"][prim["attributes"]["POSITION"]]
    ia = doc["accessors"][prim["indices"]]
    pv = doc["bufferViews"][pa["bufferView"]]
    iv = doc["bufferViews"][ia["bufferView"]]
    m = Mesh(os.path.basename(path))
    for k in range(pa["count"]):
        m.v.append(struct.unpack_from("<3f", buf, pv["byteOffset"] + 12 * k))
    for k in range(0, ia["count"], 3):
        m.t.append(struct.unpack_from("<3I", buf, iv["byteOffset"] + 4 * k))
    for k in range(3):
        if abs(min(p[k] for p in m.v) - pa["min"][k]) > 0 or abs(max(p[k] for p in m.v) - pa["max"][k]) > 0:
            raise BuildError(f"{path}: accessor min/max do not match the data")
    return m


WRITERS = {".stl": (write_stl, read_stl), ".obj": (write_obj, read_obj), ".ply": (write_ply, read_ply),
           ".gltf": (write_gltf, read_gltf), ".glb": (write_glb, read_gltf)}


# --------------------------------------------------------------------------------------------------
# The meshes
# --------------------------------------------------------------------------------------------------

SHAFT_R = 15.0       # sleeve-on-shaft: shaft radius == sleeve bore radius (equal-diameter fit)
SLEEVE_R = 25.0
SLEEVE_H = 40.0
SLEEVE_N = 64        # same count and phase as the shaft, so the bore and the shaft coincide
BLOCK = (200.0, 150.0, 40.0)
SHAFT_TOP = 160.0    # shaft rises 120 mm above the block's top face (z = 40)


def make_shaft_base():
    """Steel block 200 x 150 x 40 mm, frame at the centre of its bottom face, with a shaft (r 15 mm,
    120 mm tall, 1 mm lead-in chamfer) rising from the centre of its top face: one closed mesh."""
    m = Mesh("shaft-base")
    sx, sy, sz = BLOCK
    corners_lo = [m.vert(x, y, 0.0) for x, y in ((-sx / 2, -sy / 2), (sx / 2, -sy / 2), (sx / 2, sy / 2), (-sx / 2, sy / 2))]
    corners_hi = [m.vert(x, y, sz) for x, y in ((-sx / 2, -sy / 2), (sx / 2, -sy / 2), (sx / 2, sy / 2), (-sx / 2, sy / 2))]
    m.tri(corners_lo[0], corners_lo[2], corners_lo[1])
    m.tri(corners_lo[0], corners_lo[3], corners_lo[2])
    for k in range(4):
        a, b = k, (k + 1) % 4
        m.quad(corners_lo[a], corners_lo[b], corners_hi[b], corners_hi[a])
    foot = ring(m, SHAFT_R, sz, SLEEVE_N)
    # Top face: the rectangle around the circle where the shaft emerges (no internal faces).
    pts = [m.v[i][:2] for i in corners_hi] + [m.v[i][:2] for i in foot]
    ids = corners_hi + foot
    local = zip_loops(pts, [0, 1, 2, 3], list(range(4, 4 + SLEEVE_N)))
    for a, b, c in local:
        m.tri(ids[a], ids[b], ids[c])
    lathe(m, [(SHAFT_R, sz), (SHAFT_R, SHAFT_TOP - 1.0), (SHAFT_R - 1.0, SHAFT_TOP), (0.0, SHAFT_TOP)],
          SLEEVE_N, existing={0: foot})
    return m


def make_sleeve():
    """Brass tube, bore r 15 mm, outside r 25 mm, 40 mm long; frame at the centre of its bottom face,
    axis +z (so it rests on the block's top face at z = 40 in the base frame)."""
    m = Mesh("sleeve")
    lathe(m, [(SHAFT_R, 0.0), (SLEEVE_R, 0.0), (SLEEVE_R, SLEEVE_H), (SHAFT_R, SLEEVE_H)], SLEEVE_N, closed=True)
    return m


PLATE = (300.0, 200.0, 40.0)
BLOCK_PART = (60.0, 40.0, 30.0)


def make_flat_base():
    """Steel plate 300 x 200 x 40 mm, frame at the centre of its bottom face (top face at z = 40). The
    top face is split into a grid so that contacts have vertices nearby; it stays flat."""
    sx, sy, sz = PLATE
    nx, ny = 6, 4
    m = Mesh("flat-base")
    # A (nx+1) x (ny+1) grid on the top face; bottom and sides use only the boundary vertices.
    grid = [[m.vert(-sx / 2 + sx * i / nx, -sy / 2 + sy * j / ny, sz) for j in range(ny + 1)] for i in range(nx + 1)]
    for i in range(nx):
        for j in range(ny):
            m.quad(grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1])
    top_loop = ([grid[i][0] for i in range(nx)] + [grid[nx][j] for j in range(ny)] +
                [grid[i][ny] for i in range(nx, 0, -1)] + [grid[0][j] for j in range(ny, 0, -1)])
    bottom = [m.vert(m.v[k][0], m.v[k][1], 0.0) for k in top_loop]
    # Bottom face: fan triangulation of the boundary loop from the centre of the bottom face.
    c = m.vert(0.0, 0.0, 0.0)
    n = len(bottom)
    for k in range(n):
        m.tri(c, bottom[(k + 1) % n], bottom[k])
    for k in range(n):
        a, b = k, (k + 1) % n
        m.quad(bottom[a], bottom[b], top_loop[b], top_loop[a])
    return m


def make_block():
    """Aluminium block 60 x 40 x 30 mm, frame at its centre."""
    return box_mesh("block", *BLOCK_PART)


# Paper-like gear (docs/physics.md: r = 0.05 m, m ~ 0.3 kg, centre of mass 0.02 m off the axis).
GEAR_TEETH = 24
GEAR_RA = 50.0          # tip radius
GEAR_RF = 42.0          # root radius
GEAR_BORE_R = 10.0      # == the horizontal shaft's radius
GEAR_BORE_N = 64        # == the shaft primitive's default segments (same phase: vertex 0 at angle 0)
GEAR_CM_OFFSET = 20.0   # wanted distance of the centre of mass from the bore axis
GEAR_MASS = 0.300       # kg, wanted
STEEL = 7850.0


def make_demo_gear():
    """Spur gear, 24 trapezoidal teeth, tip radius 50 mm, bore r 10 mm off the gear's centre so that the
    centre of mass is 20 mm from the bore axis. Gear frame: bore axis = z axis through the origin, the
    gear's centre on +x, faces at z = +-t/2. The face width t is chosen for a 0.300 kg steel gear."""
    pitch = TAU / GEAR_TEETH
    w_root, w_tip = 0.30 * pitch, 0.15 * pitch  # half widths (rad): teeth 60 % of the pitch at the root

    def half_width(r):
        return w_root + (w_tip - w_root) * (r - GEAR_RF) / (GEAR_RA - GEAR_RF)

    def region(offset):
        # In the gear-centred frame the bore is at (-offset, 0); shift afterwards.
        return gear_region(GEAR_TEETH, [GEAR_RF, GEAR_RA], half_width, 0, 1,
                           GEAR_BORE_R, GEAR_BORE_N, (-offset, 0.0))

    def area_and_cx(pts, tris):
        a = cx = 0.0
        for t in tris:
            ar = area2(pts, *t) / 2
            a += ar
            cx += ar * (pts[t[0]][0] + pts[t[1]][0] + pts[t[2]][0]) / 3
        return a, cx / a

    # The centroid of the holed face, measured from the bore axis, is offset * A / (A - a) with A the
    # outline's area; iterate the bore offset until that is 20 mm to 1e-9 mm (a few passes).
    offset = GEAR_CM_OFFSET * 0.95
    for _ in range(30):
        pts, tris, loops = region(offset)
        area, cx = area_and_cx(pts, tris)
        dist = cx + offset  # centroid's distance from the bore centre
        if abs(dist - GEAR_CM_OFFSET) < 1e-9:
            break
        offset *= GEAR_CM_OFFSET / dist
    else:
        raise BuildError("gear: the bore offset did not converge")
    thickness = GEAR_MASS / (STEEL * area * 1e-9)
    thickness = round(thickness, 2)
    m = extrude("gear", pts, tris, loops, -thickness / 2, thickness / 2)
    m = m.transformed(IDENTITY, (offset, 0.0, 0.0))
    m.bore_offset = offset
    m.thickness = thickness
    return m


# Large gearbox ------------------------------------------------------------------------------------

HOUSING = dict(length=700.0, width=480.0, height=260.0, wall=20.0, floor=25.0)
SHAFT_Z = 140.0  # shaft axes above the housing's bottom face
SEG = 128        # segments of every round thing on the shafts (multiple of 4: see pillow_block)


def make_housing():
    """Cast-iron open gearbox housing (a tray), frame at the centre of its bottom face."""
    L, W, H, t, f = (HOUSING[k] for k in ("length", "width", "height", "wall", "floor"))
    m = Mesh("gearbox-housing")
    # Outer box minus a pocket open at the top; the rim, inner walls and pocket floor are subdivided
    # a little along x so that the base has some vertices where parts rest.
    nx = 14
    xs_o = [-L / 2 + L * i / nx for i in range(nx + 1)]
    xs_i = [-(L / 2 - t) + (L - 2 * t) * i / nx for i in range(nx + 1)]
    def loop(xs, y, z):
        front = [m.vert(x, -y, z) for x in xs]
        back = [m.vert(x, y, z) for x in reversed(xs)]
        return front + back  # counter-clockwise from +z
    bot = loop(xs_o, W / 2, 0.0)
    top_o = loop(xs_o, W / 2, H)
    top_i = loop(xs_i, W / 2 - t, H)
    floor_i = loop(xs_i, W / 2 - t, f)
    n = len(bot)
    # bottom face (normal -z): strips between the front and back rows
    for i in range(nx):
        a, b = bot[i], bot[i + 1]
        c, d = bot[n - 2 - i], bot[n - 1 - i]
        m.quad(a, d, c, b)
    # pocket floor (normal +z)
    for i in range(nx):
        a, b = floor_i[i], floor_i[i + 1]
        c, d = floor_i[n - 2 - i], floor_i[n - 1 - i]
        m.quad(a, b, c, d)
    for k in range(n):
        a, b = k, (k + 1) % n
        m.quad(bot[a], bot[b], top_o[b], top_o[a])          # outer walls
        m.quad(top_i[a], top_i[b], floor_i[b], floor_i[a])  # inner walls, facing the pocket
        m.quad(top_o[a], top_o[b], top_i[b], top_i[a])      # rim (normal +z)
    return m


def make_shaft(name, r, length):
    """Plain shaft with 1 mm chamfers, axis z, centred."""
    m = Mesh(name)
    h = length / 2
    lathe(m, [(0.0, -h), (r - 1.0, -h), (r, -h + 1.0), (r, h - 1.0), (r - 1.0, h), (0.0, h)], SEG)
    return m


def make_bearing(name, ri, ro, width):
    """Deep-groove ball bearing as one solid: rings with chamfers and recessed shields; axis z,
    centred. The bore is exactly ri and the outside exactly ro (they seat on shaft and pillow block)."""
    m = Mesh(name)
    h = width / 2
    c = 0.8
    land = (ro - ri) * 0.22           # width of the inner and outer ring faces
    rec = 0.6                          # shield recess depth
    prof = [(ri + c, -h), (ri + land, -h), (ri + land + 0.4, -h + rec), (ro - land - 0.4, -h + rec),
            (ro - land, -h), (ro - c, -h), (ro, -h + c), (ro, h - c), (ro - c, h), (ro - land, h),
            (ro - land - 0.4, h - rec), (ri + land + 0.4, h - rec), (ri + land, h), (ri + c, h),
            (ri, h - c), (ri, -h + c)]
    lathe(m, prof, SEG, closed=True)
    return m


def make_pillow_block(name, bore_r, below, above, width, thickness):
    """Pillow block with a through bore along x (radius bore_r, SEG segments). Frame at the bore centre;
    its foot is `below` under the axis. Built in (u, v, w) with the bore along w, then mapped
    (u, v, w) -> (x, y, z) = (w, u, v), a proper rotation. The bore vertices then coincide with those of
    a z-axis tube turned 90 degrees about y, because SEG is a multiple of 4."""
    pts = []
    outer = rect_pts(pts, -width / 2, -below, width / 2, above)
    hole = circle_pts(pts, bore_r, SEG)
    tris = zip_loops(pts, outer, hole)
    m = extrude(name, pts, tris, [outer, list(reversed(hole))], -thickness / 2, thickness / 2)
    perm = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    return m.transformed(perm)


BOLT = dict(across_flats=18.0, head=7.5, r=6.0, minor_r=5.1, length=40.0, thread=28.0, pitch=1.75, seg=96)


def make_bolt():
    """M12 x 40 hex bolt; the thread is modelled as axisymmetric ridges (not a helix). Frame: bearing
    face of the head at z = 0, head up to z = 7.5, shank down to z = -40."""
    b = BOLT
    m = Mesh("bolt-m12x40")
    hpts = []
    hex_pts(hpts, b["across_flats"])
    n = b["seg"]
    lo_hex = [m.vert(x, y, 0.0) for x, y in hpts]
    hi_hex = [m.vert(x, y, b["head"]) for x, y in hpts]
    c_top = m.vert(0.0, 0.0, b["head"])
    for k in range(6):
        m.tri(c_top, hi_hex[k], hi_hex[(k + 1) % 6])
        m.quad(lo_hex[k], lo_hex[(k + 1) % 6], hi_hex[(k + 1) % 6], hi_hex[k])
    neck = ring(m, b["r"], 0.0, n)
    pts = hpts + [m.v[i][:2] for i in neck]
    ids = lo_hex + neck
    for a, bb, c in zip_loops(pts, list(range(6)), list(range(6, 6 + n))):
        m.tri(ids[a], ids[c], ids[bb])  # bearing face looks down (-z)
    L, r, rm = b["length"], b["r"], b["minor_r"]
    prof = [(0.0, -L), (r - 1.0, -L), (r, -L + 1.0)]
    z = -L + 1.0
    top_thread = -L + b["thread"]
    half = b["pitch"] / 2
    while z + 2 * half <= top_thread + 1e-9:
        prof += [(rm, z + half), (r, z + 2 * half)]
        z += 2 * half
    prof += [(r, 0.0)]
    lathe(m, prof, n, existing={len(prof) - 1: neck})
    return m


def make_nut():
    """M12 hex nut, 18 mm across flats, 10 mm high, bore r 6 mm; frame at its centre."""
    return plate_with_hole("nut-m12", lambda pts: hex_pts(pts, 18.0), 6.0, BOLT["seg"], 10.0)


def make_washer():
    """M12 washer, 12.8 / 24 mm, 2.5 mm thick; frame at its centre."""
    m = Mesh("washer-m12")
    lathe(m, [(6.4, -1.25), (12.0, -1.25), (12.0, 1.25), (6.4, 1.25)], BOLT["seg"], closed=True)
    return m


# --------------------------------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------------------------------

def pose(pos, axis=None, angle=None):
    p = {"position": [num(x) for x in pos]}
    if axis is not None:
        p["rotation"] = {"axis": axis, "angle": angle}
    return p


def num(x):
    """Numbers as written in JSON: integers stay integers, others keep 6 decimals."""
    if isinstance(x, int):
        return x
    r = round(x, 6)
    return int(r) if r == int(r) and abs(r) < 1e15 else r


def tidy(obj):
    """Whole numbers written without a fractional part (150 rather than 150.0)."""
    if isinstance(obj, float):
        return num(obj)
    if isinstance(obj, list):
        return [tidy(x) for x in obj]
    if isinstance(obj, dict):
        return {k: tidy(v) for k, v in obj.items()}
    return obj


def dumps(obj, indent=0, width=112):
    """JSON with small arrays and objects on one line, as a person would write it."""
    flat = json.dumps(obj, separators=(", ", ": "))
    if len(flat) + indent <= width or not isinstance(obj, (dict, list)):
        return flat
    pad = " " * (indent + 2)
    if isinstance(obj, dict):
        items = [f"{pad}{json.dumps(k)}: {dumps(v, indent + 2, width)}" for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + " " * indent + "}"
    items = [pad + dumps(v, indent + 2, width) for v in obj]
    return "[\n" + ",\n".join(items) + "\n" + " " * indent + "]"


TABLE_COLOR = "#7a5c3e"


def table(size=(1600, 800, 40)):
    return {"name": "table", "kind": "table", "primitive": {"type": "box", "size": list(size)},
            "pose": {"position": [0, 0, num(-size[2] / 2)]}, "color": TABLE_COLOR}


def scene_sleeve_on_shaft():
    return {
        "format": "vaw-scene",
        "version": 1,
        "name": "Sleeve on shaft",
        "description": "Paper pictures 1-5: a block base with an extruded shaft and a sleeve that fits it. "
                       "Steel block 200 x 150 x 40 mm with a shaft of radius 15 mm rising 120 mm; brass "
                       "sleeve, bore radius 15 mm (an equal-diameter fit), outside radius 25 mm, 40 mm long. "
                       "The sleeve's property file holds the values of the true cylinder; its 64-segment "
                       "mesh disagrees with them by about 0.2 %.",
        "units": "mm",
        "materials": {
            "steel": {"density": 7850, "friction": {"static": 0.30, "kinetic": 0.20, "rotational": 0.0005},
                      "color": "#8a939c"},
            "brass": {"density": "8.5 g/cm^3", "friction": {"static": 0.25, "kinetic": 0.18, "rotational": 0.0005},
                      "color": "#c9a43b"},
            "oak": {"density": 750, "friction": {"static": 0.5, "kinetic": 0.4, "rotational": 0.0}, "color": "#8b6a45"},
        },
        "parts": [
            {"name": "base", "mesh": "../meshes/shaft-base.stl", "material": "steel", "pose": {"position": [0, 0, 0]}},
            {"name": "sleeve", "mesh": "../meshes/sleeve.obj", "material": "brass",
             "properties": "../properties/sleeve.json",
             "pose": {"position": [250, 0, 150]},
             "final_pose": {"position": [0, 0, 40]}},
        ],
        "base": "base",
        "environment": [table()],
        "constraints": [
            {"type": "insert", "part": "sleeve",
             "part_axis": {"point": [0, 0, 0], "direction": [0, 0, 1]},
             "base_axis": {"point": [0, 0, 0], "direction": [0, 0, 1]}},
        ],
    }


def scene_block_on_plate():
    bx, by, bz = BLOCK_PART
    return {
        "format": "vaw-scene",
        "version": 1,
        "name": "Block on plate",
        "description": "A steel plate 300 x 200 x 40 mm with a flat top face and an aluminium block "
                       "60 x 40 x 30 mm that is placed face down on it (a mate constraint); the block "
                       "slides on the plate with static friction 0.30 and kinetic friction 0.20.",
        "units": "mm",
        "materials": {
            "steel": {"density": 7850, "friction": {"static": 0.30, "kinetic": 0.20, "rotational": 0.0005},
                      "color": "#8a939c"},
            "aluminium": {"density": 2700, "friction": {"static": 0.30, "kinetic": 0.20, "rotational": 0.0005},
                          "color": "#c4c9cf"},
        },
        "parts": [
            {"name": "plate", "mesh": "../meshes/flat-base.ply", "material": "steel", "pose": {"position": [0, 0, 0]}},
            {"name": "block", "mesh": "../meshes/block.gltf", "material": "aluminium",
             "pose": {"position": [300, 120, 150], "rotation": {"axis": [0, 0, 1], "angle": 30}},
             "final_pose": {"position": [40, 20, num(PLATE[2] + bz / 2)], "rotation": {"axis": [0, 0, 1], "angle": 15}}},
        ],
        "base": "plate",
        "environment": [table()],
        "constraints": [
            {"type": "mate", "part": "block",
             "part_plane": {"point": [0, 0, -bz / 2], "normal": [0, 0, -1]},
             "base_plane": {"point": [0, 0, PLATE[2]], "normal": [0, 0, 1]}},
        ],
    }


# Gear-on-shaft base, built from primitives (frame at the centre of the foot's bottom face).
GEAR_FOOT = (320.0, 160.0, 30.0)
GEAR_POST = (40.0, 60.0, 160.0)
GEAR_SHAFT_Z = 150.0
GEAR_SHAFT_LEN = 250.0


def gear_base_primitives():
    fx, fy, fz = GEAR_FOOT
    px, py, pz = GEAR_POST
    post_x = -fx / 2 + px / 2
    shaft_x0 = post_x + px / 2                 # the shaft starts at the post's +x face
    return [
        {"type": "box", "size": [fx, fy, fz], "pose": {"position": [0, 0, fz / 2]}},
        {"type": "box", "size": [px, py, pz], "pose": {"position": [post_x, 0, fz + pz / 2]}},
        {"type": "cylinder", "radius": GEAR_BORE_R, "height": GEAR_SHAFT_LEN, "segments": GEAR_BORE_N,
         "pose": {"position": [shaft_x0 + GEAR_SHAFT_LEN / 2, 0, GEAR_SHAFT_Z],
                  "rotation": {"axis": [0, 1, 0], "angle": 90}}},
    ]


def scene_gear_on_shaft(gear):
    return {
        "format": "vaw-scene",
        "version": 1,
        "name": "Gear on shaft",
        "description": "Paper section 5: a gear whose bore is off its centre turns about a horizontal shaft. "
                       "Base: a steel foot, a post and a shaft of radius 10 mm along x. Gear: steel, 24 "
                       "teeth, tip radius 50 mm, bore radius 10 mm, face width %.2f mm, about 0.300 kg, "
                       "centre of mass 20 mm from the bore axis. Rotational friction 0.0005 N m s."
                       % gear.thickness,
        "units": "mm",
        "materials": {
            "steel": {"density": 7850, "friction": {"static": 0.30, "kinetic": 0.20, "rotational": 0.0005},
                      "color": "#8a939c"},
        },
        "parts": [
            {"name": "base", "primitive": gear_base_primitives(), "material": "steel",
             "pose": {"position": [0, 0, 0]}},
            {"name": "gear", "mesh": "../meshes/gear.glb", "material": "steel",
             "pose": {"position": [150, 250, 100]},
             "final_pose": {"position": [60, 0, GEAR_SHAFT_Z], "rotation": {"axis": [0, 1, 0], "angle": 90}}},
        ],
        "base": "base",
        "environment": [table()],
        "constraints": [
            {"type": "insert", "part": "gear",
             "part_axis": {"point": [0, 0, 0], "direction": [0, 0, 1]},
             "base_axis": {"point": [0, 0, GEAR_SHAFT_Z], "direction": [1, 0, 0]}},
        ],
    }


def gearbox_layout():
    """Meshes and parts of the large gearbox. Returns (meshes {file: Mesh}, scene)."""
    meshes = {}

    def use(fname, builder):
        if fname not in meshes:
            meshes[fname] = builder()
        return "../meshes/" + fname

    H = HOUSING
    hx = -450.0  # housing centre on the table
    to_x = [0, 1, 0]  # rotation axis turning a z-axis part to lie along x: 90 degrees about y
    shafts = [  # (name, y, radius, bearing outside radius, bearing width)
        ("input-shaft", -120.0, 12.0, 28.0, 20.0),
        ("intermediate-shaft", 0.0, 15.0, 35.0, 22.0),
        ("output-shaft", 120.0, 20.0, 42.0, 24.0),
    ]
    shaft_len = 600.0
    pb_x = 270.0
    floor = H["floor"]
    gears = [  # (name, shaft index, module, teeth, face width, x)
        ("gear-a1", 0, 3.0, 18, 30.0, -150.0), ("gear-a2", 1, 3.0, 55, 30.0, -150.0),
        ("gear-c1", 0, 3.0, 30, 25.0, -60.0), ("gear-c2", 1, 3.0, 43, 25.0, -60.0),
        ("gear-b1", 1, 3.5, 20, 35.0, 50.0), ("gear-b2", 2, 3.5, 42, 35.0, 50.0),
        ("gear-d1", 1, 3.5, 26, 30.0, 150.0), ("gear-d2", 2, 3.5, 36, 30.0, 150.0),
    ]
    shaft_parts, bearing_parts, block_parts, gear_parts = [], [], [], []
    for name, y, r, ro, bw in shafts:
        f = use(f"{name}.ply", lambda n=name, r=r: make_shaft(n, r, shaft_len))
        shaft_parts.append({"name": name, "mesh": f, "material": "steel",
                            "pose": pose((0, y, SHAFT_Z), to_x, 90)})
        bf = use(f"bearing-{int(2 * r)}x{int(2 * ro)}.ply", lambda r=r, ro=ro, bw=bw: make_bearing(
            f"bearing-{int(2 * r)}x{int(2 * ro)}x{int(bw)}", r, ro, bw))
        pf = use(f"pillow-block-{int(2 * ro)}.stl", lambda ro=ro: make_pillow_block(
            f"pillow-block-{int(2 * ro)}", ro, SHAFT_Z - floor, ro + 15.0, 2 * ro + 40.0, 40.0))
        for side, sx in (("left", -pb_x), ("right", pb_x)):
            bearing_parts.append({"name": f"{name}-bearing-{side}", "mesh": bf, "material": "bearing_steel",
                                  "pose": pose((sx, y, SHAFT_Z), to_x, 90)})
            block_parts.append({"name": f"{name}-pillow-block-{side}", "mesh": pf, "material": "cast_iron",
                                "pose": pose((sx, y, SHAFT_Z))})
    for name, si, module, teeth, fw, x in gears:
        _, y, r, _, _ = shafts[si]
        f = use(f"{name}.ply", lambda n=name, module=module, teeth=teeth, fw=fw, r=r: involute_gear(
            n, module, teeth, fw, r, SEG, flank_pts=28, tip_pts=8, gap_pts=10))
        gear_parts.append({"name": name, "mesh": f, "material": "steel", "pose": pose((x, y, SHAFT_Z), to_x, 90)})
    internals = [
        {"name": "shafts", "children": shaft_parts},
        {"name": "gear train", "children": gear_parts},
        {"name": "bearings", "children": bearing_parts},
        {"name": "pillow blocks", "children": block_parts},
    ]

    # Fasteners laid out on the table in front of the cover, ready for assembly.
    bolt_f = use("bolt-m12x40.stl", make_bolt)
    nut_f = use("nut-m12.stl", make_nut)
    washer_f = use("washer-m12.stl", make_washer)
    bolts, washers, nuts = [], [], []
    for k in range(24):
        col, row = k % 12, k // 12
        x = 80.0 + 60.0 * col
        bolts.append({"name": f"bolt-{k + 1:02d}", "mesh": bolt_f, "material": "steel",
                      "pose": pose((x, 170.0 + 60.0 * row, BOLT["head"]), [1, 0, 0], 180)})
        washers.append({"name": f"washer-{k + 1:02d}", "mesh": washer_f, "material": "steel",
                        "pose": pose((x, 290.0 + 50.0 * row, 1.25))})
        nuts.append({"name": f"nut-{k + 1:02d}", "mesh": nut_f, "material": "steel",
                     "pose": pose((x, 390.0 + 50.0 * row, 5.0))})

    housing_f = use("gearbox-housing.ply", make_housing)
    cover_f = use("gearbox-cover.stl", lambda: box_mesh("gearbox-cover", H["length"], H["width"], 12.0))
    scene = {
        "format": "vaw-scene",
        "version": 1,
        "name": "Large gearbox",
        "description": "A two-stage spur gearbox for performance work: an open cast-iron housing (the base) "
                       "with three shafts in six bearings and pillow blocks, eight involute gears, and the "
                       "aluminium cover with 24 bolts, washers and nuts laid out on the table. Threads are "
                       "modelled as axisymmetric ridges. The cover mates with the housing's rim.",
        "units": "mm",
        "materials": {
            "cast_iron": {"density": 7200, "friction": {"static": 0.25, "kinetic": 0.18, "rotational": 0.0005},
                          "color": "#4f5a63"},
            "steel": {"density": 7850, "friction": {"static": 0.30, "kinetic": 0.20, "rotational": 0.0005},
                      "color": "#8a939c"},
            "bearing_steel": {"density": 7810, "friction": {"static": 0.30, "kinetic": 0.20, "rotational": 0.0002},
                              "color": "#b8bec4"},
            "aluminium": {"density": 2700, "friction": {"static": 0.35, "kinetic": 0.25, "rotational": 0.0005},
                          "color": "#c4c9cf"},
        },
        "parts": [
            {"name": "housing", "mesh": housing_f, "material": "cast_iron", "pose": pose((hx, 0, 0))},
            {"name": "internals", "pose": pose((hx, 0, 0)), "children": internals},
            {"name": "cover", "mesh": cover_f, "material": "aluminium",
             "pose": pose((400, -150, 6)),
             "final_pose": pose((hx, 0, H["height"] + 6.0))},
            {"name": "fasteners", "children": [
                {"name": "bolts", "children": bolts},
                {"name": "washers", "children": washers},
                {"name": "nuts", "children": nuts}]},
        ],
        "base": "housing",
        "environment": [table((2000, 1000, 40))],
        "constraints": [
            {"type": "mate", "part": "cover",
             "part_plane": {"point": [0, 0, -6], "normal": [0, 0, -1]},
             "base_plane": {"point": [0, 0, H["height"]], "normal": [0, 0, 1]}},
        ],
    }
    return meshes, scene


# --------------------------------------------------------------------------------------------------
# Scene validation (a stand-in for `vaw-sim inspect` while that does not exist)
# --------------------------------------------------------------------------------------------------

ALLOWED = {
    "top": {"format", "version", "name", "units", "materials", "parts", "base", "environment", "constraints",
            "description"},
    "material": {"density", "friction", "color"},
    "friction": {"static", "kinetic", "rotational"},
    "part": {"name", "mesh", "primitive", "material", "pose", "final_pose", "properties", "density"},
    "group": {"name", "pose", "children"},
    "pose": {"position", "rotation"},
    "rotation_axis": {"axis", "angle"},
    "rotation_q": {"quaternion"},
    "env": {"name", "kind", "primitive", "mesh", "pose", "color"},
    "plane": {"point", "normal"},
    "axis": {"point", "direction"},
    "props": {"format", "version", "part", "units", "mass", "center_of_mass", "inertia_cm", "density", "volume",
              "surface_area", "surface_finish", "tolerance"},
}
PRIM_KEYS = {"box": {"type", "size", "pose"}, "cylinder": {"type", "radius", "height", "segments", "pose"},
             "tube": {"type", "outer_radius", "inner_radius", "height", "segments", "pose"},
             "sphere": {"type", "radius", "segments", "rings", "pose"}}
CONSTRAINT_KEYS = {"mate": {"type", "part", "part_plane", "base_plane", "offset"},
                   "align": {"type", "part", "part_plane", "base_plane", "offset"},
                   "insert": {"type", "part", "part_axis", "base_axis"}}


def keys_ok(obj, allowed, where):
    if not isinstance(obj, dict):
        raise BuildError(f"{where}: expected an object")
    bad = [k for k in obj if k not in allowed and not k.startswith("_")]
    if bad:
        raise BuildError(f"{where}: unknown keys {bad}")


def parse_pose(p, where):
    if p is None:
        return IDENTITY, (0.0, 0.0, 0.0)
    keys_ok(p, ALLOWED["pose"], where)
    pos = tuple(float(x) for x in p["position"])
    rot = IDENTITY
    if "rotation" in p:
        r = p["rotation"]
        if "quaternion" in r:
            raise BuildError(f"{where}: this checker handles axis/angle only")
        keys_ok(r, ALLOWED["rotation_axis"], where + ".rotation")
        rot = axis_angle(r["axis"], r["angle"])
    return rot, pos


def compose(a, b):
    """a then b in parent terms: world = a * b."""
    ra, pa = a
    rb, pb = b
    return mat_mul(ra, rb), add(mat_vec(ra, pb), pa)


def prim_box(size):
    return box_mesh("box", *size)


def prim_cylinder(radius, height, segments):
    m = Mesh("cylinder")
    lathe(m, [(0.0, -height / 2), (radius, -height / 2), (radius, height / 2), (0.0, height / 2)], segments)
    return m


def primitive_mesh(p, where):
    if p["type"] not in PRIM_KEYS:
        raise BuildError(f"{where}: unknown primitive {p['type']}")
    keys_ok(p, PRIM_KEYS[p["type"]], where)
    if p["type"] == "box":
        m = prim_box(p["size"])
    elif p["type"] == "cylinder":
        m = prim_cylinder(p["radius"], p["height"], p.get("segments", 64))
    elif p["type"] == "tube":
        m = Mesh("tube")
        h = p["height"] / 2
        lathe(m, [(p["inner_radius"], -h), (p["outer_radius"], -h), (p["outer_radius"], h),
                  (p["inner_radius"], h)], p.get("segments", 64), closed=True)
    else:
        raise BuildError(f"{where}: sphere not supported by this checker")
    rot, pos = parse_pose(p.get("pose"), where + ".pose")
    return m.transformed(rot, pos)


def load_shape(obj, folder, where, cache):
    if "mesh" in obj:
        path = os.path.normpath(os.path.join(folder, obj["mesh"]))
        if path not in cache:
            if not os.path.exists(path):
                raise BuildError(f"{where}.mesh: {path} does not exist")
            ext = os.path.splitext(path)[1].lower()
            m = WRITERS[ext][1](path)
            check_mesh(m, path)
            cache[path] = m
        return cache[path]
    prim = obj["primitive"]
    if isinstance(prim, list):
        m = Mesh("primitives")
        for k, p in enumerate(prim):
            m.append(primitive_mesh(p, f"{where}.primitive[{k}]"))
        return m
    return primitive_mesh(prim, where + ".primitive")


def plane_world(tf, plane):
    rot, pos = tf
    return add(mat_vec(rot, plane["point"]), pos), mat_vec(rot, plane["normal"])


def unit(v):
    n = norm(v)
    return (v[0] / n, v[1] / n, v[2] / n)


def validate_scene(path):
    """Checks a scene against docs/scene-format.md. Returns a report dict."""
    folder = os.path.dirname(path)
    s = json.load(open(path))
    keys_ok(s, ALLOWED["top"], path)
    if s["format"] != "vaw-scene" or s["version"] != 1:
        raise BuildError(f"{path}: format/version")
    if s["units"] != "mm":
        raise BuildError(f"{path}: this checker assumes mm")
    for name, mat in s["materials"].items():
        keys_ok(mat, ALLOWED["material"], f"materials.{name}")
        fr = mat["friction"]
        keys_ok(fr, ALLOWED["friction"], f"materials.{name}.friction")
        if not (0 <= fr["kinetic"] <= fr["static"] and fr["rotational"] >= 0):
            raise BuildError(f"materials.{name}.friction: need 0 <= kinetic <= static, rotational >= 0")
    densities = {}
    for name, mat in s["materials"].items():
        d = mat["density"]
        if isinstance(d, str):
            v, u = d.split()
            d = float(v) * {"kg/m^3": 1.0, "g/cm^3": 1000.0}[u]
        densities[name] = d
    cache = {}
    parts = {}

    def walk(items, parent_tf, where):
        for k, it in enumerate(items):
            w = f"{where}[{k}]"
            if "children" in it:
                keys_ok(it, ALLOWED["group"], w)
                walk(it["children"], compose(parent_tf, parse_pose(it.get("pose"), w + ".pose")), w + ".children")
                continue
            keys_ok(it, ALLOWED["part"], w)
            if ("mesh" in it) == ("primitive" in it):
                raise BuildError(f"{w}: exactly one of mesh/primitive")
            if it["name"] in parts:
                raise BuildError(f"{w}: duplicate name {it['name']}")
            if it["material"] not in s["materials"]:
                raise BuildError(f"{w}: unknown material")
            m = load_shape(it, folder, w, cache)
            tf = compose(parent_tf, parse_pose(it.get("pose"), w + ".pose"))
            ftf = compose(parent_tf, parse_pose(it["final_pose"], w + ".final_pose")) if "final_pose" in it else None
            if "properties" in it:
                pp = os.path.join(folder, it["properties"])
                keys_ok(json.load(open(pp)), ALLOWED["props"], pp)
            parts[it["name"]] = dict(mesh=m, tf=tf, final=ftf, material=it["material"], where=w)

    walk(s["parts"], (IDENTITY, (0.0, 0.0, 0.0)), "parts")
    base = s.get("base")
    if base is not None and base not in parts:
        raise BuildError(f"{path}: base {base} is not a part")
    tables = []
    for k, e in enumerate(s.get("environment", [])):
        keys_ok(e, ALLOWED["env"], f"environment[{k}]")
        if e["kind"] not in ("table", "floor", "fixture"):
            raise BuildError(f"environment[{k}].kind")
        em = load_shape(e, folder, f"environment[{k}]", cache).transformed(*parse_pose(e.get("pose"), "env"))
        if e["kind"] == "table":
            tables.append(em.bounds())
    if not tables:
        raise BuildError(f"{path}: no table")
    (tlo, thi) = tables[0]
    top = thi[2]
    report = {"parts": [], "triangles": 0}
    boxes = {}
    for name, p in parts.items():
        wm = p["mesh"].transformed(*p["tf"])
        lo, hi = wm.bounds()
        if lo[2] < top - 1e-6:
            raise BuildError(f"{path}: part {name} starts below the table top ({lo[2]} < {top})")
        if lo[0] < tlo[0] or hi[0] > thi[0] or lo[1] < tlo[1] or hi[1] > thi[1]:
            raise BuildError(f"{path}: part {name} is not over the table")
        boxes[name] = (lo, hi)
        mp = mass_props(p["mesh"], densities[p["material"]] * 1e-9)
        report["parts"].append((name, len(p["mesh"].t), mp["mass"]))
        report["triangles"] += len(p["mesh"].t)
    # Free parts must not start inside the base or each other (bounding boxes, touching allowed).
    names = list(boxes)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if a != base and b != base and len(names) > 10:
                continue  # in the large scene only check against the base
            (la, ha), (lb, hb) = boxes[a], boxes[b]
            if all(la[k] < hb[k] - 1e-6 and lb[k] < ha[k] - 1e-6 for k in range(3)):
                if base in (a, b) and len(names) > 10:
                    inner = a if b == base else b
                    if parts[inner]["where"].startswith("parts[1]"):
                        continue  # the housing's internals sit inside its bounding box by design
                raise BuildError(f"{path}: parts {a} and {b} start with overlapping bounding boxes")
    for k, c in enumerate(s.get("constraints", [])):
        w = f"constraints[{k}]"
        keys_ok(c, CONSTRAINT_KEYS[c["type"]], w)
        if c["part"] not in parts or c["part"] == base or base is None:
            raise BuildError(f"{w}: bad part or no base")
        p = parts[c["part"]]
        if p["final"] is None:
            continue
        btf = parts[base]["tf"]
        if c["type"] == "insert":
            for key in ("part_axis", "base_axis"):
                keys_ok(c[key], ALLOWED["axis"], f"{w}.{key}")
            pp, pd = plane_world(p["final"], {"point": c["part_axis"]["point"], "normal": c["part_axis"]["direction"]})
            bp, bd = plane_world(btf, {"point": c["base_axis"]["point"], "normal": c["base_axis"]["direction"]})
            pd, bd = unit(pd), unit(bd)
            if norm(cross(pd, bd)) > 1e-9 or norm(cross(sub(pp, bp), bd)) > 1e-6:
                raise BuildError(f"{w}: insert does not hold at the final pose")
        else:
            for key in ("part_plane", "base_plane"):
                keys_ok(c[key], ALLOWED["plane"], f"{w}.{key}")
            pp, pn = plane_world(p["final"], c["part_plane"])
            bp, bn = plane_world(btf, c["base_plane"])
            pn, bn = unit(pn), unit(bn)
            want = -1.0 if c["type"] == "mate" else 1.0
            if abs(dot(pn, bn) - want) > 1e-12 or abs(dot(sub(pp, bp), bn) - c.get("offset", 0.0)) > 1e-6:
                raise BuildError(f"{w}: {c['type']} does not hold at the final pose")
    return report


# --------------------------------------------------------------------------------------------------
# Property file of the sleeve: the TRUE tube, as a CAD system reports it
# --------------------------------------------------------------------------------------------------

def sleeve_properties():
    rho = 8.5e-3  # g/mm^3
    ri, ro, h = SHAFT_R, SLEEVE_R, SLEEVE_H
    vol = math.pi * (ro * ro - ri * ri) * h
    mass = rho * vol
    izz = mass / 2 * (ro * ro + ri * ri)
    ixx = mass / 12 * (3 * (ro * ro + ri * ri) + h * h)
    area = TAU * (ro + ri) * h + TAU * (ro * ro - ri * ri)
    return {
        "format": "vaw-properties",
        "version": 1,
        "part": "sleeve",
        "_comment": "Exported for the true cylindrical tube (analytic): bore 30 mm, outside 50 mm, length 40 mm, "
                    "brass 8.5 g/cm^3. Inertia in g mm^2 about the centre of mass, part-frame axes. The "
                    "64-segment mesh differs by about 0.2 %.",
        "units": {"length": "mm", "mass": "g"},
        "mass": round(mass, 4),
        "center_of_mass": [0, 0, num(h / 2)],
        "inertia_cm": [[round(ixx, 2), 0, 0], [0, round(ixx, 2), 0], [0, 0, round(izz, 2)]],
        "density": "8.5 g/cm^3",
        "volume": round(vol, 3),
        "surface_area": round(area, 3),
        "surface_finish": "Ra 1.6 um, turned",
        "tolerance": 0.05,
    }


# --------------------------------------------------------------------------------------------------
# Main
# --------------------------------------------------------------------------------------------------

def human(n):
    return f"{n / 1024 / 1024:.2f} MiB" if n > 1024 * 1024 else f"{n / 1024:.1f} KiB"


def main(argv):
    check_only = "--check" in argv
    out_mesh = MESH_DIR
    if check_only:
        import tempfile
        tmp = tempfile.mkdtemp(prefix="vaw-meshes-")
        out_mesh = os.path.join(tmp, "meshes")
        out_scene = os.path.join(tmp, "scenes")
        out_prop = os.path.join(tmp, "properties")
    else:
        out_scene, out_prop = SCENE_DIR, PROP_DIR
    for d in (out_mesh, out_scene, out_prop):
        os.makedirs(d, exist_ok=True)

    gear = make_demo_gear()
    meshes = {
        "shaft-base.stl": make_shaft_base(),
        "sleeve.obj": make_sleeve(),
        "flat-base.ply": make_flat_base(),
        "block.gltf": make_block(),
        "gear.glb": gear,
    }
    big_meshes, big_scene = gearbox_layout()
    overlap = set(meshes) & set(big_meshes)
    if overlap:
        raise BuildError(f"mesh file names used twice: {overlap}")
    meshes.update(big_meshes)

    failures = 0
    total_bytes = 0
    print(f"{'mesh':28s} {'vertices':>9s} {'triangles':>9s} {'volume mm^3':>14s} {'file':>10s}")
    for fname, m in sorted(meshes.items()):
        try:
            vol = check_mesh(m, fname)
            path = os.path.join(out_mesh, fname)
            writer, reader = WRITERS[os.path.splitext(fname)[1]]
            writer(m, path)
            back = reader(path)
            vol_back = check_mesh(back, fname + " (as read back)")
            if len(back.t) != len(m.t) or abs(vol_back - vol) > 1e-4 * vol:
                raise BuildError(f"{fname}: read back differs (triangles {len(back.t)} vs {len(m.t)}, "
                                 f"volume {vol_back} vs {vol})")
            size = os.path.getsize(path)
            total_bytes += size
            print(f"{fname:28s} {len(m.v):9d} {len(m.t):9d} {vol:14.1f} {human(size):>10s}")
        except BuildError as e:
            print(f"FAILED: {e}", file=sys.stderr)
            failures += 1
    print(f"meshes total: {human(total_bytes)}")
    if total_bytes > 25 * 1000 * 1000:
        print("FAILED: meshes exceed 25 MB", file=sys.stderr)
        failures += 1
    if failures:
        return 1

    # Demo gear facts (in its own frame: bore axis = z).
    mp = mass_props(gear, STEEL * 1e-9)
    cm = mp["centroid"]
    print(f"gear: bore {gear.bore_offset:.4f} mm off the gear centre, face width {gear.thickness} mm, "
          f"mass {mp['mass']:.4f} kg, CM {math.hypot(cm[0], cm[1]):.4f} mm from the bore axis, "
          f"I_zz about the bore axis {(mp['inertia'][2][2] + mp['mass'] * (cm[0] ** 2 + cm[1] ** 2)) * 1e-6:.6e} kg m^2")

    # Sleeve: property file vs mesh.
    props = sleeve_properties()
    smp = mass_props(meshes["sleeve.obj"], 8.5e-3)
    print(f"sleeve: property-file mass {props['mass']:.2f} g, mesh {smp['mass']:.2f} g "
          f"({100 * (smp['mass'] / props['mass'] - 1):+.3f} %), Izz file {props['inertia_cm'][2][2]:.1f} "
          f"mesh {smp['inertia'][2][2]:.1f} g mm^2")

    scenes = {
        "sleeve-on-shaft.vaw.json": scene_sleeve_on_shaft(),
        "block-on-plate.vaw.json": scene_block_on_plate(),
        "gear-on-shaft.vaw.json": scene_gear_on_shaft(gear),
        "large-gearbox.vaw.json": big_scene,
    }
    with open(os.path.join(out_prop, "sleeve.json"), "w", newline="\n") as f:
        f.write(dumps(tidy(props)) + "\n")
    for fname, sc in scenes.items():
        with open(os.path.join(out_scene, fname), "w", newline="\n") as f:
            f.write(dumps(tidy(sc)) + "\n")
    for fname in scenes:
        path = os.path.join(out_scene, fname)
        try:
            rep = validate_scene(path)
        except (BuildError, KeyError, TypeError, ValueError) as e:
            print(f"FAILED: {fname}: {e!r}", file=sys.stderr)
            failures += 1
            continue
        print(f"{fname}: {len(rep['parts'])} parts, {rep['triangles']} triangles")
        if len(rep["parts"]) <= 10:
            for name, tris, mass in rep["parts"]:
                print(f"    {name:12s} {tris:7d} triangles  {mass:8.4f} kg (mesh, material density)")
        else:
            total_mass = sum(p[2] for p in rep["parts"])
            print(f"    total mass {total_mass:.1f} kg")
    big = validate_scene(os.path.join(out_scene, "large-gearbox.vaw.json"))
    if len(big["parts"]) < 60 or big["triangles"] < 260000:
        print("FAILED: the large gearbox needs >= 60 parts and >= 260,000 triangles", file=sys.stderr)
        failures += 1
    if check_only:
        print(f"(check only: output in {tmp})")
    return 1 if failures else 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BuildError as e:
        print(f"FAILED: {e}", file=sys.stderr)
        sys.exit(1)
