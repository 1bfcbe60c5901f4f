#!/usr/bin/env python3
"""Independent check of quasar's Cryptomatte output (`--aov crypto_object,crypto_material`, README).

quasar renders the shipped Cornell box with both Cryptomatte layers and the object ids;
OpenImageIO (PyPI `OpenImageIO`) reads the EXR, and a decoder of the public Cryptomatte
specification written here (its own MurmurHash3_x86_32, not quasar's) must find: for each layer,
the header entries `cryptomatte/<key>/name|hash|conversion|manifest` with `<key>` the first 7 hex
digits of the hash of the layer's name; a manifest whose every id is the specification's float
conversion of its name's hash; rank channels `<layer>00..02.RGBA` whose ids are all in the
manifest and whose coverages sum to at most 1 per pixel, to 1 away from the pixels whose centre
ray misses the box (`depth.Z` infinite) and to less where it misses;
per pixel, the object whose matte is larger than one half is the one quasar's `object_id` names.
Exit status 1 on a failure.

    python3 tests/crosscheck/cryptomatte.py --quasar target/release/quasar --out /tmp/xc
"""

import argparse
import json
import os
import struct
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio


def murmur3_32(data: bytes, seed: int = 0) -> int:
    """MurmurHash3_x86_32 (Appleby), as the Cryptomatte specification names it."""
    c1, c2, mask = 0xCC9E2D51, 0x1B873593, 0xFFFFFFFF
    rotl = lambda x, r: ((x << r) | (x >> (32 - r))) & mask  # noqa: E731
    h = seed
    blocks = len(data) // 4
    for i in range(blocks):
        k = struct.unpack_from("<I", data, 4 * i)[0]
        k = rotl((k * c1) & mask, 15) * c2 & mask
        h = (rotl(h ^ k, 13) * 5 + 0xE6546B64) & mask
    tail, k = data[4 * blocks:], 0
    for i in reversed(range(len(tail))):
        k = (k << 8) | tail[i]
    if tail:
        h ^= rotl((k * c1) & mask, 15) * c2 & mask
    h ^= len(data)
    h ^= h >> 16
    h = (h * 0x85EBCA6B) & mask
    h ^= h >> 13
    h = (h * 0xC2B2AE35) & mask
    return h ^ (h >> 16)


def name_to_id_bits(name: str) -> int:
    """The specification's float conversion: the hash with bit 23 flipped where the exponent is 0 or 255."""
    h = murmur3_32(name.encode("utf-8"))
    exponent = (h >> 23) & 0xFF
    return h ^ (1 << 23) if exponent in (0, 255) else h


