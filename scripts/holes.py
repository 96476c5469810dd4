#!/usr/bin/env python3
"""Holes in a GPU caustic buffer: pixels that hold nothing although the reference lights
them and all eight of their neighbours (channel 0 above 0.005 of the surface irradiance,
the buffers' unit). docs/accuracy.md's "tank holes" column:

    underlight reference --scene tank --width 320 --height 200 --out out/ref
    underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/gpu --out out/gpu/o.png
    python3 scripts/holes.py out/gpu/caustics.pfm out/ref/caustics.pfm

With --as-metrics, lit means above a tenth of the mean of the reference's non-zero pixels, and
a pixel on the image's border never counts (its neighbourhood is not all lit): the figure of
`metrics::lit_holes`, which tests/accuracy.rs asserts, and which docs/accuracy.md gives at the
scenes' own sizes ("The mesh to the photon window's edges").
"""
import sys

from pfm import read_pfm

LIT = 0.005


def main():
    args = sys.argv[1:]
    as_metrics = "--as-metrics" in args
    args = [a for a in args if a != "--as-metrics"]
    if len(args) != 2:
        sys.exit(__doc__)
    w, h, c, gpu = read_pfm(args[0])
    w2, h2, c2, ref = read_pfm(args[1])
    if (w, h) != (w2, h2):
        sys.exit("%s is %dx%d, %s is %dx%d" % (args[0], w, h, args[1], w2, h2))
    at = lambda values, channels, x, y: values[(y * w + x) * channels]
    threshold = LIT
    if as_metrics:
        lit_values = [v for v in ref[::c2] if v > 0.0]
        threshold = 0.1 * sum(lit_values) / max(len(lit_values), 1)
    lit = holes = 0
    for y in range(h):
        for x in range(w):
            if as_metrics and not (0 < x < w - 1 and 0 < y < h - 1):
                continue
            # Edge pixels repeat their border neighbours, as the neighbourhood is clamped.
            around = [at(ref, c2, min(max(x + i, 0), w - 1), min(max(y + j, 0), h - 1))
                      for j in (-1, 0, 1) for i in (-1, 0, 1)]
            if min(around) > threshold:
                lit += 1
                holes += at(gpu, c, x, y) == 0.0
    print("%d holes among %d pixels lit with their neighbours (%.2f %%)" % (holes, lit, 100.0 * holes / max(lit, 1)))


if __name__ == "__main__":
    main()
