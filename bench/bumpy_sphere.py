#!/usr/bin/env python3
"""A bumpy sphere and a guide case on it: the benchmark's case at the paper's resolution.

The surface is a cube sphere (each face of a cube an n x n grid, pushed onto the sphere along the
radius) whose radius varies smoothly with the direction, r(u) = R + A (sin(k u_x + 0.3) + sin(k u_y
+ 1.1) + sin(k u_z + 2.3)) / 3: bumps about 13 mm apart and 2 mm high on a 25 mm sphere, the size
and relief of a dental arch. n = 129 gives 199,692 triangles; n = 289 about 1M, the same surface
finer. The case covers the cap within 42 degrees of +z (about 13 % of the sphere: some 26k of the
200k triangles) with T 2.5, h 0.25 and five sleeves drilled along the radius at 20 degrees from the pole.

    /usr/bin/python3 bench/bumpy_sphere.py OUT_DIR [--n 129] [--name bumpy-sphere-200k]

writes OUT_DIR/NAME.stl (binary) and OUT_DIR/NAME.json (the case) and prints the case's path.
"""
import argparse
import json
import math
import os
import struct

import numpy as np

RADIUS = 25.0
BUMP = 1.0  # amplitude A (mm): the relief is up to 2 A
FREQUENCY = 12.0  # k (radians per unit of direction)
CAP_DEG = 42.0
SLEEVE_DEG = 20.0


def radius(u):
    """The surface's radius along unit directions u (..., 3)."""
    s = np.sin(FREQUENCY * u[..., 0] + 0.3) + np.sin(FREQUENCY * u[..., 1] + 1.1) + np.sin(FREQUENCY * u[..., 2] + 2.3)
    return RADIUS + BUMP * s / 3.0


def on_surface(u):
    u = np.asarray(u, dtype=float)
    u = u / np.linalg.norm(u, axis=-1, keepdims=True)
    return radius(u)[..., None] * u


def cube_sphere(n):
    """Vertices (V, 3) and triangles (F, 3) of the bumpy cube sphere, n x n quads per cube face."""
    t = np.linspace(-1.0, 1.0, n + 1)
    a, b = np.meshgrid(t, t, indexing="ij")
    one = np.ones_like(a)
    faces = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            p = np.empty(a.shape + (3,))
            p[..., axis] = sign * one
            p[..., (axis + 1) % 3] = a
            p[..., (axis + 2) % 3] = b
            faces.append((p, sign))
    # Vertices keyed on the cube's integer grid, so the faces' shared edges and corners merge.
    keys = {}
    positions = []
    triangles = []
    for p, sign in faces:
        grid = np.rint((p + 1.0) * n / 2.0).astype(np.int64)
        flat = grid.reshape(-1, 3)
        index = np.empty(len(flat), dtype=np.int64)
        for i, key in enumerate(map(tuple, flat)):
            v = keys.get(key)
            if v is None:
                v = keys[key] = len(positions)
                positions.append(p.reshape(-1, 3)[i])
            index[i] = v
        index = index.reshape(n + 1, n + 1)
        i00, i10, i01, i11 = index[:-1, :-1], index[1:, :-1], index[:-1, 1:], index[1:, 1:]
        # Outward: the (axis+1, axis+2) grid is right-handed about +axis, so the sign picks the order;
        # each quad is split along alternating diagonals (no preferred direction in the tessellation).
        first = np.stack([i00, i10, i11], -1), np.stack([i00, i11, i01], -1)
        second = np.stack([i00, i10, i01], -1), np.stack([i10, i11, i01], -1)
        odd = ((np.add.outer(np.arange(n), np.arange(n))) % 2 == 1)[..., None]
        tri_a = np.where(odd, second[0], first[0]).reshape(-1, 3)
        tri_b = np.where(odd, second[1], first[1]).reshape(-1, 3)
        tris = np.concatenate([tri_a, tri_b])
        if sign < 0:
            tris = tris[:, [0, 2, 1]]
        triangles.append(tris)
    V = on_surface(np.array(positions))
    return V, np.concatenate(triangles)


def write_stl(path, V, F):
    tri = V[F].astype(np.float32)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    rec = np.zeros(len(F), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = n
    rec["v"] = tri
    with open(path, "wb") as f:
        f.write(b"bumpy sphere (bench/bumpy_sphere.py)".ljust(80, b" "))
        f.write(struct.pack("<I", len(F)))
        f.write(rec.tobytes())


def direction(polar_deg, azimuth_deg):
    p, a = math.radians(polar_deg), math.radians(azimuth_deg)
    return [math.sin(p) * math.cos(a), math.sin(p) * math.sin(a), math.cos(p)]


def case(name, bone_file):
    loop = on_surface([direction(CAP_DEG, 30.0 * i) for i in range(12)])
    tubes = []
    for i in range(5):
        u = direction(SLEEVE_DEG, 72.0 * i + 10.0)
        tubes.append({"name": f"s{i + 1}", "entry": [round(c, 4) for c in on_surface(u).tolist()],
                      "direction": [round(-c, 6) for c in u], "inner_radius": 1.1, "outer_radius": 2.0,
                      "length": 5.0, "offset": 3.0, "depth": 10.0})
    return {
        "format": "surgical-template-case/1",
        "name": name,
        "bone": bone_file,
        "boundary": {"points": [[round(c, 4) for c in p] for p in loop.tolist()],
                     "inside": [round(c, 4) for c in on_surface([0.0, 0.0, 1.0]).tolist()]},
        "template": {"thickness": 2.5, "clearance": 0.0, "resolution": 0.25},
        "tubes": tubes,
    }


def write_case(out_dir, n=129, name="bumpy-sphere-200k"):
    """Writes the mesh and the case; returns (case path, triangle count)."""
    os.makedirs(out_dir, exist_ok=True)
    V, F = cube_sphere(n)
    write_stl(os.path.join(out_dir, name + ".stl"), V, F)
    path = os.path.join(out_dir, name + ".json")
    with open(path, "w") as f:
        json.dump(case(name, name + ".stl"), f, indent=1)
    return path, len(F)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out_dir")
    ap.add_argument("--n", type=int, default=129, help="quads per cube-face edge (129: 200k triangles)")
    ap.add_argument("--name", default="bumpy-sphere-200k")
    args = ap.parse_args()
    path, count = write_case(args.out_dir, args.n, args.name)
    print(f"{path}: {count:,} triangles")


if __name__ == "__main__":
    main()
