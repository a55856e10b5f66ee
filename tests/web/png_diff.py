#!/usr/bin/env python3
"""png_diff.py A.png B.png: mean absolute difference of two 8-bit PNGs of equal size, in [0, 1]
(RGB; alpha ignored). A minimal reader (zlib + the five scanline filters), so the browser test needs
nothing beyond Python's standard library."""
import struct, sys, zlib


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"png_diff.py: {path}: not a PNG")
    pos, idat, w = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            if depth != 8 or colour not in (2, 6):
                sys.exit(f"png_diff.py: {path}: only 8-bit RGB/RGBA")
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([line[x * bpp:x * bpp + 3] for x in range(w)])
        prev = line
    return w, h, rows


(wa, ha, a), (wb, hb, b) = read_png(sys.argv[1]), read_png(sys.argv[2])
if (wa, ha) != (wb, hb):
    sys.exit(f"png_diff.py: sizes differ: {wa}x{ha} and {wb}x{hb}")
total = sum(abs(pa[c] - pb[c]) for ra, rb in zip(a, b) for pa, pb in zip(ra, rb) for c in range(3))
print(f"{total / (255.0 * 3 * wa * ha):.5f}")
