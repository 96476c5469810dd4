#!/usr/bin/env python3
"""Where a GPU buffer differs from the reference's, over a grid of blocks of the image (top
row first): the ratio of their sums (channel 0), each block's share of compare.py's relative
squared error (the squared difference over every channel, over the pixels' count times the
reference's mean squared: the blocks sum to the relative RMSE squared), and the pixels of
largest error, with both buffers' values as multiples of the reference's mean.
docs/accuracy.md found the godray bias ("Godrays: where the bias was") and the tank's band
beside the west wall ("Light maps along a steeper direction") with it:

    underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/gpu --out out/gpu/o.png
    underlight reference --scene tank --width 320 --height 200 --out out/ref
    python3 scripts/block_ratios.py out/gpu/godrays.pfm out/ref/godrays.pfm [COLUMNS ROWS]
"""
import sys

from pfm import read_pfm

WORST_PIXELS = 5


def main():
    if len(sys.argv) not in (3, 5):
        sys.exit(__doc__)
    w, h, c, gpu = read_pfm(sys.argv[1])
    w2, h2, c2, ref = read_pfm(sys.argv[2])
    if (w, h, c) != (w2, h2, c2):
        sys.exit("%s is %dx%dx%d, %s is %dx%dx%d" % (sys.argv[1], w, h, c, sys.argv[2], w2, h2, c2))
    cols, rows = (int(sys.argv[3]), int(sys.argv[4])) if len(sys.argv) == 5 else (8, 5)
    mean = sum(ref) / len(ref)
    # Per pixel (rows from the bottom, as the file stores them): channel 0 of each buffer, the
    # channels' sums, and the squared difference summed over the channels.
    pixels = range(w * h)
    gpu0, ref0 = gpu[::c], ref[::c]
    error = [sum((gpu[p * c + k] - ref[p * c + k]) ** 2 for k in range(c)) for p in pixels]
    scale = len(ref) * mean * mean
    blocks = [[(range(j * h // rows, (j + 1) * h // rows), range(i * w // cols, (i + 1) * w // cols))
               for i in range(cols)] for j in reversed(range(rows))]
    print("%dx%d, flux %+.1f %%; GPU / reference per block, top row first:" % (w, h, 100 * (sum(gpu0) / sum(ref0) - 1)))
    for row in blocks:
        cells = []
        for ys, xs in row:
            g = sum(gpu0[y * w + x] for y in ys for x in xs)
            r = sum(ref0[y * w + x] for y in ys for x in xs)
            cells.append("%5.2f" % (g / r) if r > 0 else "    -")
        print(" ".join(cells))
    print("relative RMSE %.3f; each block's share of its square (%.3f), top row first:"
          % ((sum(error) / scale) ** 0.5, sum(error) / scale))
    for row in blocks:
        print(" ".join("%5.3f" % (sum(error[y * w + x] for y in ys for x in xs) / scale) for ys, xs in row))
    print("the %d pixels of largest error (x, y from the top left): reference, GPU in means of the reference"
          % WORST_PIXELS)
    for p in sorted(pixels, key=lambda p: -error[p])[:WORST_PIXELS]:
        x, y = p % w, h - 1 - p // w
        print("  (%d, %d): %.1f, %.1f" % (x, y, sum(ref[p * c:(p + 1) * c]) / (c * mean),
                                          sum(gpu[p * c:(p + 1) * c]) / (c * mean)))


if __name__ == "__main__":
    main()
