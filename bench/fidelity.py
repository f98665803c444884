#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Fine detail of face crops, real against rendered (bench/fidelity.sh, issue 47). Each set is a folder of
# frames (frame_NNNNNN.png, 1-based as ffmpeg numbers them) and the landmarks.tsv that `talkhead corpus
# landmarks` tracked on the same video (frame 0-based; ibug-68 points by name). Per tracked frame: the face's
# square box (jaw and brows, grown by a fifth), cut and brought to SIZE² by Lanczos; in it, the variance of the
# 4-neighbour Laplacian of the luma over the mouth's box (its outer-lip points grown by a quarter) and over the
# face's middle; the inner-lip opening in eye distances. FIDELITY_FILTER=bilinear enlarges by bilinear
# interpolation instead (the real frames against a 1280x720 render: enlarged as the render enlarges them). The crops go to OUT/NAME/ for BRISQUE.
# Rendered frames are compared with the real ones matched by mouth opening: five bins at the real frames'
# quintiles, the rendered mean over the real mean in each bin that both fill (at least 3 frames each),
# weighted by the real frames in it.
#   fidelity.py SIZE OUT NAME FRAMES[,FRAMES...] TSV[,TSV...] [NAME FRAMES TSV...]
#     one JSON object per set on stdout: {"name", "frames", "mouth", "face", "opening"} (lists per frame)
#   fidelity.py side TSV       the median face box side of a track, pixels
#   fidelity.py summary FACE LABEL REAL.json RENDERED.json REAL.brisque RENDERED.brisque   one line
#   fidelity.py y4m FRAMES TSV speaking|all MOST   real frames as YUV4MPEG2 on stdout (for classify.js)
#   fidelity.py bands LABEL FRAMES[,FRAMES...] TSV[,TSV...] EVERY   horizontal-band energy across the nose bridge
import csv
import json
import os
import sys

import numpy as np
from PIL import Image


# How a crop is brought to SIZE²: Lanczos, or (FIDELITY_FILTER=bilinear) as the render enlarges a face.
FILTER = Image.BILINEAR if os.environ.get("FIDELITY_FILTER") == "bilinear" else Image.LANCZOS


def read_track(path):
    rows = []
    with open(path, newline="") as f:
        r = csv.reader(f, delimiter="\t")
        header = next(r)
        for row in r:
            if len(row) < len(header) or row[2] not in ("tracked", "detected", "drawn") or float(row[3]) < 0.5:
                continue
            pts = {}
            for i, name in enumerate(header[4:], 4):
                if name.endswith("_x"):
                    pts[name[:-2]] = (float(row[i]), float(row[i + 1]))
            rows.append((int(row[0]), pts))
    return rows


def group(pts, prefix, n):
    return np.array([pts[f"{prefix}{i}"] for i in range(n)])


def measure(frames_dir, track, size, out_dir, every, start):
    os.makedirs(out_dir, exist_ok=True)
    mouth, face, opening = [], [], []
    for k, (frame, pts) in enumerate(read_track(track)):
        if k % every:
            continue
        path = os.path.join(frames_dir, f"frame_{frame + 1:06d}.png")
        if not os.path.exists(path):
            continue
        outline = np.vstack([group(pts, "JAW", 17), group(pts, "RB", 5), group(pts, "LB", 5)])
        lo, hi = outline.min(0), outline.max(0)
        side = 1.2 * max(hi - lo)
        c = (lo + hi) / 2
        im = Image.open(path).convert("RGB")
        side = min(side, im.width, im.height)
        x0 = min(max(c[0] - side / 2, 0), im.width - side)
        y0 = min(max(c[1] - side / 2, 0), im.height - side)
        crop = im.resize((size, size), FILTER, box=(x0, y0, x0 + side, y0 + side))
        rgb = np.asarray(crop, dtype=np.float64)
        y = 0.299 * rgb[..., 0] + 0.587 * rgb[..., 1] + 0.114 * rgb[..., 2]
        lap = y[:-2, 1:-1] + y[2:, 1:-1] + y[1:-1, :-2] + y[1:-1, 2:] - 4 * y[1:-1, 1:-1]  # at (r+1, c+1)
        om = (group(pts, "OM", 12) - (x0, y0)) * (size / side)
        mlo, mhi = om.min(0), om.max(0)
        g = 0.25 * (mhi - mlo)
        a = np.clip(np.floor(mlo - g).astype(int), 1, size - 2)
        b = np.clip(np.ceil(mhi + g).astype(int), 1, size - 2)
        mouth.append(float(lap[a[1] - 1:b[1] - 1, a[0] - 1:b[0] - 1].var()))
        f0, f1 = int(0.2 * size), int(0.8 * size)
        face.append(float(lap[int(0.25 * size) - 1:int(0.9 * size) - 1, f0 - 1:f1 - 1].var()))
        im_ = group(pts, "IM", 8)
        eyes = np.linalg.norm(group(pts, "RE", 6).mean(0) - group(pts, "LE", 6).mean(0))
        opening.append(float(np.mean([np.linalg.norm(im_[i] - im_[8 - i]) for i in (1, 2, 3)]) / max(eyes, 1e-6)))
        crop.save(os.path.join(out_dir, f"{start + len(mouth):05d}.png"))
    return {"frames": len(mouth), "mouth": mouth, "face": face, "opening": opening}


