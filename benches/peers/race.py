#!/usr/bin/env python3
"""Equal-time race of quasar against Mitsuba 3 on the benchmark family (issues 15 and 47, BENCHMARKS.md).

The family (the default scene list): every scene of scenes/bench/ (written by
scenes/bench/make_family.py: glass plates with every bottom finish, top roughness and lamp, an
edge-lit light guide, glossy floors, a glass-sphere caustic, a reflector lamp, objects under a
sky), the shipped lightguide and its diffusing variant (which Mitsuba cannot express) and the
Cornell box (diffuse only).

For every scene, in one run on one machine:

1. `quasar export-mitsuba` writes the scene for Mitsuba with quasar's conventions (the same
   exporter as the cross-check, tests/crosscheck/); a scene Mitsuba cannot express (the
   lightguide: dispersive PMMA and a tabulated extraction face) races quasar's methods only.
2. The reference: Mitsuba (`--ref-variant`) at `--ref-spp`, in 8 batches whose spread gives the
   reference's own noise; for a scene Mitsuba cannot express, quasar `pt` at `--ref-spp`.
3. Mitsuba `path` renders for every budget in `--budgets` (seconds of rendering): its samples
   per second are measured on a warm run (the JIT's kernel compiled), then it renders
   rate x budget samples per pixel and the time it took is reported.
4. quasar renders every `--methods` entry with `--time BUDGET` (seconds of rendering, the loop's
   own clock; scene loading excluded as Mitsuba's is).
5. Every image's relMSE of the luminance Y against the reference, mean((y - r)^2 / (r^2 + 1e-3))
   (quasar compare's definition), less the reference's own expected contribution
   mean(se_r^2 / (r^2 + 1e-3)); samples per second; and the time to reach relMSE 0.01 and 0.003:
   interpolated (straight in log t, log relMSE) between the two budgets whose relMSE brackets
   the target, so give a ladder of budgets (`--budgets 1 2 4 8 16 32`); a target outside the
   ladder is extrapolated by relMSE ~ 1/t from the nearest budget (the rate of every unbiased
   method; not of progressive photon mapping, whose relMSE falls more slowly) and marked "~".
6. For every quasar image, the block z-test against the reference (`quasar compare --z-test`,
   both images' standard errors): "pass", or the share of failing blocks. A fast image that is
   biased beyond its own error bars does not count as having reached an error.

`--reuse-reference` keeps a scene's `reference.exr` from an earlier run of the same size and
reference settings (the reference takes minutes per scene); `--references-only` makes them and
stops. The end of the output is one summary table over the scenes (time to relMSE 0.01 of
Mitsuba, `pt` and `auto`, the ratios, the z-tests) and the worst narrow-BSDF scene.

Not part of CI (it takes minutes). Requires the Mitsuba venv of the cross-check:

    python3 -m venv target/mitsuba-venv
    target/mitsuba-venv/bin/pip install mitsuba==3.9.1 drjit==1.5.0 numpy OpenEXR
    cargo build --release
    target/mitsuba-venv/bin/python benches/peers/race.py --references-only
    target/mitsuba-venv/bin/python benches/peers/race.py --reuse-reference

The llvm variants need an LLVM shared library (Debian: `apt install libllvm19`; drjit finds
libLLVM through DRJIT_LIBLLVM_PATH when its name is not the default).
"""

import argparse
import os
import re
import shlex
import subprocess
import sys
import time

import numpy as np
import OpenEXR

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "crosscheck"))
# crosscheck also points drjit at Debian's libLLVM-19.so for the llvm variants
from crosscheck import CIE_Y_CORRECTION, write_exr  # noqa: E402

import mitsuba as mi  # noqa: E402

REL_EPS = 1e-3

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
FAMILY = sorted(
    os.path.relpath(os.path.join(ROOT, "scenes", "bench", f), ROOT)
    for f in os.listdir(os.path.join(ROOT, "scenes", "bench"))
    if f.endswith(".toml")
) + ["scenes/lightguide/lightguide.toml", "scenes/lightguide/lightguide-diffuser.toml",
     "scenes/cornell-box/cornell-box.toml"]
