#!/usr/bin/env python3
"""Writes the object models under data/objects/ (deterministic; standard library only).

Run from the repository root:  python3 tools/make_objects.py

For each object NAME it (over)writes
  data/objects/NAME/NAME.ply     binary little-endian PLY, float xyz in metres, uchar RGB per
                                 vertex, closed and consistently oriented (normals outward)
  data/objects/NAME/object.yaml  mass (an estimate), centre of mass and inertia from the mesh
                                 at uniform density, dimensions, and the rotations that map the
                                 shape (and its colours) onto itself, in the block
                                 `aerograsp object import` writes (docs/objects.md)

Object frame o: origin at the centre of the mesh's axis-aligned bounding box, z up,
x along the longest side. Every object is one closed polyhedron: a simple polygon
(ear-clipped caps) or an annulus, extruded along an axis.
"""

import math
import os
import struct
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT_DIR = os.path.join(REPO, "data", "objects")


# --- geometry helpers -------------------------------------------------------------------------

def f32(value):
    """Rounds to the float32 the PLY file stores, so the figures match what a loader reads."""
    return struct.unpack("<f", struct.pack("<f", value))[0]


def cross2(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def polygon_area(poly):
    return 0.5 * sum(poly[i - 1][0] * poly[i][1] - poly[i][0] * poly[i - 1][1]
                     for i in range(len(poly)))


def ear_clip(poly):
    """Triangulates a simple counter-clockwise polygon; returns index triples, counter-clockwise."""
    assert polygon_area(poly) > 0, "polygon must be counter-clockwise"
    remaining = list(range(len(poly)))
    triangles = []

    def inside_or_on(p, a, b, c):
        return cross2(a, b, p) >= 0 and cross2(b, c, p) >= 0 and cross2(c, a, p) >= 0

    while len(remaining) > 3:
        n = len(remaining)
        for k in range(n):
            i0, i1, i2 = remaining[k - 1], remaining[k], remaining[(k + 1) % n]
            a, b, c = poly[i0], poly[i1], poly[i2]
            if cross2(a, b, c) <= 1e-15:
                continue  # reflex or flat corner: not an ear
            if any(inside_or_on(poly[j], a, b, c) for j in remaining if j not in (i0, i1, i2)):
                continue
            triangles.append((i0, i1, i2))
            remaining.pop(k)
            break
        else:
            raise RuntimeError("ear clipping found no ear: is the polygon simple?")
    triangles.append(tuple(remaining))
    return triangles


class Mesh:
    def __init__(self):
        self.vertices = []  # (x, y, z) metres
        self.colors = []    # (r, g, b) 0..255
        self.triangles = []

    def add_vertex(self, p, color):
        self.vertices.append(p)
        self.colors.append(color)
        return len(self.vertices) - 1


def extrude(mesh, rings, length, segments, to_xyz, color_of, caps):
    """Extrudes closed 2D rings (u, v) along w in [-length/2, length/2].

    rings: list of point lists; the outer boundary counter-clockwise, holes clockwise.
    to_xyz(u, v, w) maps to object coordinates; color_of(u, v) gives the RGB of a vertex.
    caps(mesh, index_at, last) adds the two end caps, where index_at(station, ring, k) is a
    vertex index and stations run from 0 (w = -length/2) to last (w = +length/2).
    Side quads (a, b, c), (a, c, d) face to the right of each ring's direction, which is
    outwards for a counter-clockwise outer ring and its clockwise holes when (u, v, w) is
    right-handed; a left-handed map flips everything, which orient_outwards() then undoes.
    """
    index = {}
    for station in range(segments + 1):
        w = -0.5 * length + length * station / segments
        for r, ring in enumerate(rings):
            for k, (u, v) in enumerate(ring):
                index[(station, r, k)] = mesh.add_vertex(to_xyz(u, v, w), color_of(u, v))

    def index_at(station, r, k):
        return index[(station, r, k % len(rings[r]))]

    for station in range(segments):
        for r, ring in enumerate(rings):
            for k in range(len(ring)):
                a = index_at(station, r, k)
                b = index_at(station, r, k + 1)
                c = index_at(station + 1, r, k + 1)
                d = index_at(station + 1, r, k)
                mesh.triangles += [(a, b, c), (a, c, d)]
    caps(mesh, index_at, segments)


def polygon_caps(polygon):
    ears = ear_clip(polygon)

    def caps(mesh, index_at, last):
        for a, b, c in ears:
            # Far cap (w max) faces +w: counter-clockwise in (u, v); the near cap reversed.
            mesh.triangles.append((index_at(last, 0, a), index_at(last, 0, b),
                                   index_at(last, 0, c)))
            mesh.triangles.append((index_at(0, 0, a), index_at(0, 0, c), index_at(0, 0, b)))
    return caps


def signed_volume(mesh):
    total = 0.0
    for a, b, c in mesh.triangles:
        p, q, r = mesh.vertices[a], mesh.vertices[b], mesh.vertices[c]
        total += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                  p[2] * (q[0] * r[1] - q[1] * r[0]))
    return total / 6.0


