#!/usr/bin/env python3
"""Holes in a GPU caustic buffer: pixels that hold nothing although the reference lights
them and all eight of their neighbours (channel 0 above 0.005 of the surface irradiance,
the buffers' unit). docs/accuracy.md's "tank holes" column:

    underlight reference --scene tank --width 320 --height 200 --out out/ref
    underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/gpu --out out/gpu/o.png
    python3 scripts/holes.py out/gpu/caustics.pfm out/ref/caustics.pfm
"""
import sys

from pfm import read_pfm

LIT = 0.005


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    w, h, c, gpu = read_pfm(sys.argv[1])
    w2, h2, c2, ref = read_pfm(sys.argv[2])
    if (w, h) != (w2, h2):
        sys.exit("%s is %dx%d, %s is %dx%d" % (sys.argv[1], w, h, sys.argv[2], w2, h2))
    at = lambda values, channels, x, y: values[(y * w + x) * channels]
    lit = holes = 0
    for y in range(h):
        for x in range(w):
            # Edge pixels repeat their border neighbours, as the neighbourhood is clamped.
            around = [at(ref, c2, min(max(x + i, 0), w - 1), min(max(y + j, 0), h - 1))
                      for j in (-1, 0, 1) for i in (-1, 0, 1)]
            if min(around) > LIT:
                lit += 1
                holes += at(gpu, c, x, y) == 0.0
    print("%d holes among %d pixels lit with their neighbours" % (holes, lit))


if __name__ == "__main__":
    main()
