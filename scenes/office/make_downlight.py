#!/usr/bin/env python3
"""Writes downlight.ies: a synthetic recessed downlight for the office scene (no manufacturer
data; written for quasar): I(C, g) = I0 cos(g / w(C))^1.5 (1 - (g / 75)^8) below 75 degrees, 0
beyond, with w(C) = 1 + 0.1 cos^2 C (the beam 10% wider along C0), I0 scaled so that the table
integrates to 2000 lm; quadrant-symmetric (C 0..90 every 15 degrees), gamma 0..90 every 2.5."""
import math

GS = [g * 2.5 for g in range(0, 37)]
CS = [c * 15 for c in range(0, 7)]


def rel(c, g):
    if g >= 75:
        return 0.0
    w = 1.0 + 0.1 * math.cos(math.radians(c)) ** 2
    return math.cos(math.radians(g / w)) ** 1.5 * (1 - (g / 75.0) ** 8)


def flux_of_rel():
    n, m, s = 400, 360, 0.0
    for i in range(n):
        g = (i + 0.5) * 90 / n
        for j in range(m):
            c = (j + 0.5) * 360 / m
            cq = c % 180
            cq = 180 - cq if cq > 90 else cq
            s += rel(cq, g) * math.sin(math.radians(g))
    return s * math.radians(90 / n) * math.radians(360 / m)


i0 = 2000.0 / flux_of_rel()
lines = ["IESNA:LM-63-2002", "[TEST] quasar scenes/office (synthetic, written for quasar; no manufacturer data)",
         "[MANUFAC] quasar example", "[LUMCAT] DL-2000", "[LUMINAIRE] recessed downlight, 2000 lm, 75 deg cut-off",
         "[LAMP] LED module 2000 lm", "TILT=NONE",
         f"1 2000 1 {len(GS)} {len(CS)} 1 2 0.15 0.15 0", "1 1 22",
         " ".join(f"{g:g}" for g in GS), " ".join(str(c) for c in CS)]
for c in CS:
    lines.append(" ".join(f"{i0 * rel(c, g):.2f}" for g in GS))
with open("downlight.ies", "w") as f:
    f.write("\n".join(lines) + "\n")