# Scenes whose reference Mitsuba's path tracer cannot make in minutes (its own relMSE at 65536
# spp: reflector-lamp 1.5e-2, guide-end-fed 3e-2): what makes it instead, with its samples per
# pixel (Mitsuba) or iterations (quasar). Mitsuba's particle tracer connects the bulb's light,
# mostly reflected by the dish, to the camera at every diffuse or glossy vertex: complete there
# (no specular surface). The light guides are seen through polished faces, which the particle
# tracer cannot connect through (its mean on guide-end-fed was 0.36 where the path tracer's is
# 0.62); their reference is quasar `quasi` at gather depth 0 and a 10-degree cone, a sibling of
# `auto`'s method and so not independent of it: its z-test against Mitsuba's path tracer (wide
# error bars) is printed with the reference.
REFERENCES = {
    "reflector-lamp": ("mitsuba", "ptracer", 16384),
    "guide-end-fed": ("quasar", "quasi", 16384),
    "lightguide": ("quasar", "quasi", 16384),
    "lightguide-diffuser": ("quasar", "quasi", 16384),
}
# Scenes of the family where no narrow lobe dominates: `auto` must match `pt` there, not beat
# Mitsuba by the narrow-BSDF margin.
NOT_NARROW = {"cornell-box", "sky-objects"}


