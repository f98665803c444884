#!/usr/bin/env bash
# Makes models/au-templates/ibug-68.tsv (D48) so faces made from video (ibug-68) can take 'au' events and
# --emotion-source au. The ch-unicamp-56 templates (learned from the default corpus) are carried over to
# dlib's 68 points through the neutral face: dlib finds its 68 points on the default corpus's neutral
# rest image, and each of them takes the inverse-distance mix of the templates of the three nearest
# ch-unicamp-56 points there, rescaled to ibug-68's inter-ocular distance. (Learning directly from dlib's
# fits of the whole corpus was tried: dlib's brows follow the drawn furrows, which left half the
# displacement unexplained and turned AU4's inner-brow motion upward.)
# usage: corpus-tools/ibug68_au_templates.sh [BUILD_DIR] [OUT.tsv]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
out="${2:-$root/models/au-templates/ibug-68.tsv}"
corpus="$build/models/default-corpus"
[ -f "$corpus/neutral_sil.png" ] || { echo "ibug68_au_templates.sh: $corpus/neutral_sil.png missing (build the default face first)" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/img" && cp "$corpus/neutral_sil.png" "$tmp/img/"
"$build/talkhead" corpus landmarks "$tmp/img" -o "$tmp/lm" --no-smooth -q
/usr/bin/python3 - "$root" "$corpus/corpus.csv" "$tmp/lm/neutral_sil.pts" "$out" <<'PY'
import sys
import numpy as np
root, csv, pts, out = sys.argv[1:5]
def scheme_points(name):
    return [l.split()[1] for l in open(f"{root}/models/schemes/{name}.scheme") if l.startswith("point ")]
ch, ib = scheme_points("ch-unicamp-56"), scheme_points("ibug-68")
row = next(l for l in open(csv, encoding="utf-8") if l.startswith("neutral_sil.png,"))
p56 = np.array([[float(v) for v in c.strip("()\n").split(";")] for c in row.rstrip("\n").split(",")[9:]])
p68 = np.array([[float(v) - 1 for v in l.split()] for l in open(pts) if len(l.split()) == 2 and l.split()[0][0] in "0123456789-"])
assert p56.shape == (56, 2) and p68.shape == (68, 2), (p56.shape, p68.shape)
def iod(p, eyes):  # eye centres: midpoints of the two corners of each eye
    (a, b), (c, d) = eyes
    return np.linalg.norm((p[a] + p[b]) / 2 - (p[c] + p[d]) / 2)
iod56 = iod(p56, [(ch.index("REYE1"), ch.index("REYE3")), (ch.index("LEYE1"), ch.index("LEYE3"))])
iod68 = iod(p68, [(ib.index("RE0"), ib.index("RE3")), (ib.index("LE0"), ib.index("LE3"))])
templates, order, header = {}, [], []
for l in open(f"{root}/models/au-templates/ch-unicamp-56.tsv", encoding="utf-8"):
    if l.startswith("#") or l.startswith("au\t"):
        continue
    au, point, dx, dy = l.split("\t")
    if au not in templates:
        templates[au] = np.zeros((56, 2)); order.append(au)
    templates[au][ch.index(point)] = [float(dx), float(dy)]
with open(out, "w", encoding="utf-8") as o:
    o.write("# Action-unit shape templates for scheme ibug-68 (decision D48): per AU and point, the displacement from the\n"
            "# neutral face at full intensity in inter-ocular distances, x toward the image-right eye, y down the face.\n"
            "# Carried over from ch-unicamp-56.tsv by corpus-tools/ibug68_au_templates.sh: each of dlib's 68 points on the\n"
            "# default corpus's neutral rest image takes the inverse-distance mix of the three nearest ch-unicamp-56 points,\n"
            "# the points of the brows, lids and lips the interpolation along their contour of its points' templates (D69).\n"
            "au\tpoint\tdx\tdy\n")
    # Contours by position along them, not by the nearest points: each of dlib's points on a brow, a lid or
    # a lip takes, at its arc-length fraction along its contour, the linear interpolation of the templates of
    # the ch-unicamp-56 points of the same contour (both listed from the same end). The nearest-point mix
    # blended what moves apart: a brow's inner end with its middle (anger's knitted V came out flat), the
    # upper lid with the lower (AU5 at half strength, AU7 at a third) and, on the closed mouth of the rest
    # image, the inner upper lip with the inner lower one (AU25 and AU26 did not part the lips) (D69).
    contours = [
        (["RB0", "RB1", "RB2", "RB3", "RB4"], ["REB3", "REB2", "REB1"]),
        (["LB4", "LB3", "LB2", "LB1", "LB0"], ["LEB3", "LEB2", "LEB1"]),
        (["RE0", "RE1", "RE2", "RE3"], ["REYE1", "REYE2", "REYE3"]),
        (["RE0", "RE5", "RE4", "RE3"], ["REYE1", "REYE4", "REYE3"]),
        (["LE3", "LE2", "LE1", "LE0"], ["LEYE1", "LEYE2", "LEYE3"]),
        (["LE3", "LE4", "LE5", "LE0"], ["LEYE1", "LEYE4", "LEYE3"]),
        (["OM0", "OM1", "OM2", "OM3", "OM4", "OM5", "OM6"], ["RM2", "RM1", "VMR", "CUM", "VML", "LM1", "LM2"]),
        (["OM0", "OM11", "OM10", "OM9", "OM8", "OM7", "OM6"], ["RM2", "RM3", "CLM", "LM3", "LM2"]),
        (["IM0", "IM1", "IM2", "IM3", "IM4"], ["RM2", "RM4", "CIUM", "LM4", "LM2"]),
        (["IM0", "IM7", "IM6", "IM5", "IM4"], ["RM2", "RM5", "CILM", "LM5", "LM2"]),
    ]
    def arc(points):
        d = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
        return d / d[-1]
    along = {}
    for dl, cl in contours:
        di, ci = [ib.index(n) for n in dl], [ch.index(n) for n in cl]
        for end in (0, -1):  # the two lists start at the same end
            assert np.linalg.norm(p68[di[end]] - p56[ci[end]]) < np.linalg.norm(p68[di[end]] - p56[ci[-1 - end]]), f"{dl[0]}…: ends apart"
        sd, sc = arc(p68[di]), arc(p56[ci])
        for k, i in enumerate(di):
            along.setdefault(i, (ci, sc, sd[k]))
    for au in order:
        for i, name in enumerate(ib):
            if i in along:
                ci, sc, t = along[i]
                v = np.array([np.interp(t, sc, templates[au][ci, c]) for c in (0, 1)]) * iod56 / iod68
            else:
                d = np.linalg.norm(p56 - p68[i], axis=1)
                near = np.argsort(d)[:3]
                w = 1 / (d[near] + 1.0)
                v = (w[:, None] * templates[au][near]).sum(0) / w.sum() * iod56 / iod68
            v = np.round(v, 4) + 0.0
            o.write(f"{au}\t{name}\t{v[0]:.4f}\t{v[1]:.4f}\n")
print(f"wrote {out}: {len(order)} action units x 68 points (inter-ocular distance {iod68:.1f} px for dlib, {iod56:.1f} px for ch-unicamp-56)", file=sys.stderr)
PY
