#!/usr/bin/env python3
"""A one-dimensional model of the footprint hats (docs/accuracy.md, "A higher-order hat, in one
dimension"): how much a hat that follows the refracted map's curvature could gain over the
shipped affine hat, and what it needs to gain it. numpy.

Photons at spacing h (pixels of the target, where the map is the identity) on u are refracted
to x(u) = u + A sin(ku + p) + A/2 sin(2.3ku + 1.7p): with A·k > 1 the map folds, and its
irradiance has the caustics' 1/sqrt singularities. The reference bins 1000 photons a pixel of u;
each estimator spreads a photon's flux h over pixels [0, 400):

- affine: the shipped hat's 1-D twin: a tent on x(u_i) ± |d|, d = (x_{i+1} - x_{i-1}) / 2;
- quadratic, exact: the tent in u carried through x(s) = x_i + d s + a s^2 / 2 (a the second
  difference), integrated exactly over each pixel (sampled densely in s);
- quadratic, sampled: the same hat read the way the fragment shader reads one, at S points a
  pixel: each point's preimages in s (both roots), the tent over |dx/ds| (clamped at CLAMP
  times the photon's own 1/|d|), each hat renormalised to its flux;
- piecewise-linear: the refracted segments with flux h each (the triangles' 1-D twin);
- three sub-hats: the tent split exactly into three tents half as wide at s = -1/2, 0, 1/2
  (weights 1/4, 1/2, 1/4), each placed on the quadratic and spread affinely by its own
  derivative there, read as the fragment shader reads a hat (at S points a pixel, each
  sub-hat at least the samples' spacing wide): the quadratic hat in a form a fragment can
  read (docs/accuracy.md, "The curved hat on the scenes").

Prints each one's relative RMSE against the reference at h = 1, 2, 3 (the scenes' own sizes
put the photons about 2 pixels apart), the mean over four random maps.

    python3 scripts/hat_order_1d.py
"""
import numpy as np

WIDTH = 400  # pixels
SAMPLES = 4  # a pixel's samples, as the fragment shader's FOOTPRINT_HAT_SAMPLES per axis
CLAMP = 8.0


def refract(u, a, k, p):
    return u + a * np.sin(k * u + p) + 0.5 * a * np.sin(2.3 * k * u + 1.7 * p)


def binned(x, weights):
    return np.histogram(x, bins=WIDTH, range=(0, WIDTH), weights=weights)[0]


def estimates(a, k, p, h):
    fine = np.arange(-50, WIDTH + 50, 1e-3)
    reference = binned(refract(fine, a, k, p), np.full(fine.size, 1e-3))
    u = np.arange(-50, WIDTH + 50, h)
    x = refract(u, a, k, p)
    s = np.linspace(-1, 1, 801)[1:-1]
    w = (1 - np.abs(s)) * h * (s[1] - s[0])
    pixels = (np.arange(WIDTH)[:, None] + (np.arange(SAMPLES) + 0.5) / SAMPLES).ravel()
    out = {name: np.zeros(WIDTH) for name in ("affine", "quadratic, exact", "quadratic, sampled", "piecewise-linear", "three sub-hats")}
    for i in range(1, len(u) - 1):
        d = 0.5 * (x[i + 1] - x[i - 1])
        c = x[i + 1] - 2 * x[i] + x[i - 1]
        out["affine"] += binned(x[i] + abs(d) * s, w)
        out["quadratic, exact"] += binned(x[i] + d * s + 0.5 * c * s * s, w)
        lo, hi = min(x[i - 1], x[i + 1]) - abs(c), max(x[i - 1], x[i + 1]) + abs(c)
        q = pixels[(pixels > lo) & (pixels < hi)]
        if q.size and abs(d) > 1e-9:
            value = np.zeros_like(q)
            if abs(c) < 1e-9:
                roots = [(q - x[i]) / d]
            else:
                disc = d * d - 2 * c * (x[i] - q)
                root = np.sqrt(np.maximum(disc, 0))
                roots = [np.where(disc >= 0, (-d + sgn * root) / c, 9.0) for sgn in (1, -1)]
            for r in roots:
                slope = np.maximum(np.abs(d + c * r), abs(d) / CLAMP)
                value += np.maximum(1 - np.abs(r), 0) / slope
            total = value.sum() / SAMPLES
            if total > 0:
                value *= h / total
            out["quadratic, sampled"] += np.bincount(q.astype(int), weights=value, minlength=WIDTH)[:WIDTH] / SAMPLES
        for sk, weight in ((-0.5, 0.25), (0.0, 0.5), (0.5, 0.25)):
            centre, half = x[i] + d * sk + 0.5 * c * sk * sk, max(abs(d + c * sk) / 2, 1 / SAMPLES)
            q = pixels[np.abs(pixels - centre) < half]
            value = weight * h * (1 - np.abs(q - centre) / half) / half / SAMPLES
            out["three sub-hats"] += np.bincount(q.astype(int), weights=value, minlength=WIDTH)[:WIDTH]
        lo, hi = sorted((x[i], x[i + 1]))
        span = np.clip(np.minimum(hi, np.arange(WIDTH) + 1) - np.maximum(lo, np.arange(WIDTH)), 0, None)
        out["piecewise-linear"] += h * span / max(hi - lo, 1e-9) if hi - lo > 1e-9 else binned([lo], [h])
    mean = reference.mean()
    return {name: np.sqrt(((e - reference) ** 2).mean()) / mean for name, e in out.items()}


def main():
    rng = np.random.default_rng(1)
    maps = [(rng.uniform(4, 10), rng.uniform(0.15, 0.4), rng.uniform(0, 6)) for _ in range(4)]
    print("relative RMSE against the reference, mean of four maps")
    for h in (1.0, 2.0, 3.0):
        rows = [estimates(a, k, p, h) for a, k, p in maps]
        print(f"photons {h:.0f} px apart: " + ", ".join(f"{n} {np.mean([r[n] for r in rows]):.3f}" for n in rows[0]))


if __name__ == "__main__":
    main()
