#!/usr/bin/env python3
"""The Cornell box with a dense UV sphere inside, for the cost-per-triangle and memory figures of
BENCHMARKS.md (issue 15): writes OUT/sphere.obj (a UV sphere of radius 0.1 m on the floor in front of
the tall block, SEGMENTS x RINGS quads, 2 x SEGMENTS x (RINGS - 1) triangles) and OUT/scene.toml
(scenes/cornell-box/cornell-box.toml with its files' paths made absolute, plus the sphere).

    python3 benches/dense_mesh.py --segments 1000 --rings 500 --out target/dense-1m
    python3 benches/dense_mesh.py --segments 3163 --rings 1582 --out target/dense-10m
    /usr/bin/time -f '%e s %M KiB' target/release/quasar render target/dense-10m/scene.toml \\
        --method pt --width 128 --height 96 --spp 128 -o dense.exr

Needs numpy (the race venv has it: target/mitsuba-venv/bin/python).
"""

import argparse
import os
import re

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
BOX = os.path.join(HERE, "..", "scenes", "cornell-box")


def write_sphere(path, segments, rings, centre=(0.42, 0.1, 0.12), radius=0.1):
    theta = np.linspace(0.0, np.pi, rings + 1)[1:-1]  # interior rings; the poles are single vertices
    phi = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring_v = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    verts = np.concatenate([[[0.0, 1.0, 0.0]], ring_v, [[0.0, -1.0, 0.0]]]) * radius + np.array(centre)
    n_ring = rings - 1
    idx = lambda r, s: 2 + r * segments + (s % segments)  # noqa: E731 (1-based OBJ index)
    s = np.arange(segments)
    faces = [np.stack([np.ones(segments, int), idx(0, s + 1), idx(0, s)], axis=-1)]
    r, s2 = np.meshgrid(np.arange(n_ring - 1), s, indexing="ij")
    r, s2 = r.ravel(), s2.ravel()
    faces.append(np.stack([idx(r, s2), idx(r, s2 + 1), idx(r + 1, s2 + 1)], axis=-1))
    faces.append(np.stack([idx(r, s2), idx(r + 1, s2 + 1), idx(r + 1, s2)], axis=-1))
    bottom = 2 + n_ring * segments
    faces.append(np.stack([idx(n_ring - 1, s), idx(n_ring - 1, s + 1), np.full(segments, bottom)], axis=-1))
    faces = np.concatenate(faces)
    with open(path, "w") as f:
        np.savetxt(f, verts, fmt="v %.6f %.6f %.6f")
        np.savetxt(f, faces, fmt="f %d %d %d")
    return len(faces)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--segments", type=int, default=1000)
    ap.add_argument("--rings", type=int, default=500)
    ap.add_argument("--out", default="target/dense-1m")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    n = write_sphere(os.path.join(a.out, "sphere.obj"), a.segments, a.rings)
    with open(os.path.join(BOX, "cornell-box.toml")) as f:
        text = f.read()
    text = re.sub(r'file = "([^"]+)"', lambda m: f'file = "{os.path.abspath(os.path.join(BOX, m.group(1)))}"', text)
    text += '\n[[shape]]\ntype = "mesh"\nfile = "sphere.obj"\nmaterial = "white"\n'
    with open(os.path.join(a.out, "scene.toml"), "w") as f:
        f.write(text)
    print(f"{a.out}/scene.toml: the Cornell box with a sphere of {n} triangles")


if __name__ == "__main__":
    main()
