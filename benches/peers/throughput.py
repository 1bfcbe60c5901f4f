#!/usr/bin/env python3
"""Samples per second of quasar `pt` against Mitsuba 3's `path` on the same scenes, in one run
(issue 15's first target; BENCHMARKS.md).

For every scene: `quasar export-mitsuba` writes it for Mitsuba (as the race and the cross-check
do); Mitsuba renders it once to compile its kernel; then `--rounds` rounds alternate a Mitsuba
render and a quasar render of `--spp` samples per pixel (quasar with `--masking separable`,
Mitsuba's GGX form, so both render one image), and the fastest round of each gives its samples
per second. The machines these run on are shared and noisy: the alternation and the best of
several rounds keep the ratio, which is what counts, from depending on when a renderer ran.
Mitsuba's time is `mi.render` with the result evaluated (its scene loading and kernel
compilation excluded); quasar's is its render loop's own clock (`render_time_s` in the EXR
header: scene loading excluded). Both use every core unless `--threads` is given. Both trace
the same paths on average: Mitsuba's `rr_depth` is set to quasar `pt`'s (Russian roulette from
the third scattering event, with the same survival probability min(max(beta) eta^2, 0.95));
Mitsuba's own default, 5, makes its paths in closed scenes longer (`--rr-depth 5`).
`--variant` takes several Mitsuba variants separated by commas (`llvm_ad_spectral,scalar_spectral`:
the vectorised and the scalar backend); every round then renders each of them.
`--llvm-target CPU:FEATURES:WIDTH` (for example `haswell:+avx2,+fma:4`) makes Dr.Jit's LLVM
backend compile for that CPU, instruction-set features and number of lanes instead of the host's
(here `skylake-avx512`, 16 lanes), through `jit_llvm_set_target` of `libdrjit-core.so` (a C++
symbol, called with ctypes; Dr.Jit 1.5): how much of Mitsuba's speed comes from its lanes and
how much from the instruction set. `--quasar` likewise takes several quasar binaries separated
by commas (`target/release/quasar,target/pgo/quasar`: the release build and the PGO build of
`scripts/build-pgo.sh`), each rendered in every round. `--max-depth N` limits both renderers to N
scattering events (quasar's `--max-depth N`, Mitsuba's `max_depth` N + 1, since Mitsuba counts
the vertices of a path), so that the camera ray and the first bounces can be compared on their
own (BENCHMARKS.md "Eighth engine round").

Not part of CI (minutes). Requires the Mitsuba venv of the cross-check:

    target/mitsuba-venv/bin/python benches/peers/throughput.py --spp 256 --rounds 5
"""

import argparse
import ctypes
import os
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "crosscheck"))
import crosscheck  # noqa: E402,F401  (points drjit at Debian's libLLVM-19)

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

SCENES = ["scenes/cornell-box/cornell-box.toml", "scenes/glass-plate/glass-plate.toml",
          "scenes/glossy-room/glossy-room.toml"]


def mitsuba_seconds(scene, spp, seed):
    t0 = time.perf_counter()
    img = mi.render(scene, seed=seed, spp=spp)
    dr.eval(img)
    dr.sync_thread()
    return time.perf_counter() - t0


def set_llvm_target(variants, target):
    """Dr.Jit's LLVM backend compiles for `target` = CPU:FEATURES:WIDTH from now on."""
    cpu, features, width = target.split(":")
    llvm = [v for v in variants if v.startswith("llvm")]
    assert llvm, "--llvm-target needs an llvm variant"
    mi.set_variant(llvm[0])  # initialises the LLVM backend
    lib = ctypes.CDLL(os.path.join(os.path.dirname(dr.__file__), "libdrjit-core.so"))
    set_target = lib._Z19jit_llvm_set_targetPKcS0_j  # jit_llvm_set_target(const char*, const char*, uint32_t)
    set_target.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32]
    set_target(cpu.encode(), features.encode(), int(width))
    vector_width = lib._Z21jit_llvm_vector_widthv
    vector_width.restype = ctypes.c_uint32
    assert vector_width() == int(width), f"Dr.Jit kept {vector_width()} lanes"
    print(f"Dr.Jit LLVM target: cpu {cpu}, features {features}, {vector_width()} lanes")