def side(track):
    sides = []
    for _, pts in read_track(track):
        outline = np.vstack([group(pts, "JAW", 17), group(pts, "RB", 5), group(pts, "LB", 5)])
        sides.append(1.2 * max(outline.max(0) - outline.min(0)))
    return int(round(float(np.median(sides)))) if sides else 256


def matched(real, rendered, key):
    """Rendered over real, matched by mouth opening (five bins at the real frames' quintiles)."""
    ro, rv = np.array(real["opening"]), np.array(real[key])
    go, gv = np.array(rendered["opening"]), np.array(rendered[key])
    edges = np.quantile(ro, [0.2, 0.4, 0.6, 0.8])
    rb, gb = np.digitize(ro, edges), np.digitize(go, edges)
    num = den = 0.0
    for b in range(5):
        r, g = rv[rb == b], gv[gb == b]
        if len(r) >= 3 and len(g) >= 3:
            num += len(r) * g.mean() / r.mean()
            den += len(r)
    return num / den if den else float("nan")


def brisque(path):
    vals = [float(l.split()[0]) for l in open(path) if l.strip()]
    return float(np.mean(vals)) if vals else float("nan")


def summary(face, label, real_json, rendered_json, real_brisque, rendered_brisque):
    real, rendered = json.loads(open(real_json).read()), json.loads(open(rendered_json).read())
    rb, gb = brisque(real_brisque), brisque(rendered_brisque)
    line = (f"{face:7} {label}\n         real {real['frames']:4d} frames, rendered {rendered['frames']:4d}:"
          f"  mouth {np.mean(real['mouth']):7.2f} / {np.mean(rendered['mouth']):7.2f} = {matched(real, rendered, 'mouth'):4.2f}x (goal >= 0.9)"
          f"  face {np.mean(real['face']):6.2f} / {np.mean(rendered['face']):6.2f} = {matched(real, rendered, 'face'):4.2f}x"
          f"  BRISQUE {rb:5.1f} / {gb:5.1f} ({gb - rb:+5.1f}; goal within 3)"
          f"  opening p5-p95 {np.percentile(real['opening'], 5):.3f}-{np.percentile(real['opening'], 95):.3f} /"
          f" {np.percentile(rendered['opening'], 5):.3f}-{np.percentile(rendered['opening'], 95):.3f}")
    if "no goal" in label:
        line = line.replace(" (goal >= 0.9)", "").replace("; goal within 3", "")
    print(line)


def smooth(v, s):
    r = int(3 * s) + 1
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / s) ** 2)
    return np.convolve(np.pad(v, r, mode="edge"), k / k.sum(), mode="valid")


