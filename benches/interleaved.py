#!/usr/bin/env python3
"""Render time of several quasar binaries on one scene, runs interleaved (BENCHMARKS.md).

    python3 benches/interleaved.py --runs 5 scenes/glass-plate/glass-plate.toml OLD/quasar NEW/quasar

Every round renders the scene once with each binary, in turn; the fastest of `--runs` rounds
of each is reported with its samples per second and its speed-up over the first binary. On the
shared, noisy development machines the alternation and the best of several rounds make the
ratios (not the single figures) comparable. The time is the render loop's own clock
(`render_time_s` in the EXR header: loading and writing excluded). `--threads` (default 1)
and the method, size and budget flags are passed to every render.
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
    ap.add_argument("--threads", type=int, default=1)
    a = ap.parse_args()
    times = {b: [] for b in a.binaries}
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.exr")
        for _ in range(a.runs):
            for b in a.binaries:
                subprocess.run([b, "render", a.scene, "--method", a.method, "--spp", str(a.spp), "--width",
                                str(a.width), "--height", str(a.height), "--threads", str(a.threads),
                                "--masking", "separable", "--quiet", "-o", out], check=True)
                with open(out, "rb") as f:
                    times[b].append(float(re.search(rb"render_time_s *= *([0-9.]+)", f.read()).group(1)))
    base = min(times[a.binaries[0]])
    samples = a.width * a.height * a.spp
    for b in a.binaries:
        t = times[b]
        print(f"{b}: best {min(t):.3f} s, median {statistics.median(t):.3f} s, "
              f"{samples / min(t) / 1e6:.2f} M samples/s, {base / min(t):.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
