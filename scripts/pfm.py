"""PFM reading for the scripts beside this file (the format `underlight render --hdr` and
`underlight reference` write): width, height, channels, and the floats as the file stores
them, bottom row first, channels interleaved."""
import struct


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        count = width * height * channels
        values = struct.unpack(("<" if scale < 0 else ">") + "%df" % count, f.read(4 * count))
    return width, height, channels, values


def read_rgb_pfms(paths):
    """The RGB PFMs at `paths`, which must share one size: (width, height, [values per file]).
    Exits naming the file that is not RGB, or the sizes that differ."""
    sizes, buffers = set(), []
    for path in paths:
        width, height, channels, values = read_pfm(path)
        if channels != 3:
            raise SystemExit("%s: expected an RGB PFM" % path)
        sizes.add((width, height))
        buffers.append(values)
    if len(sizes) != 1:
        raise SystemExit("the buffers differ in size: %s" % sorted(sizes))
    (width, height), = sizes
    return width, height, buffers
