#!/usr/bin/env python3
"""Independent cross-check of quasar's `pt` against Mitsuba 3 (docs/validation.md).

For every scene: `quasar export-mitsuba` writes it as a Mitsuba scene with quasar's conventions
(or says why Mitsuba cannot express it: the scene is then reported as skipped, with the reason);
Mitsuba renders it in `--batches` independent batches, whose per-pixel mean and standard error
of Y are written as an EXR (`XYZ.Y`, `stderr.Y`, quasar's names); quasar renders it with `pt`; and
`quasar compare --z-test` runs the block z-test of quasar's Y against Mitsuba's with both
images' standard errors. Exit status 1 when a scene fails, 0 otherwise.

Mitsuba's spectral XYZ film divides by its CIE Y integral 106.7502594 while its CIE table
integrates to 106.857 (the sum quasar divides by), so its Y is 0.100% high; it is corrected.
Mitsuba's rough conductors and dielectrics use Smith's separable masking-shadowing G1 G1, quasar
the height-correlated form by default: quasar renders with `--masking separable` here (the
default form is 0.5-0.7% brighter on the GGX alpha 0.3 test floors, which this check detects).
Mitsuba's `volpath` returns a rare NaN in scattering media (5 of 16 x 768 batch-pixels of
scattering-slab at 65,536 spp): such a batch is left out of that pixel's mean and error, and
the count is printed.

    python3 tests/crosscheck/crosscheck.py --quasar target/release/quasar --out /tmp/xc
"""

import argparse
import os
import re
import subprocess
import sys
import time

import numpy as np
import OpenEXR

# drjit looks for libLLVM.so (the llvm variants); Debian's libllvm19 installs it as libLLVM-19.so
for _llvm in ("/usr/lib/x86_64-linux-gnu/libLLVM-19.so", "/usr/lib/llvm-19/lib/libLLVM.so"):
    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(_llvm):
        os.environ["DRJIT_LIBLLVM_PATH"] = _llvm

import mitsuba as mi  # noqa: E402

CIE_Y_CORRECTION = 106.7502594 / 106.857

SCENES = [
    "scenes/cornell-box/cornell-box.toml",
    "scenes/glass-plate/glass-plate.toml",
    "scenes/glossy-room/glossy-room.toml",
    "scenes/lightguide/lightguide.toml",
    "scenes/material-library/material-library.toml",
    "scenes/gltf-showcase/showcase.toml",
    "scenes/tests/narrow-sun.toml",
    "scenes/tests/narrow-point.toml",
    "scenes/tests/facing-mirrors.toml",
    "scenes/tests/glossy-chain.toml",
    "scenes/tests/glossy-area.toml",
    "scenes/tests/glossy-point.toml",
    "scenes/tests/glossy-spot.toml",
    "scenes/tests/glossy-directional.toml",
    "scenes/tests/glossy-environment.toml",
    "scenes/tests/tinted-glass.toml",
    "scenes/tests/absorbing-glass.toml",
    "scenes/tests/scattering-slab.toml",
    "scenes/tests/absorbing-rod.toml",
    "scenes/tests/coated-plastic.toml",
]


def render_mitsuba(xml, spp, batches):
    scene = mi.load_file(xml)
    per = max(1, spp // batches)
    ys = []
    for k in range(batches):
        img = np.array(mi.render(scene, seed=k, spp=per))
        ys.append(img[:, :, 1] * CIE_Y_CORRECTION)
    ys = np.stack(ys)
    # Mitsuba 3.9's volpath leaves a rare NaN (a scattering medium at 65,536 spp: 2 batch-pixels
    # of 16 x 768); a batch is dropped from the pixel it poisons, and the count is reported
    bad = ~np.isfinite(ys)
    if bad.any():
        print(f"{xml}: {int(bad.sum())} non-finite batch-pixels of Mitsuba dropped", file=sys.stderr)
    n = (~bad).sum(axis=0)
    mean = np.nanmean(np.where(bad, np.nan, ys), axis=0)
    stderr = np.nanstd(np.where(bad, np.nan, ys), axis=0, ddof=1) / np.sqrt(n)
    return mean.astype(np.float32), stderr.astype(np.float32), per * batches


def write_exr(path, y, stderr):
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    OpenEXR.File(header, {"XYZ.Y": y, "stderr.Y": stderr}).write(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", default="target/release/quasar")
    ap.add_argument("--out", default="target/crosscheck")
    ap.add_argument("--width", type=int, default=32)
    ap.add_argument("--height", type=int, default=24)
    ap.add_argument("--spp", type=int, default=4096, help="samples per pixel of each renderer")
    ap.add_argument("--batches", type=int, default=16, help="independent Mitsuba renders")
    ap.add_argument("--variant", default="scalar_spectral")
    ap.add_argument("scenes", nargs="*", default=SCENES)
    a = ap.parse_args()
    mi.set_variant(a.variant)
    os.makedirs(a.out, exist_ok=True)
    rows, failed = [], False
    for scene in a.scenes:
        name = os.path.splitext(os.path.basename(scene))[0]
        d = os.path.join(a.out, name)
        exp = subprocess.run(
            [a.quasar, "export-mitsuba", scene, "-o", d, "--width", str(a.width), "--height", str(a.height),
             "--spp", str(a.spp)], capture_output=True, text=True)
        if exp.returncode != 0:
            reason = exp.stderr.strip().splitlines()[-1].split("cannot be written for Mitsuba: ")[-1]
            rows.append((name, "skipped", reason))
            continue
        t0 = time.time()
        y, se, spp = render_mitsuba(os.path.join(d, "scene.xml"), a.spp, a.batches)
        tm = time.time() - t0
        write_exr(os.path.join(d, "mitsuba.exr"), y, se)
        t0 = time.time()
        subprocess.run([a.quasar, "render", scene, "--method", "pt", "--spp", str(spp), "--width", str(a.width),
                        "--height", str(a.height), "--seed", "1", "--masking", "separable", "--quiet",
                        "-o", os.path.join(d, "quasar.exr")], check=True)
        tq = time.time() - t0
        cmp = subprocess.run([a.quasar, "compare", os.path.join(d, "quasar.exr"), os.path.join(d, "mitsuba.exr"),
                              "--z-test"], capture_output=True, text=True)
        report = cmp.stdout[cmp.stdout.find("block z-test"):]
        m = re.search(r"image mean ratio ([0-9.]+) \+- ([0-9.]+) \(z ([-+0-9.]+)", report)
        worst = max((float(x) for x in re.findall(r"\(([0-9.]+)%, limit", report)), default=0.0)
        status = "passed" if cmp.returncode == 0 else "FAILED"
        failed |= cmp.returncode != 0
        detail = (f"quasar/Mitsuba mean {m.group(1)} +- {m.group(2)} (z {m.group(3)}), "
                  f"largest share of blocks with |z| > 4.5: {worst:.1f}%, {spp} spp each, "
                  f"Mitsuba {tm:.1f} s, quasar {tq:.1f} s")
        rows.append((name, status, detail))
        if cmp.returncode != 0:
            print(f"{name}:\n{report}", file=sys.stderr)
    print(f"| scene ({a.width}x{a.height}, {a.variant}) | result | detail |")
    print("|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]} |")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
