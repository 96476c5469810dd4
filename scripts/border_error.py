#!/usr/bin/env python3
"""The caustic error along the edges of the reference's light: shadows' and receivers'
borders, where the triangles' handed-back cells draw the light. docs/accuracy.md's figures
"within 4 px of the reference's light's borders (3 × 3 boxes)":

    underlight reference --scene storage --photons 64000000 --out out/ref
    underlight render --scene storage --frames 1 --hdr out/gpu --hdr-format pfm --out out/gpu/o.png
    python3 scripts/border_error.py out/ref/caustics.pfm out/gpu/caustics.pfm [more.pfm ...]

Lit: the reference's channel 0 averaged over a 5×5 box (clamped at the image's edges, so its
own noise does not make borders) above a tenth of the mean of its non-zero pixels. The band:
pixels within 4 steps (4-neighbourhood) of a pixel whose left or upper neighbour differs in
that. Both buffers are averaged over 3×3 boxes first (where a line lies within a pixel is
not what this measures). Printed per GPU buffer: the band's relative RMSE sqrt(mean (g −
r)²) / mean r, its relative L1 and its flux error. Pure Python, like the scripts beside it.
"""
import sys

from pfm import read_pfm

BAND = 4


def channel0(path):
    w, h, c, values = read_pfm(path)
    # PFM rows run bottom to top; flip so that row 0 is the top.
    rows = [values[(h - 1 - y) * w * c:(h - y) * w * c:c] for y in range(h)]
    return w, h, [v for row in rows for v in row]


def box_mean(w, h, values, k):
    """Mean over a k×k box, the image's edge pixels repeated past it (k odd)."""
    r = k // 2
    out = [0.0] * (w * h)
    for y in range(h):
        rows = [min(max(y + d, 0), h - 1) * w for d in range(-r, r + 1)]
        for x in range(w):
            s = 0.0
            for d in range(-r, r + 1):
                xx = min(max(x + d, 0), w - 1)
                for base in rows:
                    s += values[base + xx]
            out[y * w + x] = s / (k * k)
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    w, h, ref = channel0(sys.argv[1])
    nonzero = [v for v in ref if v > 0.0]
    threshold = 0.1 * sum(nonzero) / max(len(nonzero), 1)
    lit = [v > threshold for v in box_mean(w, h, ref, 5)]
    band = [False] * (w * h)
    for y in range(h):
        for x in range(w):
            i = y * w + x
            if (x > 0 and lit[i] != lit[i - 1]) or (y > 0 and lit[i] != lit[i - w]):
                band[i] = True
    for _ in range(BAND):
        grown = band[:]
        for i in range(w * h):
            if band[i]:
                x = i % w
                if x > 0:
                    grown[i - 1] = True
                if x + 1 < w:
                    grown[i + 1] = True
                if i >= w:
                    grown[i - w] = True
                if i + w < w * h:
                    grown[i + w] = True
        band = grown
    inside = [i for i in range(w * h) if band[i]]
    ref3 = box_mean(w, h, ref, 3)
    ref_sum = sum(ref3[i] for i in inside)
    for path in sys.argv[2:]:
        w2, h2, gpu = channel0(path)
        if (w2, h2) != (w, h):
            sys.exit("%s is %dx%d, the reference %dx%d" % (path, w2, h2, w, h))
        gpu3 = box_mean(w, h, gpu, 3)
        sq = sum((gpu3[i] - ref3[i]) ** 2 for i in inside)
        l1 = sum(abs(gpu3[i] - ref3[i]) for i in inside)
        g_sum = sum(gpu3[i] for i in inside)
        n = len(inside)
        print("%s: %d band pixels, relative RMSE %.4f, L1 %.4f, flux %+.2f %%"
              % (path, n, (sq / n) ** 0.5 / (ref_sum / n), l1 / ref_sum, 100.0 * (g_sum / ref_sum - 1.0)))


if __name__ == "__main__":
    main()