def band_energy(path, pts):
    """Horizontal bands across the nose bridge: the rows' mean luma between the eyes' inner corners (less a
    tenth of an eye distance each side), from just above the eye line down 0.45 eye distances, less its
    smooth course (Gaussian, 0.08 eye distances); the RMS of what is left, in % of the mean. Skin texture
    averages out along a row; a band across the bridge does not."""
    y = np.asarray(Image.open(path).convert("L"), dtype=np.float64)
    re, le = group(pts, "RE", 6).mean(0), group(pts, "LE", 6).mean(0)
    iod = np.linalg.norm(le - re)
    x0, x1 = int(pts["RE3"][0] + 0.1 * iod), int(pts["LE0"][0] - 0.1 * iod)
    y0 = int((re[1] + le[1]) / 2 - 0.05 * iod)
    y1 = int(y0 + 0.45 * iod)
    prof = y[y0:y1, x0:x1].mean(1)
    res = prof - smooth(prof, 0.08 * iod)
    return float(np.sqrt((res ** 2).mean()) / prof.mean() * 100)


def bands(label, frames, tracks, every):
    v = []
    for fr, tr in zip(frames.split(","), tracks.split(",")):
        for k, (frame, pts) in enumerate(read_track(tr)):
            path = os.path.join(fr, f"frame_{frame + 1:06d}.png")
            if k % int(every) == 0 and os.path.exists(path):
                v.append(band_energy(path, pts))
    print(f"         nose bands {label:26} median {np.median(v):5.2f} %  p95 {np.percentile(v, 95):5.2f} %  max {max(v):5.2f} %  ({len(v)} frames)")


