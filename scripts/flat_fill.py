#!/usr/bin/env python3
"""What filling a GPU caustic buffer's holes with flat water's light would do (a fill tried
offline and not built; docs/accuracy.md, "flat water's light where no photon landed"). The
flat-water buffer is the reference's for a copy of the scene file with `amplitude = 0` and
`noise_amplitude = 0` (a new `name`, so the reference cache keeps them apart):

    underlight reference --scene storage --photons 64000000 --out out/ref
    underlight reference --scene out/storage-flat.toml --width 1440 --height 850 --photons 64000000 --out out/flat
    underlight render --scene storage --frames 1 --hdr out/gpu --hdr-format pfm --out out/gpu/o.png
    python3 scripts/flat_fill.py out/gpu/caustics.pfm out/ref/caustics.pfm out/flat/caustics.pfm

(the scene file's `obj` path is relative to it: copy the .obj and .mtl beside it). Printed,
for the buffer as it is and filled where it holds exactly zero (every such pixel flat water
lights, then only those at least r = 1, 2, 3, 5 pixels inside flat water's light: all of the
(2r+1)² pixels around lit): relative RMSE and flux against the reference as compare.py
measures them, holes as `holes.py --as-metrics` counts them, and the reference's light over
the fill's in the filled pixels. Pure Python, like the scripts beside it.
"""
import sys

from pfm import read_rgb_pfms


def window_all(w, h, mask, r):
    """Whether every pixel within r (Chebyshev) of each pixel is set, outside the image unset."""
    table = [0] * ((w + 1) * (h + 1))
    for y in range(h):
        run = 0
        for x in range(w):
            run += mask[y * w + x]
            table[(y + 1) * (w + 1) + x + 1] = table[y * (w + 1) + x + 1] + run
    full = (2 * r + 1) ** 2
    out = [False] * (w * h)
    for y in range(r, h - r):
        for x in range(r, w - r):
            x0, x1, y0, y1 = x - r, x + r + 1, y - r, y + r + 1
            s = table[y1 * (w + 1) + x1] - table[y0 * (w + 1) + x1] - table[y1 * (w + 1) + x0] + table[y0 * (w + 1) + x0]
            out[y * w + x] = s == full
    return out


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    w, h, (gpu, ref, flat) = read_rgb_pfms(sys.argv[1:4])
    n = w * h
    ref0 = ref[0::3]
    nonzero = [v for v in ref0 if v > 0.0]
    threshold = 0.1 * sum(nonzero) / max(len(nonzero), 1)
    lit_all = window_all(w, h, [1 if v > threshold else 0 for v in ref0], 1)
    region = sum(lit_all)
    ref_mean = sum(ref) / len(ref)
    ref_sum = sum(ref)

    def report(name, buffer, filled):
        sq = sum((a - b) ** 2 for a, b in zip(buffer, ref))
        holes = sum(1 for i in range(n) if lit_all[i] and buffer[3 * i] == 0.0)
        line = "%-28s relative RMSE %.4f, flux %+.2f %%, holes %.2f %%" % (
            name, (sq / len(ref)) ** 0.5 / ref_mean, 100.0 * (sum(buffer) / ref_sum - 1.0), 100.0 * holes / region)
        if filled:
            fill = sum(flat[3 * i + k] for i in filled for k in range(3))
            there = sum(ref[3 * i + k] for i in filled for k in range(3))
            line += ", %d pixels filled, the reference's light there %.2f of the fill's" % (len(filled), there / fill)
        print(line)

    report("as rendered", gpu, [])
    zero = [gpu[3 * i] == 0.0 for i in range(n)]
    flat_lit = [1 if flat[3 * i] > 0.0 else 0 for i in range(n)]
    for r in (0, 1, 2, 3, 5):
        inside = flat_lit if r == 0 else window_all(w, h, flat_lit, r)
        filled = [i for i in range(n) if zero[i] and inside[i]]
        buffer = list(gpu)
        for i in filled:
            buffer[3 * i:3 * i + 3] = flat[3 * i:3 * i + 3]
        report("filled" if r == 0 else "filled %d px inside" % r, buffer, filled)


if __name__ == "__main__":
    main()