def read_y(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        y = ch["XYZ.Y" if "XYZ.Y" in ch else "Y"].pixels.astype(np.float64)
        se = ch["stderr.Y"].pixels.astype(np.float64) if "stderr.Y" in ch else np.zeros_like(y)
    return y, se


def rel_mse(y, ref):
    return float(np.mean((y - ref) ** 2 / (ref ** 2 + REL_EPS)))


def mitsuba_render(scene, spp, seed):
    t0 = time.time()
    img = mi.render(scene, seed=seed, spp=spp)
    y = np.array(img)[:, :, 1].astype(np.float64) * CIE_Y_CORRECTION
    return y, time.time() - t0


def mitsuba_scene(d, integrator="path"):
    """The exported scene of folder `d`, with Mitsuba integrator `integrator`."""
    xml = os.path.join(d, "scene.xml")
    if integrator != "path":
        with open(xml) as f:
            text = f.read().replace('<integrator type="path">', f'<integrator type="{integrator}">')
        xml = os.path.join(d, f"scene_{integrator}.xml")
        with open(xml, "w") as f:
            f.write(text)
    return mi.load_file(xml)


def mitsuba_reference(scene, spp, batches=8):
    ys = [mitsuba_render(scene, max(1, spp // batches), 1000 + k)[0] for k in range(batches)]
    ys = np.stack(ys)
    return ys.mean(axis=0), ys.std(axis=0, ddof=1) / np.sqrt(batches)


def quasar_render(a, scene, out, method, budget=None, spp=None, seed=1):
    """Renders with `method`: a method name, optionally followed by render flags
    ("auto --photons-per-iteration 65536")."""
    words = shlex.split(method)
    cmd = [a.quasar, "render", scene, "--method", words[0], *words[1:], "--width", str(a.width),
           "--height", str(a.height), "--seed", str(seed), "--quiet", "-o", out]
    if a.masking_separable:
        cmd += ["--masking", "separable"]
    cmd += ["--time", str(budget)] if budget is not None else ["--spp", str(spp)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{p.stderr}")
    # the render's own clock and sample count, from the EXR header text (read while the file is open)
    meta = {}
    with OpenEXR.File(out) as f:
        for v in f.header().values():
            if isinstance(v, str) and "render_time_s" in v:
                for line in v.splitlines():
                    k, _, val = line.partition("=")
                    meta[k.strip()] = val.strip()
    y, _ = read_y(out)
    return y, float(meta.get("render_time_s", "nan")), meta.get("spp", meta.get("iterations", "?"))


def time_to(target, runs):
    """Time to reach relMSE `target` from `runs` [(budget, time, samples, relMSE)], and whether it
    was extrapolated: log-log interpolation between the first pair of consecutive budgets whose
    relMSE brackets the target, else relMSE ~ 1/t from the budget nearest to it."""
    pts = sorted((r[1], r[3]) for r in runs if r[1] > 0)
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e0 > 0 and e1 > 0 and e0 >= target >= e1:
            if e0 == e1:
                return t0, False
            s = np.log(target / e0) / np.log(e1 / e0)
            return float(np.exp(np.log(t0) + s * np.log(t1 / t0))), False
    good = [(t, e) for (t, e) in pts if e > 0]
    if not good:
        return float("nan"), True
    t, e = good[-1] if good[-1][1] > target else good[0]
    return t * e / target, True


def z_test(a, image, reference):
    """`quasar compare --z-test`: "pass", or the worst scale's failing block share."""
    p = subprocess.run([a.quasar, "compare", "--z-test", image, reference], capture_output=True, text=True)
    if p.returncode == 0:
        return "pass"
    shares = re.findall(r"\(([0-9.]+)%, limit", p.stdout)
    mean_z = re.search(r"\(z ([-+0-9.]+), limit", p.stdout)
    worst = max((float(x) for x in shares), default=0.0)
    return f"fail ({worst:.1f}% of blocks, mean z {mean_z.group(1) if mean_z else '?'})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", default="target/release/quasar")
    ap.add_argument("--out", default="target/peers")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=128)
    ap.add_argument("--budgets", type=float, nargs="+", default=[1.0, 3.0, 9.0, 27.0])
    ap.add_argument("--methods", nargs="+", default=["pt", "auto"],
                    help="quasar methods raced, each a name optionally followed by render flags, quoted")
    ap.add_argument("--variant", default="llvm_ad_spectral", help="Mitsuba variant raced ('none': quasar only)")
    ap.add_argument("--ref-variant", default="llvm_ad_spectral")
    ap.add_argument("--ref-spp", type=int, default=65536)
    ap.add_argument("--masking-separable", action="store_true", default=True,
                    help="quasar uses Mitsuba's GGX masking form (the default here, so both render one image)")
    ap.add_argument("--reuse-reference", action="store_true",
                    help="keep a scene's reference.exr of an earlier run (same size and reference settings)")
    ap.add_argument("--references-only", action="store_true", help="make the references and stop")
    ap.add_argument("scenes", nargs="*", default=FAMILY)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for scene_path in a.scenes:
        name = os.path.splitext(os.path.basename(scene_path))[0]
        d = os.path.join(a.out, name)
        os.makedirs(d, exist_ok=True)
        exp = subprocess.run([a.quasar, "export-mitsuba", scene_path, "-o", d, "--width", str(a.width),
                              "--height", str(a.height), "--spp", "1"], capture_output=True, text=True)
        expressible = exp.returncode == 0
        t0 = time.time()
        ref_path = os.path.join(d, "reference.exr")
        by, integrator, ref_spp = REFERENCES.get(name, ("mitsuba", "path", a.ref_spp))
        if by == "mitsuba" and not expressible:
            by, integrator = "quasar", "pt"
        if a.reuse_reference and os.path.exists(ref_path) and read_y(ref_path)[0].shape == (a.height, a.width):
            ref, ref_se = read_y(ref_path)
            ref_by = f"{by} {integrator} {ref_spp}, reused"
        elif by == "mitsuba":
            mi.set_variant(a.ref_variant)
            ref, ref_se = mitsuba_reference(mitsuba_scene(d, integrator), ref_spp)
            ref_by = f"Mitsuba {a.ref_variant} {integrator} {ref_spp} spp"
        else:
            if not expressible:
                reason = exp.stderr.strip().splitlines()[-1].split("cannot be written for Mitsuba: ")[-1]
                print(f"{name}: Mitsuba cannot render it ({reason}); quasar methods only", file=sys.stderr)
            quasar_render(a, scene_path, ref_path, f"{integrator} --gather-depth 0" if integrator == "quasi" else integrator,
                          spp=ref_spp, seed=999)
            ref, ref_se = read_y(ref_path)
            ref_by = f"quasar {integrator} {ref_spp}"
            if expressible:
                mi.set_variant(a.ref_variant)
                check, check_se = mitsuba_reference(mitsuba_scene(d), a.ref_spp)
                check_path = os.path.join(d, "reference_mitsuba_path.exr")
                write_exr(check_path, check.astype(np.float32), check_se.astype(np.float32))
                write_exr(ref_path, ref.astype(np.float32), ref_se.astype(np.float32))
                ref_by += f" (against Mitsuba path {a.ref_spp} spp: z-test {z_test(a, ref_path, check_path)})"
        write_exr(ref_path, ref.astype(np.float32), ref_se.astype(np.float32))
        floor = float(np.mean(ref_se ** 2 / (ref ** 2 + REL_EPS)))
        print(f"{name}: reference ({ref_by}) in {time.time() - t0:.0f} s, its own relMSE {floor:.2e}",
              file=sys.stderr)
        if a.references_only:
            continue
        results = {}
        if expressible and a.variant != "none":
            mi.set_variant(a.variant)
            scene = mi.load_file(os.path.join(d, "scene.xml"))
            mitsuba_render(scene, 4, 0)  # compiles the kernel
            _, tw = mitsuba_render(scene, 64, 1)
            rate = 64 / tw
            for b in a.budgets:
                spp = max(1, int(rate * b))
                y, t = mitsuba_render(scene, spp, 7)
                write_exr(os.path.join(d, f"mitsuba_{int(b)}s.exr"), y.astype(np.float32), np.zeros_like(y, np.float32))
                results.setdefault(f"Mitsuba path ({a.variant})", []).append((b, t, spp, rel_mse(y, ref) - floor, ""))
        for m in a.methods:
            for b in a.budgets:
                out = os.path.join(d, f"{re.sub('[^A-Za-z0-9]+', '_', m)}_{int(b)}s.exr")
                y, t, n = quasar_render(a, scene_path, out, m, budget=b)
                z = z_test(a, out, ref_path)
                results.setdefault(f"quasar {m}", []).append((b, t, n, rel_mse(y, ref) - floor, z))
        rows.append((name, ref_by, floor, results))
        print_scene(a, rows[-1])
    if rows:
        print_summary(rows)
    return 0


def print_summary(rows):
    """One line per scene: time to relMSE 0.01 of Mitsuba, quasar pt and quasar auto, auto's
    ratios to both, auto's z-test; then the worst narrow-BSDF scene."""
    print("\n### Summary: time to relMSE 0.01 (s; ~ extrapolated)\n")
    print("| scene | Mitsuba path | quasar pt | quasar auto | auto vs Mitsuba | auto vs pt | auto z-test |")
    print("|---|---|---|---|---|---|---|")
    worst = None
    for name, _, _, results in rows:
        def t(key):
            runs = next((v for k, v in results.items() if k.startswith(key)), None)
            return (None, False) if runs is None else time_to(0.01, runs)
        (tm, xm), (tp, xp), (ta, xa) = t("Mitsuba"), t("quasar pt"), t("quasar auto")
        cell = lambda v, x: "-" if v is None else f"{'~' * x}{v:.1f}"
        vs_m = tm / ta if tm and ta else None
        vs_p = tp / ta if tp and ta else None
        z = next((v for k, v in results.items() if k == "quasar auto"), [])
        zs = sorted({r[4] for r in z if r[4]})
        z = "pass" if zs == ["pass"] else "; ".join(zs)
        print(f"| {name} | {cell(tm, xm)} | {cell(tp, xp)} | {cell(ta, xa)} | "
              f"{'-' if vs_m is None else f'{vs_m:.2f}x'} | {'-' if vs_p is None else f'{vs_p:.2f}x'} | {z} |")
        if name not in NOT_NARROW and vs_m is not None and (worst is None or vs_m < worst[1]):
            worst = (name, vs_m)
    if worst:
        print(f"\nworst narrow-BSDF scene against Mitsuba: {worst[0]} ({worst[1]:.2f}x)")
    sys.stdout.flush()


def print_scene(a, row):
    name, ref_by, floor, results = row
    pixels = a.width * a.height
    print(f"\n### {name} ({a.width}x{a.height}; reference {ref_by}, its own relMSE {floor:.1e} subtracted)\n")
    base = results.get(next((k for k in results if k.startswith("Mitsuba")), ""), None)
    head = "| renderer | " + " | ".join(f"relMSE at {b:g} s (spp)" for b in a.budgets)
    print(head + " | samples/s | time to 0.01 | time to 0.003 | vs Mitsuba at 0.01 | z-test |")
    print("|---" * (len(a.budgets) + 6) + "|")
    for k, runs in results.items():
        cells = " | ".join(f"{e:.3g} ({n})" for (_, _, n, e, _) in runs)
        b, t, n, e, _ = runs[-1]
        try:
            sps = float(n) * pixels / t
            sps_s = f"{sps / 1e6:.2f} M"
        except ValueError:
            sps_s = "-"
        (t1, x1), (t3, x3) = time_to(0.01, runs), time_to(0.003, runs)
        ratio = ""
        if base is not None and t1 > 0:
            ratio = f"{time_to(0.01, base)[0] / t1:.2f}x"
        zs = sorted({z for (*_, z) in runs if z})
        z = "pass" if zs == ["pass"] else "; ".join(f"{b:g} s: {z}" for (b, _, _, _, z) in runs if z and z != "pass")
        print(f"| {k} | {cells} | {sps_s} | {'~' * x1}{t1:.1f} s | {'~' * x3}{t3:.1f} s | {ratio} | {z} |")
    sys.stdout.flush()


if __name__ == "__main__":
    sys.exit(main())
