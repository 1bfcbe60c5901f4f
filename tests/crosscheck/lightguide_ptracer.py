#!/usr/bin/env python3
"""Which renderer is right where quasar's photon methods and its path tracer disagree on the
lightguide (BENCHMARKS.md, issue 15)?

The shipped lightguide's PMMA is dispersive, which Mitsuba cannot express, and absorbs, which
Mitsuba's particle tracer does not simulate (media are checked against Mitsuba's `volpath` by
crosscheck.py's absorbing-rod and scattering-slab scenes), so this check renders a copy with a
constant index of refraction (1.49) and no absorption in four renderers:

- Mitsuba `ptracer` (a particle tracer: light paths connected to the camera at every diffuse
  vertex; it carries light through the rod as easily as photons do, but it cannot show what the
  camera sees through a specular surface, so it is a reference for diffuse regions only);
- Mitsuba `path`, quasar `pt` (path tracers: they reach the LEDs behind the rod's polished ends
  only by BSDF sampling, so their errors there are heavy-tailed);
- quasar `vismap` (photons gathered at the first non-specular vertex);

and prints each one's mean Y and standard error over image regions: the reflector strip above
the rod (lit by light leaving the rod's back face), the housing beyond the rod's left end, and
the whole image.

With `--check` (the CI step, `.ci/run`) it renders the particle tracer and quasar's photon
methods (`--check-methods`, fixed iteration counts) only, and fails (exit 1) when a method's mean
over a region differs from the particle tracer's by more than 4 combined standard errors.

    target/mitsuba-venv/bin/python tests/crosscheck/lightguide_ptracer.py --spp 65536 --vismap-time 30
    target/mitsuba-venv/bin/python tests/crosscheck/lightguide_ptracer.py --check --size 32 --spp 8192 \
        --variant scalar_spectral
"""

import argparse
import os
import shlex
import subprocess
import sys
import time

import numpy as np
import OpenEXR

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from crosscheck import render_mitsuba, write_exr  # noqa: E402 (it finds libLLVM for the llvm variants)

import mitsuba as mi  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "scenes", "lightguide", "lightguide.toml")
Z_LIMIT = 4.0


def mitsuba(xml, integrator, spp, out, batches=8):
    """Mitsuba's `integrator` on the exported scene `xml`, in `batches` independent batches
    (crosscheck's `render_mitsuba`), written to `out`; returns the seconds it took."""
    with open(xml) as f:
        text = f.read().replace('<integrator type="path">', f'<integrator type="{integrator}">')
    path = xml.replace(".xml", f"_{integrator}.xml")
    with open(path, "w") as f:
        f.write(text)
    t0 = time.time()
    y, se, _ = render_mitsuba(path, spp, batches)
    write_exr(out, y, se)
    return time.time() - t0


def read(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        return ch["XYZ.Y"].pixels.astype(np.float64), ch["stderr.Y"].pixels.astype(np.float64)


def region_mean(image, ys, xs):
    y, se = image
    return y[ys, xs].mean(), np.sqrt((se[ys, xs] ** 2).sum()) / se[ys, xs].size


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", default="target/release/quasar")
    ap.add_argument("--out", default="target/lightguide-check")
    ap.add_argument("--size", type=int, default=64, help="image width and height")
    ap.add_argument("--spp", type=int, default=65536, help="samples per pixel of the reference renders")
    ap.add_argument("--vismap-time", type=float, default=30.0, help="seconds of quasar vismap")
    ap.add_argument("--variant", default="llvm_ad_spectral")
    ap.add_argument("--check", action="store_true", help="compare photon methods with the particle tracer; exit 1 on a difference")
    ap.add_argument("--check-methods", nargs="+", default=["vismap", "auto"],
                    help="quasar methods checked, each a name optionally followed by render flags, quoted")
    ap.add_argument("--iterations", type=int, default=1024, help="iterations of each checked method")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    with open(SCENE) as f:
        text = f.read().replace('ior = "PMMA"', "ior = 1.49").replace('absorption = "PMMA"\n', "")
    scene = os.path.join(a.out, "lightguide-ior-1.49.toml")
    with open(scene, "w") as f:
        f.write(text)
    n = str(a.size)
    subprocess.run([a.quasar, "export-mitsuba", scene, "-o", os.path.join(a.out, "mitsuba"), "--width", n,
                    "--height", n, "--spp", "1"], check=True)
    mi.set_variant(a.variant)
    xml = os.path.join(a.out, "mitsuba", "scene.xml")
    images = {}
    for integrator in ("ptracer",) if a.check else ("ptracer", "path"):
        out = os.path.join(a.out, f"mitsuba_{integrator}.exr")
        t = mitsuba(xml, integrator, a.spp, out)
        images[f"Mitsuba {integrator} ({a.spp} spp, {t:.0f} s)"] = read(out)
    common = [a.quasar, "render", scene, "--width", n, "--height", n, "--masking", "separable", "--quiet"]
    if a.check:
        # an entry may carry its own flags ("pt --spp 2048"); otherwise it runs --iterations
        runs = [(w[0], (w[1:] or ["--iterations", str(a.iterations)]) + ["--seed", "3"])
                for w in map(shlex.split, a.check_methods)]
    else:
        runs = [("pt", ["--spp", str(a.spp)]), ("vismap", ["--time", str(a.vismap_time)])]
    for method, budget in runs:
        out = os.path.join(a.out, f"quasar_{method}.exr")
        t0 = time.time()
        subprocess.run(common + ["--method", method, *budget, "-o", out], check=True)
        images[f"quasar {method} ({' '.join(budget)}, {time.time() - t0:.0f} s)"] = read(out)
    s = a.size / 64
    regions = {
        "reflector strip above the rod": (slice(int(14 * s), int(26 * s)), slice(int(8 * s), int(56 * s))),
        "housing beyond the rod's left end": (slice(0, a.size), slice(0, int(6 * s))),
    }
    if not a.check:
        regions["whole image (ptracer: no specular views)"] = (slice(0, a.size), slice(0, a.size))
    print(f"| region ({a.size}x{a.size}) | " + " | ".join(images) + " |")
    print("|---" * (len(images) + 1) + "|")
    failed = False
    reference = next(iter(images.values()))
    for name, (ys, xs) in regions.items():
        cells = []
        r, re_ = region_mean(reference, ys, xs)
        for label, image in images.items():
            m, e = region_mean(image, ys, xs)
            cell = f"{m:.5f} +- {e:.1g}"
            if a.check and image is not reference:
                z = (m - r) / np.sqrt(e ** 2 + re_ ** 2)
                cell += f" (z {z:+.2f})"
                if not abs(z) <= Z_LIMIT:
                    failed = True
                    print(f"{label} differs from the particle tracer in the {name}: z {z:+.2f}", file=sys.stderr)
            cells.append(cell)
        print(f"| {name} | " + " | ".join(cells) + " |")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
