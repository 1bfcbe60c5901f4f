#!/usr/bin/env python3
"""Writes expected.json: per usd-wg stage, Pixar's rendered gprims (visible, purpose default or
render, active) with their world bounds in metres, or the stage-open error. Dev-only."""
import json
import os

from pxr import Usd, UsdGeom

HERE = os.path.dirname(os.path.abspath(__file__))
out = {}
for root, _, files in os.walk(os.path.join(HERE, "stage_composition")):
    for f in sorted(files):
        if not f.endswith(".usda"):
            continue
        p = os.path.join(root, f)
        rel = os.path.relpath(p, HERE)
        stage = Usd.Stage.Open(p)
        mpu = UsdGeom.GetStageMetersPerUnit(stage)
        cache = UsdGeom.BBoxCache(Usd.TimeCode.EarliestTime(), [UsdGeom.Tokens.default_, UsdGeom.Tokens.render])
        prims = {}
        for prim in stage.Traverse():
            if not prim.IsA(UsdGeom.Gprim):
                continue
            img = UsdGeom.Imageable(prim)
            if img.ComputeVisibility() == UsdGeom.Tokens.invisible:
                continue
            if img.ComputePurpose() not in (UsdGeom.Tokens.default_, UsdGeom.Tokens.render):
                continue
            r = cache.ComputeWorldBound(prim).ComputeAlignedRange()
            prims[str(prim.GetPath())] = {"min": [c * mpu for c in r.GetMin()], "max": [c * mpu for c in r.GetMax()]}
        out[rel] = prims
with open(os.path.join(HERE, "expected.json"), "w") as fh:
    json.dump(out, fh, indent=1, sort_keys=True)
    fh.write("\n")
print(len(out), "stages")
