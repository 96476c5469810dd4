#!/usr/bin/env python3
"""Where a GPU buffer differs from the reference's: the ratio of their sums over a grid of
blocks of the image, printed top row first. docs/accuracy.md ("Godrays: where the bias was")
found the godray bias with it:

    underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/gpu --out out/gpu/o.png
    underlight reference --scene tank --width 320 --height 200 --out out/ref
    python3 scripts/block_ratios.py out/gpu/godrays.pfm out/ref/godrays.pfm [COLUMNS ROWS]
"""
import sys

from pfm import read_pfm


def channel0(path):
    """Channel 0 of a PFM, rows from the bottom (as the file stores them)."""
    width, height, channels, values = read_pfm(path)
    return width, height, values[::channels]


def main():
    if len(sys.argv) not in (3, 5):
        sys.exit(__doc__)
    w, h, gpu = channel0(sys.argv[1])
    w2, h2, ref = channel0(sys.argv[2])
    if (w, h) != (w2, h2):
        sys.exit("%s is %dx%d, %s is %dx%d" % (sys.argv[1], w, h, sys.argv[2], w2, h2))
    cols, rows = (int(sys.argv[3]), int(sys.argv[4])) if len(sys.argv) == 5 else (8, 5)
    print("%dx%d, flux %+.1f %%; GPU / reference per block, top row first:" % (w, h, 100 * (sum(gpu) / sum(ref) - 1)))
    for j in reversed(range(rows)):
        cells = []
        for i in range(cols):
            ys = range(j * h // rows, (j + 1) * h // rows)
            xs = range(i * w // cols, (i + 1) * w // cols)
            g = sum(gpu[y * w + x] for y in ys for x in xs)
            r = sum(ref[y * w + x] for y in ys for x in xs)
            cells.append("%5.2f" % (g / r) if r > 0 else "    -")
        print(" ".join(cells))


if __name__ == "__main__":
    main()
