#!/usr/bin/env python3
"""Which renderer is right where quasar's photon methods and its path tracer disagree on the
lightguide (BENCHMARKS.md, issue 15)?

The shipped lightguide's PMMA is dispersive, which Mitsuba cannot express, so this check renders
a copy with a constant index of refraction (1.49) in four renderers:

- Mitsuba `ptracer` (a particle tracer: light paths connected to the camera at every diffuse
  vertex; it carries light through the rod as easily as photons do, but it cannot show what the
  camera sees through a specular surface, so it is a reference for diffuse regions only);
- Mitsuba `path`, quasar `pt` (path tracers: they reach the LEDs behind the rod's polished ends
  only by BSDF sampling, so their errors there are heavy-tailed);
- quasar `vismap` (photons gathered at the first non-specular vertex);

and prints each one's mean Y and standard error over image regions: the reflector strip above
the rod (lit by light leaving the rod's back face), the housing beyond the rod's left end, and
the whole image.

    target/mitsuba-venv/bin/python benches/peers/lightguide_check.py --spp 65536 --vismap-time 30
"""

import argparse
import os
import subprocess
import sys
import time

import numpy as np
import OpenEXR

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "crosscheck"))
from crosscheck import CIE_Y_CORRECTION, write_exr  # noqa: E402

for _llvm in ("/usr/lib/x86_64-linux-gnu/libLLVM-19.so", "/usr/lib/llvm-19/lib/libLLVM.so"):
    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(_llvm):
        os.environ["DRJIT_LIBLLVM_PATH"] = _llvm

import mitsuba as mi  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "scenes", "lightguide", "lightguide.toml")


def mitsuba(xml, integrator, spp, out, batches=8):
    with open(xml) as f:
        text = f.read().replace('<integrator type="path">', f'<integrator type="{integrator}">')
    path = xml.replace(".xml", f"_{integrator}.xml")
    with open(path, "w") as f:
        f.write(text)
    scene = mi.load_file(path)
    t0 = time.time()
    ys = np.stack([np.array(mi.render(scene, seed=100 + k, spp=max(1, spp // batches)))[:, :, 1] * CIE_Y_CORRECTION
                   for k in range(batches)])
    write_exr(out, ys.mean(0).astype(np.float32), (ys.std(0, ddof=1) / np.sqrt(batches)).astype(np.float32))
    return time.time() - t0


def read(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        return ch["XYZ.Y"].pixels.astype(np.float64), ch["stderr.Y"].pixels.astype(np.float64)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", default="target/release/quasar")
    ap.add_argument("--out", default="target/lightguide-check")
    ap.add_argument("--size", type=int, default=64, help="image width and height")
    ap.add_argument("--spp", type=int, default=65536, help="samples per pixel of the three reference renders")
    ap.add_argument("--vismap-time", type=float, default=30.0, help="seconds of quasar vismap")
    ap.add_argument("--variant", default="llvm_ad_spectral")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    with open(SCENE) as f:
        text = f.read().replace('ior = "PMMA"', "ior = 1.49")
    scene = os.path.join(a.out, "lightguide-ior-1.49.toml")
    with open(scene, "w") as f:
        f.write(text)
    n = str(a.size)
    subprocess.run([a.quasar, "export-mitsuba", scene, "-o", os.path.join(a.out, "mitsuba"), "--width", n,
                    "--height", n, "--spp", "1"], check=True)
    mi.set_variant(a.variant)
    xml = os.path.join(a.out, "mitsuba", "scene.xml")
    images = {}
    for integrator in ("ptracer", "path"):
        out = os.path.join(a.out, f"mitsuba_{integrator}.exr")
        t = mitsuba(xml, integrator, a.spp, out)
        images[f"Mitsuba {integrator} ({a.spp} spp, {t:.0f} s)"] = read(out)
    common = [a.quasar, "render", scene, "--width", n, "--height", n, "--masking", "separable", "--quiet"]
    for method, budget in (("pt", ["--spp", str(a.spp)]), ("vismap", ["--time", str(a.vismap_time)])):
        out = os.path.join(a.out, f"quasar_{method}.exr")
        subprocess.run(common + ["--method", method, *budget, "-o", out], check=True)
        images[f"quasar {method} ({' '.join(budget)})"] = read(out)
    s = a.size / 64
    regions = {
        "reflector strip above the rod": (slice(int(14 * s), int(26 * s)), slice(int(8 * s), int(56 * s))),
        "housing beyond the rod's left end": (slice(0, a.size), slice(0, int(6 * s))),
        "whole image (ptracer: no specular views)": (slice(0, a.size), slice(0, a.size)),
    }
    print(f"| region ({a.size}x{a.size}) | " + " | ".join(images) + " |")
    print("|---" * (len(images) + 1) + "|")
    for name, (ys, xs) in regions.items():
        cells = []
        for y, se in images.values():
            m = y[ys, xs].mean()
            e = np.sqrt((se[ys, xs] ** 2).sum()) / se[ys, xs].size
            cells.append(f"{m:.5f} +- {e:.1g}")
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    sys.exit(main())
