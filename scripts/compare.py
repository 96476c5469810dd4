#!/usr/bin/env python3
"""A GPU buffer against the reference's, with the sweep's metrics (src/metrics.rs): relative
RMSE sqrt(mean (gpu - ref)^2) / mean ref and the flux error sum gpu / sum ref - 1, over the RGB
of every pixel; with one file, metrics::gap_fraction of it (zero pixels among those whose
15x15 mean exceeds a tenth of the mean of the pixels that hold anything, channel sums).
A GPU buffer smaller than the reference is first upsampled to the reference's size bilinearly
between texel centres, clamped at the border, as compose samples it: the error of the light
the final image shows, at the output's resolution when the reference is traced there. One
larger by a whole factor f on both axes is averaged over f×f blocks instead: rendered at f
times the size, f² samples per pixel. With --blur N both buffers are first averaged over an
N×N box around each pixel (the part of it inside the buffer): the error left at scales above
N pixels.
Where the reference's folder holds caustics_half.pfm (`underlight reference` writes it: the
same estimate from an independent half of the photons), the reference's own error is printed
too, from its two halves, and the figure it leaves for the GPU's buffer, sqrt(figure^2 -
own^2): a reference whose own error is not well below the figure inflates it.
docs/accuracy.md's step-by-step table and own-size gap fractions:

    underlight reference --scene tank --width 320 --height 200 --out out/ref
    underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/gpu --out out/gpu/o.png
    python3 scripts/compare.py out/gpu/caustics.pfm out/ref/caustics.pfm
    underlight render --scene tank --frames 1 --hdr out/own --out out/own/o.png
    python3 scripts/compare.py out/own/caustics.pfm
    underlight reference --scene port --photons 64000000 --out out/ref-own
    python3 scripts/compare.py --blur 3 out/own/caustics.pfm out/ref-own/caustics.pfm
"""
import math
import os
import sys

from pfm import read_pfm


def gap_fraction(width, height, channels, values):
    v = [sum(values[i * channels:(i + 1) * channels]) for i in range(width * height)]  # bottom row first
    lit = [x for x in v if x > 0.0]
    if not lit:
        return 0.0
    lit_mean = sum(lit) / len(lit)
    table = [0.0] * ((width + 1) * (height + 1))  # summed-area table, a zero row and column in front
    for y in range(height):
        row = 0.0
        for x in range(width):
            row += v[y * width + x]
            table[(y + 1) * (width + 1) + x + 1] = table[y * (width + 1) + x + 1] + row
    at = lambda x, y: table[y * (width + 1) + x]
    region = empty = 0
    for y in range(height):
        for x in range(width):
            x0, x1 = max(x - 7, 0), min(x + 8, width)
            y0, y1 = max(y - 7, 0), min(y + 8, height)
            mean = (at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0)) / ((x1 - x0) * (y1 - y0))
            if mean > 0.1 * lit_mean:
                region += 1
                empty += v[y * width + x] == 0.0
    return empty / region if region else 0.0


def upsample(w, h, c, values, w2, h2):
    """values (w x h x c, rows in file order) resampled to w2 x h2 as a bilinear sampler reads it."""
    def taps(n, n2, i):
        x = (i + 0.5) * n / n2 - 0.5
        x0 = math.floor(x)
        f = x - x0
        return min(max(x0, 0), n - 1), min(max(x0 + 1, 0), n - 1), f
    columns = [taps(w, w2, i) for i in range(w2)]
    out = []
    for j in range(h2):
        y0, y1, fy = taps(h, h2, j)
        for x0, x1, fx in columns:
            for k in range(c):
                at = lambda x, y: values[(y * w + x) * c + k]
                top = at(x0, y0) * (1 - fx) + at(x1, y0) * fx
                bottom = at(x0, y1) * (1 - fx) + at(x1, y1) * fx
                out.append(top * (1 - fy) + bottom * fy)
    return out