def bits(values: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=np.float32).view(np.uint32)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    exr = os.path.join(args.out, "cornell-cryptomatte.exr")
    subprocess.run(
        [args.quasar, "render", "scenes/cornell-box/cornell-box.toml", "-o", exr, "--width", "48", "--height", "48",
         "--spp", "1", "--method", "pt", "--aov", "crypto_object,crypto_material,object_id", "--aov-samples", "64",
         "--quiet"],
        check=True,
    )
    inp = oiio.ImageInput.open(exr)
    if inp is None:
        print("FAIL: OpenImageIO cannot open", exr, oiio.geterror())
        return 1
    spec = inp.spec()
    pixels = np.asarray(inp.read_image(format=oiio.FLOAT), dtype=np.float32)
    inp.close()
    names = list(spec.channelnames)
    channel = {n: pixels[..., i] for i, n in enumerate(names)}
    attrs = {a.name: a.value for a in spec.extra_attribs}
    failures = []
    layers = {}
    for key, value in attrs.items():
        parts = key.split("/")
        if len(parts) == 3 and parts[0] == "cryptomatte":
            layers.setdefault(parts[1], {})[parts[2]] = value
    found = sorted(entries.get("name", "?") for entries in layers.values())
    if found != ["CryptoMaterial", "CryptoObject"]:
        failures.append(f"Cryptomatte layers in the header: {found}")
    mattes = {}
    for key, entries in layers.items():
        layer = entries.get("name", "")
        if key != f"{murmur3_32(layer.encode()):08x}"[:7]:
            failures.append(f"{layer}: key {key} is not the first 7 hex digits of the name's hash")
        if entries.get("hash") != "MurmurHash3_32" or entries.get("conversion") != "uint32_to_float32":
            failures.append(f"{layer}: hash {entries.get('hash')}, conversion {entries.get('conversion')}")
        manifest = json.loads(entries.get("manifest", "{}"))
        for name, hexid in manifest.items():
            if int(hexid, 16) != name_to_id_bits(name):
                failures.append(f"{layer}: manifest id {hexid} of {name!r} is not the specification's")
        ranks = sorted({n.rsplit(".", 1)[0] for n in names if n.startswith(layer) and n[len(layer):len(layer) + 2].isdigit()})
        if ranks != [f"{layer}{i:02}" for i in range(3)]:
            failures.append(f"{layer}: rank layers {ranks}")
            continue
        ids = [bits(channel[f"{r}.{c}"]) for r in ranks for c in "RB"]
        coverage = [channel[f"{r}.{c}"] for r in ranks for c in "GA"]
        total = sum(coverage)
        known = np.zeros(total.shape, dtype=bool)
        layer_mattes = {}
        for name in manifest:
            target = name_to_id_bits(name)
            matte = sum(np.where(i == target, c, 0.0) for i, c in zip(ids, coverage))
            layer_mattes[name] = matte
            known |= np.any([(i == target) & (c > 0) for i, c in zip(ids, coverage)], axis=0)
        unknown = sum(np.sum((c > 0) & ~np.isin(i, [name_to_id_bits(n) for n in manifest])) for i, c in zip(ids, coverage))
        if unknown:
            failures.append(f"{layer}: {unknown} ranks hold ids the manifest does not list")
        if total.max() > 1.0 + 1e-5:
            failures.append(f"{layer}: coverages sum to {total.max()} in a pixel")
        # the coverages sum to 1 unless some of the pixel's rays miss the box (its camera sees
        # past the walls in places): then the pixel-centre ray of the pixel or of a neighbour
        # misses (depth.Z is +inf), and where the centre ray misses the sum is below 1
        miss = np.isinf(channel["depth.Z"])
        near_miss = np.zeros_like(miss)
        h, w = miss.shape
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                near_miss[max(dy, 0):h + min(dy, 0), max(dx, 0):w + min(dx, 0)] |= \
                    miss[max(-dy, 0):h + min(-dy, 0), max(-dx, 0):w + min(-dx, 0)]
        partial = np.abs(total - 1.0) > 1e-5
        if np.any(partial & ~near_miss):
            failures.append(f"{layer}: {np.sum(partial & ~near_miss)} pixels away from any miss have coverages not summing to 1")
        if np.any(miss & ~partial):
            failures.append(f"{layer}: {np.sum(miss & ~partial)} pixels whose centre ray misses have full coverage")
        full = np.mean(~partial)
        mattes[layer] = layer_mattes
        print(f"{layer}: {len(manifest)} names, coverage sums to 1 in {100 * full:.1f}% of the pixels")
    object_ids = json.loads(attrs.get("quasar:object_ids", "{}"))
    if "CryptoObject" in mattes and object_ids:
        ids = channel["object_id.Y"]
        checked = 0
        for name, matte in mattes["CryptoObject"].items():
            mine = [float(k) for k, v in object_ids.items() if v == name]
            majority = matte > 0.5
            checked += int(majority.sum())
            if not mine or np.any(ids[majority] != mine[0]):
                failures.append(f"object_id disagrees with the Cryptomatte of {name!r}")
        print(f"object_id agrees with the Cryptomatte majority in {checked} pixels")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