def quasar_seconds(a, binary, scene_path, spp, seed, out):
    cmd = [binary, "render", scene_path, "--method", "pt", "--width", str(a.width), "--height", str(a.height),
           "--spp", str(spp), "--seed", str(seed), "--masking", "separable", "--quiet", "-o", out]
    if a.threads:
        cmd += ["--threads", str(a.threads)]
    if a.max_depth is not None:
        cmd += ["--max-depth", str(a.max_depth)]
    subprocess.run(cmd, check=True)
    with open(out, "rb") as f:
        return float(re.search(rb"render_time_s *= *([0-9.]+)", f.read()).group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", type=lambda v: v.split(","), default=["target/release/quasar"],
                    help="quasar binary, or several separated by commas")
    ap.add_argument("--variant", type=lambda v: v.split(","), default=["llvm_ad_spectral"],
                    help="Mitsuba variant, or several separated by commas")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=128)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--threads", type=int, default=0, help="quasar worker threads (0: all cores, as Mitsuba)")
    ap.add_argument("--rr-depth", type=int, default=3,
                    help="Mitsuba's rr_depth (3: quasar pt's; 5: Mitsuba's default)")
    ap.add_argument("--max-depth", type=int,
                    help="at most this many scattering events per path (quasar's --max-depth; Mitsuba's "
                    "max_depth counts vertices and is set to one more): the cost of the first bounces alone")
    ap.add_argument("--llvm-target", help="CPU:FEATURES:WIDTH of Dr.Jit's LLVM backend (default: the host's)")
    ap.add_argument("scenes", nargs="*", default=SCENES)
    a = ap.parse_args()
    if a.llvm_target:
        set_llvm_target(a.variant, a.llvm_target)
    pixels = a.width * a.height
    head = " | ".join(f"Mitsuba {v} (rr_depth {a.rr_depth}) samples/s" for v in a.variant)
    quasars = " | ".join(f"{b} pt samples/s" for b in a.quasar)
    ratios = " | ".join(f"{b} / {v}" for b in a.quasar for v in a.variant)
    print(f"| scene | {head} | {quasars} | {ratios} |")
    print("|---|" + "---|" * ((len(a.variant) + 1) * (len(a.quasar) + 1) - 1))
    with tempfile.TemporaryDirectory() as d:
        for scene_path in a.scenes:
            name = os.path.splitext(os.path.basename(scene_path))[0]
            xml_dir = os.path.join(d, name)
            subprocess.run([a.quasar[0], "export-mitsuba", scene_path, "-o", xml_dir, "--width", str(a.width),
                            "--height", str(a.height), "--spp", "1"], check=True, capture_output=True)
            xml = os.path.join(xml_dir, "scene.xml")
            with open(xml) as f:
                text = f.read()
            integrator = '<integrator type="path">'
            assert integrator in text, "the exported scene has no path integrator"
            extra = f'<integer name="rr_depth" value="{a.rr_depth}"/>'
            if a.max_depth is not None:
                unbounded = '<integer name="max_depth" value="-1"/>'
                assert unbounded in text, "the exported scene's path integrator is not unbounded"
                text = text.replace(unbounded, f'<integer name="max_depth" value="{a.max_depth + 1}"/>', 1)
            text = text.replace(integrator, integrator + extra, 1)
            with open(xml, "w") as f:
                f.write(text)
            scenes = {}
            for v in a.variant:
                mi.set_variant(v)
                scenes[v] = mi.load_file(xml)
                mitsuba_seconds(scenes[v], 4, 0)  # compiles the kernel
            m, q = {v: [] for v in a.variant}, {b: [] for b in a.quasar}
            for r in range(a.rounds):
                for v in a.variant:
                    mi.set_variant(v)
                    m[v].append(mitsuba_seconds(scenes[v], a.spp, 1 + r))
                for b in a.quasar:
                    q[b].append(quasar_seconds(a, b, scene_path, a.spp, 1 + r, os.path.join(d, f"{name}.exr")))
            sm = {v: pixels * a.spp / min(t) for v, t in m.items()}
            sq = {b: pixels * a.spp / min(t) for b, t in q.items()}
            rates = " | ".join(f"{sm[v] / 1e6:.2f} M" for v in a.variant)
            qrates = " | ".join(f"{sq[b] / 1e6:.2f} M" for b in a.quasar)
            ratio = " | ".join(f"{sq[b] / sm[v]:.2f}x" for b in a.quasar for v in a.variant)
            print(f"| {name} | {rates} | {qrates} | {ratio} |")
            sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
