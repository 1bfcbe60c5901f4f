#!/usr/bin/env python3
"""Render time of several quasar binaries on one scene, runs interleaved (BENCHMARKS.md).

    python3 benches/interleaved.py --runs 5 scenes/glass-plate/glass-plate.toml OLD/quasar NEW/quasar

Every round renders the scene once with each binary, in turn; the fastest of `--runs` rounds
of each is reported with its samples per second and its speed-up over the first binary. On the
shared, noisy development machines the alternation and the best of several rounds make the
ratios (not the single figures) comparable. The time is the render loop's own clock
(`render_time_s` in the EXR header: loading and writing excluded). The method, size and budget
flags are passed to every render. `--threads` (default 1) takes several counts: every round then
renders each binary at each count (`--threads 1,2`), and each line also gives the speed-up over the binary's
first count (thread scaling measured in the same alternation). `--phases` adds, for the
bidirectional methods, each phase's best seconds (the header's `time_share` times the render time).
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("binaries", nargs="+")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--method", default="pt")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel (iterations for bidirectional methods)")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=128)
    ap.add_argument("--threads", type=lambda v: [int(t) for t in v.split(",")], default=[1],
                    help="thread count, or several separated by commas (1,2)")
    ap.add_argument("--masking", default="separable", help="microfacet masking (the renders' --masking)")
    ap.add_argument("--max-depth", type=int, help="pt: at most this many scattering events (the first bounces' cost)")
    ap.add_argument("--phases", action="store_true", help="also each phase's best seconds (bidirectional methods)")
    a = ap.parse_args()
    runs = [(b, t) for b in a.binaries for t in a.threads]
    times = {r: [] for r in runs}
    phases = {r: {} for r in runs}
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.exr")
        depth = [] if a.max_depth is None else ["--max-depth", str(a.max_depth)]
        for _ in range(a.runs):
            for b, t in runs:
                subprocess.run([b, "render", a.scene, "--method", a.method, "--spp", str(a.spp), "--width",
                                str(a.width), "--height", str(a.height), "--threads", str(t),
                                "--masking", a.masking, "--quiet", "-o", out] + depth, check=True)
                with open(out, "rb") as f:
                    header = f.read()
                seconds = float(re.search(rb"render_time_s *= *([0-9.]+)", header).group(1))
                times[(b, t)].append(seconds)
                share = re.search(rb"time_share=([^\n]*)", header)
                for name, percent in re.findall(rb"(\w+) ([0-9.]+)%", share.group(1) if share else b""):
                    phases[(b, t)].setdefault(name.decode(), []).append(float(percent) / 100 * seconds)
    samples = a.width * a.height * a.spp
    for b, t in runs:
        best = min(times[(b, t)])
        line = (f"{b}, {t} thread{'s' if t > 1 else ''}: best {best:.3f} s, median {statistics.median(times[(b, t)]):.3f} s, "
                f"{samples / best / 1e6:.2f} M samples/s, {min(times[(a.binaries[0], t)]) / best:.2f}x")
        if len(a.threads) > 1:
            line += f", {min(times[(b, a.threads[0])]) / best:.2f}x of {a.threads[0]} thread(s)"
        if a.phases and phases[(b, t)]:
            line += "; phases (best s): " + ", ".join(f"{k} {min(v):.3f}" for k, v in phases[(b, t)].items())
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
