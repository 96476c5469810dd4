#!/usr/bin/env python3
"""Where one GPU buffer's error against the reference grew most over another's, pixel by
pixel: for a change whose figure rose, whether the rise is spread over the picture or sits in
a few pixels. docs/accuracy.md's "all of it one pixel" (the cut cells on the tank):

    underlight reference --scene tank --width 320 --height 200 --photons 64000000 --out out/ref
    (render the buffer before the change into out/before and after it into out/after:
     underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/after --hdr-format pfm --out out/a.png)
    python3 scripts/worst_pixels.py out/ref/caustics.pfm out/before/caustics.pfm out/after/caustics.pfm [N]

Printed: both buffers' relative RMSE as compare.py measures it (sqrt(mean (gpu - ref)^2) /
mean ref over the RGB of every pixel); the N pixels (5 unless given; x, y from the top left)
whose squared error rose most from the first buffer to the second, each with its value (the
mean of its RGB) in the reference and both buffers; and the second buffer's figure with those
N pixels taken from the first. Pure Python, like the scripts beside it.
"""
import sys

from pfm import read_rgb_pfms


def relative_rmse(buffer, ref):
    sq = sum((a - b) ** 2 for a, b in zip(buffer, ref))
    return (sq / len(ref)) ** 0.5 / (sum(ref) / len(ref))


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    w, h, (ref, before, after) = read_rgb_pfms(sys.argv[1:4])
    count = int(sys.argv[4]) if len(sys.argv) == 5 else 5

    def pixel_error(buffer, i):
        return sum((buffer[3 * i + k] - ref[3 * i + k]) ** 2 for k in range(3))

    rise = sorted(range(w * h), key=lambda i: pixel_error(after, i) - pixel_error(before, i), reverse=True)[:count]
    print("relative RMSE: %s %.4f, %s %.4f" % (sys.argv[2], relative_rmse(before, ref), sys.argv[3], relative_rmse(after, ref)))
    for i in rise:
        x, y = i % w, h - 1 - i // w  # PFM rows run bottom to top
        mean = lambda b: sum(b[3 * i:3 * i + 3]) / 3.0
        print("  pixel (%d, %d): reference %.4f, first %.4f, second %.4f" % (x, y, mean(ref), mean(before), mean(after)))
    mended = list(after)
    for i in rise:
        mended[3 * i:3 * i + 3] = before[3 * i:3 * i + 3]
    print("the second with those %d pixels from the first: relative RMSE %.4f" % (count, relative_rmse(mended, ref)))


if __name__ == "__main__":
    main()