def box_downsample(w, h, c, values, f):
    """The mean of each f×f block: a buffer rendered at f times the reference's size per axis,
    brought to it as f² samples per pixel (docs/accuracy.md, "What the remaining error is not")."""
    out = []
    for y in range(h // f):
        for x in range(w // f):
            for k in range(c):
                total = sum(values[((y * f + j) * w + x * f + i) * c + k] for j in range(f) for i in range(f))
                out.append(total / (f * f))
    return out


def box_blur(w, h, c, values, n):
    """Each pixel the mean of the n×n box around it, over the part of the box inside the buffer."""
    r = n // 2
    out = [0.0] * len(values)
    for k in range(c):
        table = [0.0] * ((w + 1) * (h + 1))  # summed-area table, a zero row and column in front
        for y in range(h):
            row = 0.0
            for x in range(w):
                row += values[(y * w + x) * c + k]
                table[(y + 1) * (w + 1) + x + 1] = table[y * (w + 1) + x + 1] + row
        for y in range(h):
            y0, y1 = max(y - r, 0), min(y + r + 1, h)
            for x in range(w):
                x0, x1 = max(x - r, 0), min(x + r + 1, w)
                total = (table[y1 * (w + 1) + x1] - table[y0 * (w + 1) + x1]
                         - table[y1 * (w + 1) + x0] + table[y0 * (w + 1) + x0])
                out[(y * w + x) * c + k] = total / ((x1 - x0) * (y1 - y0))
    return out


def main():
    args = sys.argv[1:]
    blur = 1
    if "--blur" in args:
        i = args.index("--blur")
        if i + 1 >= len(args) or not args[i + 1].isdigit() or int(args[i + 1]) < 1:
            sys.exit("--blur takes a box size in pixels, a whole number of at least 1")
        blur = int(args[i + 1])
        del args[i:i + 2]
    if len(args) not in (1, 2):
        sys.exit(__doc__)
    w, h, c, gpu = read_pfm(args[0])
    if len(args) == 1:
        print("%s: gap fraction %.4f" % (args[0], gap_fraction(w, h, c, gpu)))
        return
    w2, h2, c2, ref = read_pfm(args[1])
    if c == c2 and w <= w2 and h <= h2 and (w, h) != (w2, h2):
        print("%s: %dx%d upsampled to the reference's %dx%d" % (args[0], w, h, w2, h2))
        gpu, w, h = upsample(w, h, c, gpu, w2, h2), w2, h2
    if c == c2 and w > w2 and w % w2 == 0 and w // w2 == h // h2 and h % h2 == 0:
        f = w // w2
        print("%s: %dx%d averaged over %dx%d blocks to the reference's %dx%d" % (args[0], w, h, f, f, w2, h2))
        gpu, w, h = box_downsample(w, h, c, gpu, f), w2, h2
    if (w, h, c) != (w2, h2, c2):
        sys.exit("%s is %dx%dx%d, %s is %dx%dx%d" % (args[0], w, h, c, args[1], w2, h2, c2))
    if blur > 1:
        print("both buffers averaged over %dx%d boxes" % (blur, blur))
        gpu, ref = box_blur(w, h, c, gpu, blur), box_blur(w, h, c, ref, blur)
    mean_ref = sum(ref) / len(ref)
    rmse = math.sqrt(sum((g - r) ** 2 for g, r in zip(gpu, ref)) / len(ref)) / mean_ref
    print("%s: relative RMSE %.3f, flux %+.2f %%" % (args[0], rmse, 100 * (sum(gpu) / sum(ref) - 1)))
    half_path = os.path.join(os.path.dirname(args[1]), "caustics_half.pfm")
    if os.path.basename(args[1]) == "caustics.pfm" and os.path.exists(half_path):
        w3, h3, c3, half = read_pfm(half_path)
        if (w3, h3, c3) == (w2, h2, c2):
            if blur > 1:
                half = box_blur(w3, h3, c3, half, blur)
            # The halves' difference has the reference's own noise (src/reference/mod.rs).
            own = math.sqrt(sum((a - r) ** 2 for a, r in zip(half, ref)) / len(ref)) / mean_ref
            print("  the reference's own error, from its two halves: %.3f; without it the figure reads %.3f"
                  % (own, math.sqrt(max(rmse * rmse - own * own, 0.0))))


if __name__ == "__main__":
    main()