def y4m(frames_dir, track, which, most):
    """The real frames as YUV4MPEG2 (4:2:0, BT.601 limited range, as classify.js reads) on stdout: `speaking`
    (the inner-lip opening ranges over 0.08 eye distances within ±12 frames) or `all`, at most `most` of
    them, evenly spaced."""
    opening = {}
    for frame, pts in read_track(track):
        im_ = group(pts, "IM", 8)
        eyes = np.linalg.norm(group(pts, "RE", 6).mean(0) - group(pts, "LE", 6).mean(0))
        opening[frame] = float(np.mean([np.linalg.norm(im_[i] - im_[8 - i]) for i in (1, 2, 3)]) / max(eyes, 1e-6))
    frames = sorted(opening)
    if which == "speaking":
        def moving(f):
            near = [opening[g] for g in range(f - 12, f + 13) if g in opening]
            return max(near) - min(near) > 0.08
        frames = [f for f in frames if moving(f)]
    frames = frames[:: max(1, len(frames) // int(most))]
    out = sys.stdout.buffer
    w = h = None
    for f in frames:
        path = os.path.join(frames_dir, f"frame_{f + 1:06d}.png")
        if not os.path.exists(path):
            continue
        a = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)
        if w is None:
            h, w = a.shape[0] // 2 * 2, a.shape[1] // 2 * 2
            out.write(f"YUV4MPEG2 W{w} H{h} F25:1 Ip A1:1 C420jpeg\n".encode())
        a = a[:h, :w]
        r, g, b = a[..., 0], a[..., 1], a[..., 2]
        planes = (16 + 0.257 * r + 0.504 * g + 0.098 * b,
                  (128 - 0.148 * r - 0.291 * g + 0.439 * b).reshape(h // 2, 2, w // 2, 2).mean((1, 3)),
                  (128 + 0.439 * r - 0.368 * g - 0.071 * b).reshape(h // 2, 2, w // 2, 2).mean((1, 3)))
        out.write(b"FRAME\n")
        for p in planes:
            out.write(np.clip(np.round(p), 0, 255).astype(np.uint8).tobytes())


CLASSES = ("neutral", "happy", "sad", "angry", "fearful", "disgusted", "surprised")


def reading(path):
    """classify.js's JSON lines in a file, pooled by their frames with a face."""
    n, m = 0, {c: 0.0 for c in CLASSES}
    for line in open(path):
        if line.strip():
            d = json.loads(line)
            n += d["faces"]
            for c in CLASSES:
                m[c] += d["mean"][c] * d["faces"]
    return {c: (m[c] / n if n else 0.0) for c in CLASSES}


def expression(face, *pairs):
    """LABEL=FILE... : one line per reading, neutral and happy and the largest class."""
    for pair in pairs:
        label, path = pair.split("=", 1)
        r = reading(path)
        top = max(CLASSES, key=lambda c: r[c])
        print(f"         expression {label:28} neutral {r['neutral']:.2f}  happy {r['happy']:.2f}  (largest: {top} {r[top]:.2f})")


def emotions(prefix):
    """PREFIX-{take,render}-EMOTION.json for the six emotions: by argmax and by the gain over the same source's
    neutral, how many of joy, distress, anger, fear and hate read as happy, sad, angry, fearful, disgusted."""
    want = {"joy": "happy", "distress": "sad", "anger": "angry", "fear": "fearful", "hate": "disgusted"}
    for src in ("take", "render"):
        neutral = reading(f"{prefix}-{src}-neutral.json")
        arg = gain = 0
        cells = []
        for e, c in want.items():
            r = reading(f"{prefix}-{src}-{e}.json")
            top = max(CLASSES, key=lambda k: r[k])
            best = max(CLASSES, key=lambda k: r[k] - neutral[k])
            arg += top == c
            gain += best == c
            cells.append(f"{e} {c} {r[c]:.2f}")
        print(f"         expression {src + 's' if src == 'take' else 'renders':8} {', '.join(cells)}; argmax {arg} of 5, gain over neutral {gain} of 5")


def sheet(out, prefix, row):
    """hate and anger, learned skin | own skin, the eyes and nose (1.5 × 1.2 eye distances) at 300 × 240."""
    tiles = []
    for e in ("hate", "anger"):
        for s in ("learned", "on"):
            with open(f"{prefix}-{e}-{s}.tsv", newline="") as f:
                r = list(csv.reader(f, delimiter="\t"))
            h, v = r[0], r[int(row) + 1]
            g = lambda k: float(v[h.index(k)])
            names = ("RE0", "LE3") if "RE0_x" in h else ("REYE1", "LEYE1")
            cx, cy = (g(names[0] + "_x") + g(names[1] + "_x")) / 2, (g(names[0] + "_y") + g(names[1] + "_y")) / 2
            iod = abs(g(names[1] + "_x") - g(names[0] + "_x"))
            box = tuple(int(b) for b in (cx - 0.75 * iod, cy - 0.6 * iod, cx + 0.75 * iod, cy + 0.6 * iod))
            tiles.append(Image.open(f"{prefix}-{e}-{s}.png").crop(box).resize((300, 240), Image.LANCZOS))
    c = Image.new("RGB", (1212, 240), "white")
    for j, t in enumerate(tiles):
        c.paste(t, (j * 300 + (j // 2) * 12, 0))
    c.save(out)


def main():
    if sys.argv[1] == "expression":
        expression(*sys.argv[2:])
        return
    if sys.argv[1] == "emotions":
        emotions(sys.argv[2])
        return
    if sys.argv[1] == "y4m":
        y4m(*sys.argv[2:6])
        return
    if sys.argv[1] == "bands":
        bands(*sys.argv[2:6])
        return
    if sys.argv[1] == "sheet":
        sheet(*sys.argv[2:5])
        return
    if sys.argv[1] == "side":
        print(side(sys.argv[2]))
        return
    if sys.argv[1] == "summary":
        summary(*sys.argv[2:8])
        return
    size, out = int(sys.argv[1]), sys.argv[2]
    args = sys.argv[3:]
    every = int(os.environ.get("FIDELITY_EVERY", "1"))
    while args:
        name, frames, track = args[:3]
        args = args[3:]
        total = {"frames": 0, "mouth": [], "face": [], "opening": []}
        fl, tl = frames.split(","), track.split(",")
        for fr, tr in zip(fl, tl):
            m = measure(fr, tr, size, os.path.join(out, name), every, total["frames"])
            for key in ("mouth", "face", "opening"):
                total[key] += m[key]
            total["frames"] += m["frames"]
        total["name"] = name
        print(json.dumps(total))


if __name__ == "__main__":
    main()
