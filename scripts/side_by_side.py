#!/usr/bin/env python3
"""Caustic (or godray) buffers side by side, one row per scene, one column per buffer, all of
a row at one exposure: the first column's 99.5th percentile maps to white, with a square-root
curve so that faint light stays visible. Pure Python (no imaging library): reads PFM, writes
PNG. docs/accuracy.md's estimator pictures come from it:

    underlight reference --scene tank --width 320 --height 200 --out out/ref/tank
    underlight render --scene tank --width 320 --height 200 --frames 1 --hdr out/gpu/tank --out out/gpu/tank.png
    python3 scripts/side_by_side.py docs/x.png out/ref/tank/caustics.pfm out/gpu/tank/caustics.pfm \\
        -- out/ref/port/caustics.pfm out/gpu/port/caustics.pfm

Arguments: [--scale S] [--upsample] [--crop X0,Y0,X1,Y1] the output PNG, then the PFM files of
the first row, "--", those of the next, ... Every image is drawn at S times its size (nearest;
1.5 unless given), with a 4-pixel grey gutter. docs/godray-methods.png is the godray buffers
at --scale 4.5. With --upsample, a buffer smaller than its row's first is drawn upsampled to
that size as compose reads it (bilinear between texel centres; docs/caustic-target-scale.png).
With --crop, every image is cut to the pixels x0 <= x < x1, y0 <= y < y1 (from the top left)
before it is drawn, and the exposure comes from the row's first crop
(docs/light-map-steeper.png, docs/caustic-brightness-survey.png).
"""
import struct
import sys
import zlib

from compare import upsample
from pfm import read_pfm

SCALE = 1.5
GUTTER = 4


def read_rows(path):
    """Channel sums of a PFM as rows from the top, with its width and height."""
    width, height, channels, values = read_pfm(path)
    rows = []
    for y in reversed(range(height)):  # PFM stores the bottom row first
        row = values[y * width * channels:(y + 1) * width * channels]
        rows.append([sum(row[x * channels:(x + 1) * channels]) for x in range(width)])
    return width, height, rows


def percentile(rows, q):
    flat = sorted(v for row in rows for v in row)
    return flat[min(len(flat) - 1, int(q * len(flat)))]


def write_png(path, width, height, grey_rows):
    raw = b"".join(b"\x00" + bytes(row) for row in grey_rows)
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def main():
    global SCALE
    if len(sys.argv) > 2 and sys.argv[1] == "--scale":
        SCALE = float(sys.argv[2])
        del sys.argv[1:3]
    upsampled = len(sys.argv) > 1 and sys.argv[1] == "--upsample"
    if upsampled:
        del sys.argv[1]
    crop = None
    if len(sys.argv) > 2 and sys.argv[1] == "--crop":
        try:
            crop = [int(v) for v in sys.argv[2].split(",")]
        except ValueError:
            crop = []
        if len(crop) != 4 or crop[0] < 0 or crop[1] < 0 or crop[2] <= crop[0] or crop[3] <= crop[1]:
            sys.exit("--crop takes X0,Y0,X1,Y1: whole pixels from the top left, X1 > X0 >= 0, Y1 > Y0 >= 0")
        del sys.argv[1:3]
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, rest = sys.argv[1], sys.argv[2:]
    groups, group = [], []
    for arg in rest:
        if arg == "--":
            groups.append(group)
            group = []
        else:
            group.append(arg)
    groups.append(group)
    images = [[read_rows(p) for p in g] for g in groups if g]
    if upsampled:
        for row_images in images:
            w0, h0, _ = row_images[0]
            for i, (w, h, pixels) in enumerate(row_images):
                if (w, h) != (w0, h0) and w <= w0 and h <= h0:
                    flat = upsample(w, h, 1, [v for row in pixels for v in row], w0, h0)
                    row_images[i] = (w0, h0, [flat[y * w0:(y + 1) * w0] for y in range(h0)])
    if crop:
        x0, y0, x1, y1 = crop
        for row_images in images:
            for i, (w, h, pixels) in enumerate(row_images):
                if x1 > w or y1 > h:
                    sys.exit("--crop %d,%d,%d,%d reaches past a %dx%d image" % (x0, y0, x1, y1, w, h))
                row_images[i] = (x1 - x0, y1 - y0, [row[x0:x1] for row in pixels[y0:y1]])
    columns = max(len(g) for g in images)
    cell_w = max(int(w * SCALE) for g in images for (w, _, _) in g)
    cell_h = max(int(h * SCALE) for g in images for (_, h, _) in g)
    width = columns * cell_w + (columns - 1) * GUTTER
    height = len(images) * cell_h + (len(images) - 1) * GUTTER
    canvas = [[128] * width for _ in range(height)]
    for r, row_images in enumerate(images):
        white = percentile(row_images[0][2], 0.995) or 1.0
        for c, (w, h, pixels) in enumerate(row_images):
            x0, y0 = c * (cell_w + GUTTER), r * (cell_h + GUTTER)
            for y in range(cell_h):
                for x in range(cell_w):
                    sx, sy = int(x / SCALE), int(y / SCALE)
                    if sx < w and sy < h:
                        v = max(0.0, min(1.0, pixels[sy][sx] / white)) ** 0.5
                        canvas[y0 + y][x0 + x] = int(round(255 * v))
    write_png(out, width, height, canvas)
    print("wrote %s (%dx%d)" % (out, width, height))


if __name__ == "__main__":
    main()
