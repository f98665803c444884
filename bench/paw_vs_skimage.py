#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""PAW benchmark: talkhead's piecewise-affine warp against scikit-image's PiecewiseAffineTransform +
warp (the stack Costa 2015 used) on the same 1280x720 RGB image and the same 64-point mesh.

Prints both times, their ratio and the PSNR between the two outputs. Goal: >= 100x faster, >= 40 dB.
usage: bench/paw_vs_skimage.py [BUILD_DIR] [IMM_FOLDER]   (Debian's python3-skimage; run with /usr/bin/python3)
"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from skimage import io
from skimage.transform import PiecewiseAffineTransform, warp

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build")
imm = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "..", "shared", "data", "imm-frontal", "IMM-Frontal_Face_DB_SMALL")
if not os.path.isdir(os.path.join(imm, "asf")):
    sys.exit(f"IMM data not found in {imm}")

with tempfile.TemporaryDirectory() as tmp:
    out = subprocess.run([os.path.join(build, "bench", "bench_paw"), tmp, imm], check=True, capture_output=True, text=True).stdout
    ours = dict(line.split() for line in out.strip().splitlines())
    src = io.imread(os.path.join(tmp, "src.png")).astype(np.float64) / 255.0
    th = io.imread(os.path.join(tmp, "talkhead.png")).astype(np.float64)
    sp = np.loadtxt(os.path.join(tmp, "src_points.txt"))
    dp = np.loadtxt(os.path.join(tmp, "dst_points.txt"))

    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        tform = PiecewiseAffineTransform()
        tform.estimate(dp, sp)  # maps output (destination) coordinates to input coordinates
        sk = warp(src, tform, order=1, mode="edge", output_shape=src.shape[:2])
        times.append(time.perf_counter() - t0)
    sk_ms = 1000 * sorted(times)[1]

sk255 = sk * 255.0
mse = np.mean((sk255 - th) ** 2)
psnr = 10 * np.log10(255.0 ** 2 / mse) if mse > 0 else float("inf")
warp_ms = float(ours["talkhead_warp_ms"])
map_ms = float(ours["talkhead_map_ms"])
print(f"image 1280x720 RGB, mesh {ours['points']} points / {ours['triangles']} triangles")
print(f"scikit-image  PiecewiseAffineTransform+warp : {sk_ms:9.2f} ms")
print(f"talkhead      map (rasterise the mesh)      : {map_ms:9.3f} ms")
print(f"talkhead      warp (one pass, 1 thread)     : {warp_ms:9.3f} ms")
print(f"speed-up warp only: {sk_ms / warp_ms:7.1f}x   map + warp: {sk_ms / (map_ms + warp_ms):7.1f}x   (goal >= 100x)")
print(f"PSNR talkhead vs scikit-image: {psnr:.2f} dB (goal >= 40 dB)")
