#!/usr/bin/env python3
"""Decode an 8-bit grayscale, non-interlaced PNG into raw row-major bytes
(image row 0 first), using only the standard library (zlib).

    python3 tools/png_to_raw.py IN.png OUT.raw

Used once to make data/maunga_whau_87x61.u8.raw, which the firmware embeds
with include_bytes!. Prints width, height and byte count; refuses anything
other than 8-bit gray so the result is exactly width*height bytes.
"""
import struct
import sys
import zlib


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def decode_gray8(data):
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            width, height, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if (depth, color, interlace) != (8, 0, 0):
                raise ValueError(f"need 8-bit gray non-interlaced, got depth={depth} color={color} interlace={interlace}")
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    raw = zlib.decompress(idat)
    out = bytearray()
    prev = bytearray(width)
    stride = width + 1
    for r in range(height):
        ftype, line = raw[r * stride], bytearray(raw[r * stride + 1:(r + 1) * stride])
        for i in range(width):
            a = line[i - 1] if i else 0
            b, c = prev[i], prev[i - 1] if i else 0
            line[i] = (line[i] + (0, a, b, (a + b) // 2, paeth(a, b, c))[ftype]) & 0xFF
        out += line
        prev = line
    return width, height, bytes(out)


if __name__ == "__main__":
    w, h, pixels = decode_gray8(open(sys.argv[1], "rb").read())
    open(sys.argv[2], "wb").write(pixels)
    print(f"width={w} height={h} bytes={len(pixels)} min={min(pixels)} max={max(pixels)}")
