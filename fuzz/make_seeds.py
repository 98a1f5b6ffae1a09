#!/usr/bin/env python3
"""Writes the small seed files of fuzz/corpus/load_image/ (stdlib only).

Each seed is one byte choosing the format (0 GIF, 1 POT, 2 PNG, 3 PGM,
4 PPM, 5 TGA, as the load_image target reads it) followed by a tiny image.
"""
import struct, zlib, os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "load_image")
W, H = 4, 3
PIX = [(x * 60 + y * 20) % 256 for y in range(H) for x in range(W)]


def gif(w, h, pix, interlaced=False):
    # Global palette of 256 entries; LZW with min code size 8 and 9-bit
    # codes throughout (clear, literals, end: the table never reaches 512).
    pal = b"".join(bytes((i, 255 - i, i // 2)) for i in range(256))
    out = b"GIF89a" + struct.pack("<HHBBB", w, h, 0xF7, 0, 0) + pal
    rows = list(range(h))
    if interlaced:
        rows = [r for s, st in ((0, 8), (4, 8), (2, 4), (1, 2)) for r in range(s, h, st)]
    stored = [pix[r * w + x] for r in rows for x in range(w)]
    codes = [256] + stored + [257]
    acc = nbits = 0
    data = bytearray()
    for c in codes:
        acc |= c << nbits
        nbits += 9
        while nbits >= 8:
            data.append(acc & 255)
            acc >>= 8
            nbits -= 8
    if nbits:
        data.append(acc & 255)
    out += b"\x2c" + struct.pack("<HHHHB", 0, 0, w, h, 0x40 if interlaced else 0)
    out += b"\x08"
    for i in range(0, len(data), 255):
        chunk = data[i:i + 255]
        out += bytes((len(chunk),)) + chunk
    return out + b"\x00\x3b"


def png(w, h, color_type, bit_depth, rows, plte=None):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + r for r in rows)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth, color_type, 0, 0, 0))
    if plte is not None:
        out += chunk(b"PLTE", plte)
    return out + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def tga(image_type, bits, pixels, descriptor=0x20, cmap=None):
    cmap_type = 1 if cmap else 0
    cmap_len = len(cmap) // 3 if cmap else 0
    head = struct.pack("<BBBHHBHHHHBB", 0, cmap_type, image_type, 0, cmap_len, 24 if cmap else 0,
                       0, 0, W, H, bits, descriptor)
    return head + (cmap or b"") + pixels


def write(name, fmt, body):
    with open(os.path.join(OUT, "seed-" + name), "wb") as f:
        f.write(bytes((fmt,)) + body)


os.makedirs(OUT, exist_ok=True)
write("gif", 0, gif(W, H, PIX))
write("gif-interlaced", 0, gif(W, 9, [(i * 7) % 256 for i in range(W * 9)], interlaced=True))
write("pot", 1, gif(2 * W, H, [(i * 13) % 256 for i in range(2 * W * H)]))
rows8 = [bytes(PIX[y * W:(y + 1) * W]) for y in range(H)]
write("png-gray8", 2, png(W, H, 0, 8, rows8))
write("png-gray16", 2, png(W, H, 0, 16, [b"".join(struct.pack(">H", v * 257) for v in r) for r in rows8]))
write("png-indexed4", 2, png(W, H, 3, 4, [bytes(((r[0] & 15) << 4 | (r[1] & 15), (r[2] & 15) << 4 | (r[3] & 15))) for r in rows8],
                          plte=bytes(range(48))))
write("png-rgb8", 2, png(W, H, 2, 8, [b"".join(bytes((v, 255 - v, 0)) for v in r) for r in rows8]))
write("png-rgba16", 2, png(W, H, 6, 16, [b"".join(struct.pack(">HHHH", v * 257, v * 100, 7, 65535) for v in r) for r in rows8]))
write("pgm-p5", 3, b"P5\n# seed\n%d %d\n255\n" % (W, H) + bytes(PIX))
write("pgm-p2-wide", 3, b"P2 %d %d 1000\n" % (W, H) + b" ".join(b"%d" % (v * 3) for v in PIX) + b"\n")
write("ppm-p6", 4, b"P6 %d %d 255\n" % (W, H) + b"".join(bytes((v, v, v)) for v in PIX))
write("ppm-p3-16", 4, b"P3 %d %d 65535\n" % (W, H) + b" ".join(b"%d %d %d" % (v * 257, v, 3) for v in PIX))
write("tga-gray", 5, tga(3, 8, bytes(PIX)))
write("tga-rgb-rle-bottom-up", 5, tga(10, 24, b"\x83\x10\x20\x30" + b"\x07" + b"".join(bytes((v, v, 1)) for v in PIX[:8]), descriptor=0))
write("tga-mapped", 5, tga(1, 8, bytes(v % 16 for v in PIX), cmap=bytes(range(48))))
write("tga-rgb16", 5, tga(2, 16, b"".join(struct.pack("<H", v * 97) for v in PIX)))
