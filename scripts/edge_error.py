#!/usr/bin/env python3
"""How much of a GPU caustic buffer's error lies at the edges of the reference's lit regions
(shadow edges, silhouettes, a receiver's rim), and how many pixels the GPU lights well inside
the reference's shadows (cells reaching past a receiver's border). A pixel is in the band of
width k when the reference lights a pixel within k pixels of it (Chebyshev distance) and
leaves another one dark; lit means any channel above zero, which is exact for the reference's photon gathering.
It prints the squared error's share where one of the two buffers is dark and the other lit,
and for k = 1 and 2 the band's share of the pixels and of the squared error, and the
relative RMSE (compare.py's) with the band's pixels taken from the reference: the most that
perfect edges could gain. docs/accuracy.md, "What the remaining error is not":

    underlight reference --scene port --width 320 --height 200 --out out/ref
    underlight render --scene port --width 320 --height 200 --frames 1 --hdr out/gpu --hdr-format pfm --out out/gpu/o.png
    python3 scripts/edge_error.py out/gpu/caustics.pfm out/ref/caustics.pfm
"""
import math
import sys

from pfm import read_pfm


def near(mask, w, h, k):
    """Pixels within k pixels (Chebyshev) of a pixel set in `mask`."""
    rows = [[any(mask[y * w + i] for i in range(max(x - k, 0), min(x + k, w - 1) + 1)) for x in range(w)]
            for y in range(h)]
    return [any(rows[j][x] for j in range(max(y - k, 0), min(y + k, h - 1) + 1)) for y in range(h) for x in range(w)]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    w, h, c, gpu = read_pfm(sys.argv[1])
    w2, h2, c2, ref = read_pfm(sys.argv[2])
    if (w, h, c) != (w2, h2, c2):
        sys.exit("%s is %dx%dx%d, %s is %dx%dx%d" % (sys.argv[1], w, h, c, sys.argv[2], w2, h2, c2))
    n = w * h
    lit = [any(ref[p * c + i] > 0.0 for i in range(c)) for p in range(n)]
    error = [sum((gpu[p * c + i] - ref[p * c + i]) ** 2 for i in range(c)) for p in range(n)]
    total = sum(error)
    mean_ref = sum(ref) / len(ref)
    rmse = math.sqrt(total / len(ref)) / mean_ref
    print("relative RMSE %.3f" % rmse)
    gpu_lit = [any(gpu[p * c + i] > 0.0 for i in range(c)) for p in range(n)]
    dark_lit = sum(e for e, r, g in zip(error, lit, gpu_lit) if g and not r)
    lit_dark = sum(e for e, r, g in zip(error, lit, gpu_lit) if r and not g)
    print("where the reference is dark and the GPU lit: %.1f %% of the squared error; lit and dark: %.1f %%"
          % (100.0 * dark_lit / max(total, 1e-30), 100.0 * lit_dark / max(total, 1e-30)))
    # Light spilled into the reference's shadows: pixels with no lit reference pixel within
    # 2 px that the GPU lights above 5 % of the reference's mean lit pixel (channel sums).
    ref_sum = [sum(ref[p * c:(p + 1) * c]) for p in range(n)]
    lit_sums = [v for v in ref_sum if v > 0.0]
    threshold = 0.05 * sum(lit_sums) / max(len(lit_sums), 1)
    near_lit = {k: near(lit, w, h, k) for k in (1, 2)}
    deep_dark = [not v for v in near_lit[2]]
    spilled = sum(1 for p in range(n) if deep_dark[p] and sum(gpu[p * c:(p + 1) * c]) > threshold)
    print("lit more than 2 px inside the reference's dark: %d pixels of its %d" % (spilled, sum(deep_dark)))
    for k in (1, 2):
        near_dark = near([not v for v in lit], w, h, k)
        band = [a and b for a, b in zip(near_lit[k], near_dark)]
        in_band = sum(e for e, b in zip(error, band) if b)
        fixed = math.sqrt((total - in_band) / len(ref)) / mean_ref
        print("within %d px of an edge: %.1f %% of the pixels, %.1f %% of the squared error; "
              "relative RMSE with the band from the reference %.3f (%.2f of it)"
              % (k, 100.0 * sum(band) / n, 100.0 * in_band / max(total, 1e-30), fixed, fixed / rmse))


if __name__ == "__main__":
    main()