def orient_outwards(mesh):
    if signed_volume(mesh) < 0:
        mesh.triangles = [(a, c, b) for a, b, c in mesh.triangles]


def check_closed(name, mesh):
    """Every edge used exactly twice, in opposite directions; positive volume."""
    directed = {}
    for t in mesh.triangles:
        assert len(set(t)) == 3, f"{name}: triangle {t} repeats a vertex"
        for k in range(3):
            e = (t[k], t[(k + 1) % 3])
            if e in directed:
                raise RuntimeError(f"{name}: edge {e} used twice in the same direction")
            directed[e] = True
    for a, b in directed:
        if (b, a) not in directed:
            raise RuntimeError(f"{name}: boundary edge ({a}, {b})")
    if signed_volume(mesh) <= 0:
        raise RuntimeError(f"{name}: the triangles face inwards")


def center_on_bounds(mesh):
    lo = [min(v[i] for v in mesh.vertices) for i in range(3)]
    hi = [max(v[i] for v in mesh.vertices) for i in range(3)]
    centre = [0.5 * (lo[i] + hi[i]) for i in range(3)]
    mesh.vertices = [tuple(f32(v[i] - centre[i]) for i in range(3)) for v in mesh.vertices]


def mass_properties(mesh, mass_kg):
    """Volume, centre of mass and inertia about it (uniform density), by tetrahedra from the origin.

    A tetrahedron (0, a, b, c) with det = a.(b x c) has volume det/6, first moment
    det/24 (a+b+c) and second moment  integral p p^T dV = det/120 (sum p p^T + s s^T), s = a+b+c.
    """
    volume6 = 0.0
    first = [0.0] * 3
    second = [[0.0] * 3 for _ in range(3)]
    for ia, ib, ic in mesh.triangles:
        a, b, c = mesh.vertices[ia], mesh.vertices[ib], mesh.vertices[ic]
        det = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
               a[2] * (b[0] * c[1] - b[1] * c[0]))
        s = [a[i] + b[i] + c[i] for i in range(3)]
        volume6 += det
        for i in range(3):
            first[i] += det * s[i]
            for j in range(3):
                second[i][j] += det * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j])
    volume = volume6 / 6.0
    com = [first[i] / 24.0 / volume for i in range(3)]
    density = mass_kg / volume
    # Second moment about the centre of mass, then the inertia tensor.
    cov = [[density * second[i][j] / 120.0 - mass_kg * com[i] * com[j] for j in range(3)]
           for i in range(3)]
    trace = cov[0][0] + cov[1][1] + cov[2][2]
    inertia = [[(trace if i == j else 0.0) - cov[i][j] for j in range(3)] for i in range(3)]
    # Products of inertia that are rounding noise of a symmetric shape become exact zeros.
    scale = max(inertia[i][i] for i in range(3))
    inertia = [[0.0 if abs(x) < 1e-12 * scale else x for x in row] for row in inertia]
    return volume, com, inertia


# --- the objects ------------------------------------------------------------------------------

def make_crawler():
    """Pipe-inspection crawler: body between two tracks, extruded along x.

    A mock-up sized for our gripper (the paper gives no dimensions): 0.09 m across the
    tracks, so a top-down grasp closing across y fits the 0.10 m the fingers take
    (max_aperture_m 0.12 less 2 x finger_clearance_m 0.01) with 0.01 m to spare.
    """
    length, segments = 0.22, 10
    body_half_width, track_outer = 0.03, 0.045  # tracks 0.015 m wide
    body_bottom, body_top, height = 0.015, 0.065, 0.08
    # Cross-section in the y-z plane (z from the bottom), counter-clockwise seen from +x.
    section = [(-track_outer, 0.0), (-body_half_width, 0.0), (-body_half_width, body_bottom),
               (body_half_width, body_bottom), (body_half_width, 0.0), (track_outer, 0.0),
               (track_outer, height), (body_half_width, height), (body_half_width, body_top),
               (-body_half_width, body_top), (-body_half_width, height), (-track_outer, height)]
    track_color, body_color = (40, 40, 40), (230, 180, 20)
    eps = 1e-9

    def color_of(y, z):
        # Vertices on the seam between body and track take the body colour.
        on_body = abs(y) <= body_half_width + eps and body_bottom - eps <= z <= body_top + eps
        return body_color if on_body else track_color

    mesh = Mesh()
    extrude(mesh, [section], length, segments, lambda u, v, w: (w, u, v), color_of,
            polygon_caps(section))
    return mesh


