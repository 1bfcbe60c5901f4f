#!/usr/bin/env python3
"""Luminance along the shipped lightguide's front face: what the PMMA's measured absorption and a
weak diffuser change (issue 49 item 4; the figures are in docs/lightguide.md).

Renders scenes/lightguide/lightguide.toml seen straight from the front (a camera 0.5 m in front of
the rod's middle) three times, with the rod's medium replaced by [[override]]s: clear PMMA (no
absorption), the shipped measured absorption (`absorption = "PMMA"`), and the diffusing variant
(scenes/lightguide/lightguide-diffuser.toml's medium). Prints the mean luminance (cd/m²) of the
front face in bins along the rod with its standard error, and each variant's ratio to the clear
rod.

    target/mitsuba-venv/bin/python benches/lightguide_profile.py --time 120
"""

import argparse
import math
import os
import subprocess

import numpy as np
import OpenEXR

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENE = os.path.join(ROOT, "scenes", "lightguide", "lightguide.toml")
HALF_LENGTH, HALF_HEIGHT, FRONT_Z = 0.12, 0.006, 0.006  # the rod (lightguide.toml), metres
DISTANCE, FOV_DEG = 0.5, 30.0
LUMINANCE_PER_Y = 72983.0  # docs/photometry.md

MEDIA = {
    "clear PMMA": "",
    "measured PMMA": 'absorption = "PMMA"',
    "PMMA + diffuser": 'absorption = "PMMA"\nscattering = 10\nphase_g = 0.6',
}
FINISHES = {"front": "alpha = 0.02", "back": "alpha = 0.15", "polished": ""}


def view(medium):
    """A scene file that includes the shipped lightguide, looks at it from the front and gives its
    rod `medium`."""
    text = f"""[camera]
position = [0, 0, {DISTANCE}]
target = [0, 0, 0]
fov_deg = {FOV_DEG}
fov_axis = "x"
[[include]]
file = "{SCENE}"
"""
    for finish, alpha in FINISHES.items():
        text += f'[materials.rod_{finish}]\ntype = "dielectric"\nior = "PMMA"\n{alpha}\n{medium}\n'
        text += f'[[override]]\nmatch = "pmma_{finish}"\nmaterial = "rod_{finish}"\n'
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", default=os.path.join(ROOT, "target", "release", "quasar"))
    ap.add_argument("--out", default=os.path.join(ROOT, "target", "lightguide-profile"))
    ap.add_argument("--time", type=float, default=120.0, help="seconds per render")
    ap.add_argument("--method", default="auto")
    ap.add_argument("--width", type=int, default=480)
    ap.add_argument("--bins", type=int, default=12, help="bins along the rod (the two halves are folded)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    w = a.width
    h = w // 8
    # pixel coordinates of the front face: a pinhole with the horizontal field of view FOV_DEG
    scale = (w / 2) / math.tan(math.radians(FOV_DEG) / 2) / (DISTANCE - FRONT_Z)
    x0, x1 = w / 2 - HALF_LENGTH * scale, w / 2 + HALF_LENGTH * scale
    y0, y1 = h / 2 - HALF_HEIGHT * scale, h / 2 + HALF_HEIGHT * scale
    rows = slice(math.ceil(y0) + 1, math.floor(y1) - 1)  # a pixel's margin from the edges
    cols = np.arange(math.ceil(x0) + 1, math.floor(x1) - 1)
    # distance of each column's centre from the nearer end of the rod, metres
    from_end = HALF_LENGTH - np.abs((cols + 0.5 - w / 2) / scale)
    edges = np.linspace(0.0, HALF_LENGTH, a.bins + 1)
    profiles = {}
    for name, medium in MEDIA.items():
        path = os.path.join(a.out, name.replace(" ", "-").replace("+", "and") + ".toml")
        with open(path, "w") as f:
            f.write(view(medium))
        exr = path.replace(".toml", ".exr")
        subprocess.run([a.quasar, "render", path, "--method", a.method, "--time", str(a.time), "--width", str(w),
                        "--height", str(h), "--quiet", "-o", exr], check=True)
        with OpenEXR.File(exr) as f:
            ch = f.channels()
            y = ch["XYZ.Y"].pixels.astype(np.float64)[rows][:, cols] * LUMINANCE_PER_Y
            se = ch["stderr.Y"].pixels.astype(np.float64)[rows][:, cols] * LUMINANCE_PER_Y
        profile = []
        for lo, hi in zip(edges[:-1], edges[1:]):
            sel = (from_end >= lo) & (from_end < hi)
            n = y[:, sel].size
            profile.append((y[:, sel].mean(), math.sqrt((se[:, sel] ** 2).sum()) / n))
        profiles[name] = profile
    names = list(MEDIA)
    print(f"front-face luminance (cd/m²), {a.method}, {a.time:g} s each, {w}x{h}; both halves folded")
    print("| distance from the rod's end (mm) | " + " | ".join(names) + " | " +
          " | ".join(f"{n} / clear" for n in names[1:]) + " |")
    print("|---" * (2 * len(names)) + "|")
    for i, (lo, hi) in enumerate(zip(edges[:-1], edges[1:])):
        clear = profiles[names[0]][i][0]
        cells = [f"{profiles[n][i][0]:.4g} ± {profiles[n][i][1]:.2g}" for n in names]
        ratios = [f"{profiles[n][i][0] / clear:.3f}" for n in names[1:]]
        print(f"| {lo * 1000:.0f}-{hi * 1000:.0f} | " + " | ".join(cells) + " | " + " | ".join(ratios) + " |")


if __name__ == "__main__":
    main()
