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
    python3 scripts/block_ratios.py [--crop X0,Y0,X1,Y1] out/gpu/godrays.pfm out/ref/godrays.pfm [COLUMNS ROWS]

With --crop, both buffers are first cut to the pixels x0 <= x < x1, y0 <= y < y1 (from the top
left), and the blocks and the relative RMSE are the crop's (the rocks' sides in "Cells that
reach to where their receiver ends").
"""
import sys

from pfm import read_pfm

WORST_PIXELS = 5


def crop(w, h, c, values, x0, y0, x1, y1):
    """The pixels x0 <= x < x1, y0 <= y < y1 (y from the top) of a buffer stored bottom row first."""
    out = []
    for file_row in range(h - y1, h - y0):
        out.extend(values[(file_row * w + x0) * c:(file_row * w + x1) * c])
    return out


def main():
    args = sys.argv[1:]
    window = None
    if "--crop" in args:
        i = args.index("--crop")
        try:
            window = [int(v) for v in args[i + 1].split(",")]
            assert len(window) == 4
        except (IndexError, ValueError, AssertionError):
            sys.exit("--crop takes X0,Y0,X1,Y1: four whole numbers")
        del args[i:i + 2]
    if len(args) not in (2, 4):
        sys.exit(__doc__)
    w, h, c, gpu = read_pfm(args[0])
    w2, h2, c2, ref = read_pfm(args[1])
    if (w, h, c) != (w2, h2, c2):
        sys.exit("%s is %dx%dx%d, %s is %dx%dx%d" % (args[0], w, h, c, args[1], w2, h2, c2))
    if window:
        x0, y0, x1, y1 = window
        if not (0 <= x0 < x1 <= w and 0 <= y0 < y1 <= h):
            sys.exit("--crop %d,%d,%d,%d lies outside the %dx%d buffer" % (x0, y0, x1, y1, w, h))
        gpu, ref = crop(w, h, c, gpu, x0, y0, x1, y1), crop(w, h, c, ref, x0, y0, x1, y1)
        w, h = x1 - x0, y1 - y0
    cols, rows = (int(args[2]), int(args[3])) if len(args) == 4 else (8, 5)
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