def make_u_shape():
    """U-shaped bracket open at the top: U in the x-z plane, extruded along y."""
    width, height, wall, depth_y, segments = 0.20, 0.12, 0.03, 0.06, 3
    hw, inner = 0.5 * width, 0.5 * width - wall
    # Cross-section in the x-z plane (z from the bottom), counter-clockwise in (x, z).
    section = [(-hw, 0.0), (hw, 0.0), (hw, height), (inner, height), (inner, wall),
               (-inner, wall), (-inner, height), (-hw, height)]
    mesh = Mesh()
    extrude(mesh, [section], depth_y, segments, lambda u, v, w: (u, w, v),
            lambda u, v: (40, 90, 200), polygon_caps(section))
    return mesh


def make_pipe():
    """Pipe segment along x: an annulus extruded, 48 segments around."""
    outer_r, wall, length, around, segments = 0.045, 0.006, 0.20, 48, 8
    inner_r = outer_r - wall
    angles = [2.0 * math.pi * k / around for k in range(around)]
    outer = [(outer_r * math.cos(t), outer_r * math.sin(t)) for t in angles]
    inner = [(inner_r * math.cos(t), inner_r * math.sin(t)) for t in angles]
    # Holes run clockwise; hole vertex k then sits at angle index (around - k) % around.
    hole = [inner[(around - k) % around] for k in range(around)]

    def caps(mesh, index_at, last):
        tris = mesh.triangles
        for k in range(around):
            o0, o1 = k, k + 1
            i0, i1 = (around - k) % around, (around - k - 1) % around  # hole indices of k, k+1
            # Far cap (w max) faces +w: counter-clockwise in (u, v).
            tris.append((index_at(last, 0, o0), index_at(last, 0, o1), index_at(last, 1, i1)))
            tris.append((index_at(last, 0, o0), index_at(last, 1, i1), index_at(last, 1, i0)))
            # Near cap (w min) faces -w.
            tris.append((index_at(0, 0, o0), index_at(0, 1, i1), index_at(0, 0, o1)))
            tris.append((index_at(0, 0, o0), index_at(0, 1, i0), index_at(0, 1, i1)))

    mesh = Mesh()
    extrude(mesh, [outer, hole], length, segments, lambda u, v, w: (w, u, v),
            lambda u, v: (180, 180, 185), caps)
    return mesh


class Symmetry:
    """The proper rotations mapping an object onto itself: half turns about axes of frame o
    (besides the identity) and, for a body of revolution, its axis (any turn about it).
    The rotations turn about the area centroid of the surface, as core/symmetry.h's do;
    tests/core/test_mesh.cpp checks the group against the one found on the mesh."""

    def __init__(self, half_turn_axes, continuous_axis=None):
        self.half_turn_axes = half_turn_axes
        self.continuous_axis = continuous_axis


OBJECTS = [
    # name, builder, mass_kg, description, symmetry
    # 0.4 kg: a guess for a 3D-printed mock-up of this size (about 1.2e-3 m^3 of solid,
    # so ~340 kg/m^3, PLA at roughly a quarter infill), not a weighed robot.
    # The crawler is the same seen from either end, either side and upside down (its body sits
    # half-way up its tracks): the three half turns about x, y and z. The U turns end for end
    # about its vertical axis. The pipe spins freely about its axis and turns end for end.
    ("crawler", make_crawler, 0.4,
     "mock-up of a pipe-inspection crawler: yellow body between two dark grey tracks",
     Symmetry([(1, 0, 0), (0, 1, 0), (0, 0, 1)])),
    ("u_shape", make_u_shape, 0.3, "U-shaped bracket, open at the top (+z)",
     Symmetry([(0, 0, 1)])),
    ("pipe", make_pipe, 0.25, "pipe segment along x, outer diameter 0.09 m, wall 0.006 m",
     Symmetry([(0, 0, 1)], continuous_axis=(1, 0, 0))),
]


# --- writers ----------------------------------------------------------------------------------

def write_ply(path, name, mesh):
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"comment aerograsp object '{name}', metres, written by tools/make_objects.py\n"
              f"element vertex {len(mesh.vertices)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\n"
              f"element face {len(mesh.triangles)}\n"
              "property list uchar int vertex_indices\nend_header\n")
    body = bytearray()
    for (x, y, z), (r, g, b) in zip(mesh.vertices, mesh.colors):
        body += struct.pack("<fffBBB", x, y, z, r, g, b)
    for a, b, c in mesh.triangles:
        body += struct.pack("<Biii", 3, a, b, c)
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(body)


