#!/usr/bin/env python3
"""Where a GPU caustic buffer's error against the reference lies (docs/accuracy.md, "Triangles
of about a pixel"): the two buffers' value distributions (quantiles over the reference's mean),
the relative RMSE with the GPU buffer moved by a quarter pixel (a misregistration would lower
it), the share of the squared error in the reference's brightest pixels, and the error of both
buffers blurred by a 3x3 box. Channel sums; buffers of the same size. Pure Python.

    underlight reference --scene tank --width 320 --height 200 --out out/ref
    underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/gpu --out out/gpu/o.png
    python3 scripts/error_structure.py out/gpu/caustics.pfm out/ref/caustics.pfm
"""
import math
import sys

from pfm import read_pfm


def channel_sums(path):
    width, height, channels, values = read_pfm(path)
    return width, height, [sum(values[i * channels:(i + 1) * channels]) for i in range(width * height)]


def shifted(v, width, height, dx, dy):
    """v moved by (dx, dy) pixels, bilinearly, clamped at the border."""
    out = [0.0] * len(v)
    for y in range(height):
        for x in range(width):
            sx = min(max(x - dx, 0.0), width - 1.0)
            sy = min(max(y - dy, 0.0), height - 1.0)
            x0, y0 = int(sx), int(sy)
            x1, y1 = min(x0 + 1, width - 1), min(y0 + 1, height - 1)
            fx, fy = sx - x0, sy - y0
            out[y * width + x] = (v[y0 * width + x0] * (1 - fx) * (1 - fy) + v[y0 * width + x1] * fx * (1 - fy)
                                  + v[y1 * width + x0] * (1 - fx) * fy + v[y1 * width + x1] * fx * fy)
    return out


def box3(v, width, height):
    out = [0.0] * len(v)
    for y in range(height):
        for x in range(width):
            taps = [v[min(max(y + j, 0), height - 1) * width + min(max(x + i, 0), width - 1)]
                    for j in (-1, 0, 1) for i in (-1, 0, 1)]
            out[y * width + x] = sum(taps) / 9.0
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: error_structure.py GPU.pfm REFERENCE.pfm")
    w, h, gpu = channel_sums(sys.argv[1])
    w2, h2, ref = channel_sums(sys.argv[2])
    if (w, h) != (w2, h2):
        sys.exit(f"the buffers differ in size: {w}x{h} against {w2}x{h2}")
    mean = sum(ref) / len(ref)
    rmse = lambda a: math.sqrt(sum((p - q) ** 2 for p, q in zip(a, ref)) / len(ref)) / mean
    print(f"relative RMSE {rmse(gpu):.3f}")
    gs, rs = sorted(gpu, reverse=True), sorted(ref, reverse=True)
    for q in (0.001, 0.01, 0.1, 0.5):
        i = int(q * len(ref))
        print(f"top {100 * q:g} % quantile over the reference's mean: GPU {gs[i] / mean:.2f}, reference {rs[i] / mean:.2f}")
    for dx, dy in ((0.25, 0), (-0.25, 0), (0, 0.25), (0, -0.25)):
        print(f"GPU moved by ({dx:+}, {dy:+}) px: {rmse(shifted(gpu, w, h, dx, dy)):.3f}")
    print(f"reference moved by 0.5 px against itself: "
          f"{math.sqrt(sum((p - q) ** 2 for p, q in zip(shifted(ref, w, h, 0.5, 0), ref)) / len(ref)) / mean:.3f}")
    squared = [(p - q) ** 2 for p, q in zip(gpu, ref)]
    order = sorted(range(len(ref)), key=lambda i: -ref[i])
    top = sum(squared[i] for i in order[:len(ref) // 10])
    print(f"share of the squared error in the reference's brightest 10 %: {100 * top / sum(squared):.0f} %")
    blurred_ref = box3(ref, w, h)
    blurred = box3(gpu, w, h)
    print(f"both blurred by a 3x3 box: {math.sqrt(sum((p - q) ** 2 for p, q in zip(blurred, blurred_ref)) / len(ref)) / mean:.3f}")


if __name__ == "__main__":
    main()
