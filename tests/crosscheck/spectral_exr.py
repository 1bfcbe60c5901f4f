#!/usr/bin/env python3
"""Independent check of quasar's spectral EXR output (`--spectral-bins`, docs/photometry.md).

quasar renders the shipped Cornell box with 94 bins of 5 nm, which it writes to
`<stem>.spectral.exr` beside the image; colour-science's reader of the layout of Fichet et al. 2021
(`colour.io.read_spectral_image_Fichet2021`, over OpenImageIO) must read that file as an emissive, unpolarised spectral image with the bin centres as its wavelengths, and
the luminance computed from its spectra with colour-science's own CIE 1931 2-degree table,
Y = sum_b L_b ybar(lambda_b) d / integral(ybar), must equal quasar's `XYZ.Y` to 0.2% over the
image (5 nm bins leave about 0.01%), and its `XYZ.Y` must be the image's own. Exit status 1 on a
failure.

    python3 tests/crosscheck/spectral_exr.py --quasar target/release/quasar --out /tmp/xc
"""

import argparse
import os
import subprocess
import sys
import warnings

import numpy as np
import OpenEXR

warnings.filterwarnings("ignore")  # colour-science warns about its optional packages
import colour  # noqa: E402
from colour.io import read_spectral_image_Fichet2021  # noqa: E402

BINS, LO, HI = 94, 360.0, 830.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quasar", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    exr = os.path.join(args.out, "cornell-spectral.exr")
    subprocess.run(
        [args.quasar, "render", "scenes/cornell-box/cornell-box.toml", "-o", exr, "--width", "32",
         "--height", "32", "--spp", "64", "--spectral-bins", str(BINS), "--quiet"],
        check=True,
    )
    spectral_exr = os.path.join(args.out, "cornell-spectral.spectral.exr")
    components, spec = read_spectral_image_Fichet2021(spectral_exr, additional_data=True)
    failures = []
    if not spec.is_emissive or spec.is_polarised:
        failures.append(f"read as emissive={spec.is_emissive}, polarised={spec.is_polarised}")
    wavelengths, image = components["S0"]
    wavelengths, image = np.asarray(wavelengths, float), np.asarray(image, float)
    d = (HI - LO) / BINS
    centres = LO + (np.arange(BINS) + 0.5) * d
    if wavelengths.shape != centres.shape or np.abs(wavelengths - centres).max() > 1e-6:
        failures.append(f"wavelengths {wavelengths[:3]}... are not the bin centres {centres[:3]}...")
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    ybar = np.interp(wavelengths, cmfs.wavelengths, cmfs.values[:, 1])
    y_spectral = (image * ybar).sum(axis=-1) * d / np.trapezoid(cmfs.values[:, 1], cmfs.wavelengths)
    y_film = np.asarray(OpenEXR.File(exr).channels()["XYZ.Y"].pixels, float)
    y_beside = np.asarray(OpenEXR.File(spectral_exr).channels()["XYZ.Y"].pixels, float)
    if not np.array_equal(y_film, y_beside):
        failures.append("XYZ.Y of the spectral file differs from the image's")
    ratio = y_spectral.mean() / y_film.mean()
    print(f"spectral EXR: {len(wavelengths)} bins read by colour-science {colour.__version__}; "
          f"mean Y from the spectra {y_spectral.mean():.6f}, XYZ.Y {y_film.mean():.6f}, ratio {ratio:.6f}")
    if abs(ratio - 1.0) > 2e-3:
        failures.append(f"Y from the spectra / XYZ.Y = {ratio}")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