def fmt(value, spec=".6f"):
    text = format(value, spec)
    return text[1:] if text.startswith("-") and float(text) == 0.0 else text


def surface_centroid(mesh):
    """The area centroid of the surface, the point the symmetry rotations turn about."""
    area, first = 0.0, [0.0] * 3
    for ia, ib, ic in mesh.triangles:
        a, b, c = mesh.vertices[ia], mesh.vertices[ib], mesh.vertices[ic]
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        A = 0.5 * math.sqrt(sum(x * x for x in n))
        area += A
        for i in range(3):
            first[i] += A * (a[i] + b[i] + c[i]) / 3.0
    return [first[i] / area for i in range(3)]


def vec(v, spec=".6f"):
    return "[" + ", ".join(fmt(x, spec) for x in v) + "]"


def symmetry_lines(symmetry, center):
    """The `symmetry` block in the layout `aerograsp object import` writes."""
    lines = [
        "# The rotations that map the object (shape and vertex colours) onto itself, about",
        "# center_m: p -> center + R (p - center). Written by tools/make_objects.py from the",
        "# shapes it builds; `aerograsp object import` finds the same group on the mesh",
        "# (docs/objects.md). rotations_wxyz: quaternions, the identity first.",
        "symmetry:",
        f"  center_m: {vec(center)}",
    ]
    if symmetry.continuous_axis:
        lines.append(f"  continuous_axis: {vec(symmetry.continuous_axis)}"
                     "  # any turn about this axis through center_m")
    # A half turn about the unit axis a is the quaternion (0, a).
    rows = [((1, 0, 0, 0), "identity")] + [
        ((0,) + tuple(axis), f"180 deg about {vec(axis, '.4f')}")
        for axis in symmetry.half_turn_axes]
    lines.append("  rotations_wxyz: [")
    for k, (q, comment) in enumerate(rows):
        sep = "," if k + 1 < len(rows) else ""
        lines.append("    " + ", ".join(fmt(x, ".9f") for x in q) + f"{sep}  # {comment}")
    lines.append("  ]")
    return lines


def write_yaml(path, name, description, mass_kg, volume, com, inertia, dims, symmetry, center):

    lines = [
        f"# aerograsp object model '{name}': {description}.",
        "# Written by tools/make_objects.py; edit that script and rerun it rather than this file.",
        "# Frame o: origin at the centre of the mesh's bounding box, z up, x along the longest side.",
        "# mass_kg is an estimate (the object was not weighed); the centre of mass and inertia",
        "# are computed from the mesh at uniform density.",
        f"name: {name}",
        f"mesh: {name}.ply",
        f"mass_kg: {mass_kg}",
        f"volume_m3: {volume:.9f}",
        f"center_of_mass_m: {vec(com)}",
        "# Inertia about the centre of mass, axes of frame o, kg m^2 (rows of the 3x3 tensor).",
        "inertia_kg_m2: [" + ", ".join(vec(row, ".6e") for row in inertia) + "]",
        f"dimensions_m: {vec(dims)}",
    ] + symmetry_lines(symmetry, center)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    os.makedirs(OUT_DIR, exist_ok=True)
    for name, build, mass_kg, description, symmetry in OBJECTS:
        mesh = build()
        orient_outwards(mesh)
        center_on_bounds(mesh)
        check_closed(name, mesh)
        volume, com, inertia = mass_properties(mesh, mass_kg)
        dims = [max(v[i] for v in mesh.vertices) - min(v[i] for v in mesh.vertices)
                for i in range(3)]
        assert dims[0] >= dims[1] and dims[0] >= dims[2], f"{name}: x is not the longest side"
        folder = os.path.join(OUT_DIR, name)
        os.makedirs(folder, exist_ok=True)
        write_ply(os.path.join(folder, f"{name}.ply"), name, mesh)
        write_yaml(os.path.join(folder, "object.yaml"), name, description, mass_kg, volume, com,
                   inertia, dims, symmetry, surface_centroid(mesh))
        print(f"{name}: {len(mesh.vertices)} vertices, {len(mesh.triangles)} triangles, "
              f"volume {volume:.9f} m^3, com [{', '.join(fmt(c) for c in com)}] m, "
              f"dimensions [{', '.join(fmt(d, '.3f') for d in dims)}] m, mass {mass_kg} kg "
              f"-> {os.path.relpath(folder, REPO)}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
