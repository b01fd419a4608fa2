#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets: tests/fuzz/corpus/{png,code}/.

The files are committed; this script documents how they were made and remakes
them (python3 standard library only): python3 tests/fuzz/make_corpus.py
PNGs are small (under 2 KB) and cover every colour type and bit depth,
interlacing, tRNS, several IDAT chunks, ancillary chunks and an iCCP profile.
Files named regression-* are inputs the fuzzer found; this script leaves them.
"""
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2),
         (0, 1, 1, 2)]  # (x0, y0, dx, dy)
SAMPLES = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def pack_row(pixels, depth):
    """Filter byte 0, then the samples of `pixels` (tuples) packed at `depth` bits."""
    samples = [s for pixel in pixels for s in pixel]
    out = bytearray([0])
    if depth == 16:
        for s in samples:
            out += struct.pack(">H", s)
    elif depth == 8:
        out += bytes(samples)
    else:
        per_byte = 8 // depth
        for i in range(0, len(samples), per_byte):
            byte = 0
            for j, s in enumerate(samples[i:i + per_byte]):
                byte |= s << (8 - depth * (j + 1))
            out.append(byte)
    return bytes(out)


def png(width, height, depth, color_type, pixel, interlace=False, before_idat=(), after_idat=(),
        idat_parts=1, level=9):
    """A PNG whose pixel (x, y) is the sample tuple pixel(x, y)."""
    raw = bytearray()
    if interlace:
        for x0, y0, dx, dy in ADAM7:
            xs = range(x0, width, dx)
            if not xs:
                continue
            for y in range(y0, height, dy):
                raw += pack_row([pixel(x, y) for x in xs], depth)
    else:
        for y in range(height):
            raw += pack_row([pixel(x, y) for x in range(width)], depth)
    data = zlib.compress(bytes(raw), level)
    step = -(-len(data) // idat_parts)
    idats = b"".join(chunk(b"IDAT", data[i:i + step]) for i in range(0, len(data), step))
    ihdr = struct.pack(">IIBBBBB", width, height, depth, color_type, 0, 0, 1 if interlace else 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + b"".join(before_idat) + idats +
            b"".join(after_idat) + chunk(b"IEND", b""))


def gray(depth):
    top = (1 << depth) - 1
    return lambda x, y: ((x * 3 + y * 5 + (x // 4 + y // 3) % 2 * top // 2) % (top + 1),)


def colour(depth, samples):
    top = (1 << depth) - 1
    return lambda x, y: tuple((x * 37 + y * 19 + c * 71) * (top // 255 or 1) % (top + 1)
                              for c in range(samples))


def palette_chunks(entries, transparent=0):
    plte = b"".join(bytes(t) for t in ((i * 53 % 256, (255 - i * 29) % 256, i * 7 % 256)
                                        for i in range(entries)))
    out = [chunk(b"PLTE", plte)]
    if transparent:
        out.append(chunk(b"tRNS", bytes(range(0, 255, 255 // transparent))[:transparent]))
    return out


def icc_profile():
    """A minimal ICC v2 display profile header for RGB with no tags."""
    header = struct.pack(">I4sI4s4s4s", 132, b"none", 0x02100000, b"mntr", b"RGB ", b"XYZ ")
    header += bytes(12)  # date
    header += b"acsp" + b"APPL" + bytes(4) + b"none" + b"none" + bytes(8) + struct.pack(">I", 0)
    header += struct.pack(">iii", 63190, 65536, 54061)  # D50 illuminant
    header += b"none" + bytes(16) + bytes(28)
    assert len(header) == 128, len(header)
    return header + struct.pack(">I", 0)  # tag count


def write_pngs(directory):
    iccp = chunk(b"iCCP", b"fssim test\x00\x00" + zlib.compress(icc_profile()))
    ancillary = [
        chunk(b"gAMA", struct.pack(">I", 45455)),
        chunk(b"cHRM", struct.pack(">8I", 31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000)),
        chunk(b"pHYs", struct.pack(">IIB", 2835, 2835, 1)),
        chunk(b"tEXt", b"Comment\x00fuzz seed"),
        chunk(b"zTXt", b"Title\x00\x00" + zlib.compress(b"a compressed title")),
        chunk(b"tIME", struct.pack(">HBBBBB", 2012, 5, 6, 7, 8, 9)),
    ]
    files = {
        "gray1.png": png(33, 9, 1, 0, gray(1)),
        "gray2-interlaced.png": png(19, 11, 2, 0, gray(2), interlace=True),
        "gray4.png": png(17, 5, 4, 0, gray(4)),
        "gray8.png": png(24, 16, 8, 0, gray(8)),
        "gray8-trns-split.png": png(20, 10, 8, 0, gray(8), before_idat=[chunk(b"tRNS", b"\x00\x07")],
                                    idat_parts=3),
        "gray16.png": png(12, 7, 16, 0, gray(16)),
        "gray-1x1.png": png(1, 1, 8, 0, lambda x, y: (200,)),
        "rgb8.png": png(16, 12, 8, 2, colour(8, 3)),
        "rgb8-ancillary.png": png(10, 6, 8, 2, colour(8, 3), before_idat=ancillary[:3],
                                  after_idat=ancillary[3:]),
        "rgb8-iccp.png": png(9, 7, 8, 2, colour(8, 3), before_idat=[iccp]),
        "rgb16-interlaced.png": png(13, 9, 16, 2, colour(16, 3), interlace=True),
        "palette1-trns.png": png(29, 6, 1, 3, lambda x, y: ((x + y) % 2,),
                                 before_idat=palette_chunks(2, transparent=1)),
        "palette4.png": png(21, 8, 4, 3, lambda x, y: ((x * y) % 12,),
                            before_idat=palette_chunks(12)),
        "palette8-interlaced-trns.png": png(18, 14, 8, 3, lambda x, y: ((x * 7 + y) % 40,),
                                            interlace=True,
                                            before_idat=palette_chunks(40, transparent=5)),
        "graya8.png": png(14, 9, 8, 4, colour(8, 2)),
        "graya16.png": png(8, 8, 16, 4, colour(16, 2)),
        "rgba8-interlaced.png": png(15, 10, 8, 6, colour(8, 4), interlace=True),
        "rgba16.png": png(7, 5, 16, 6, colour(16, 4)),
    }
    for name, data in files.items():
        assert len(data) < 2048, (name, len(data))
        with open(os.path.join(directory, name), "wb") as f:
            f.write(data)


RASKAR = "1010000111000001010000110011110111010111001001100111"


def write_codes(directory):
    files = {
        "reference-code.txt": "".join(bit + ";\n" for bit in RASKAR),
        "spaces.txt": " ".join(RASKAR) + "\n",
        "commas.txt": ", ".join(RASKAR[:20]),
        "semicolons-crlf.txt": ";\r\n".join(RASKAR[:12]) + ";\r\n",
        "comments.txt": "# a code\n1 0 1  # inline\n\n# blank line above\n0.5 0.25\n",
        "reals.txt": "-0.0214 1.000000e+00 0.73351 -1.2e-3\t+0.5\n.25 5. 3e2\n",
        "single.txt": "1",
        "analog.txt": "0\n0.125\n1\n0.5\n",
        "bad-token.txt": "1 0 1\nx1 0\n",
        "nan.txt": "1; nan; 1;",
    }
    for name, text in files.items():
        with open(os.path.join(directory, name), "w", newline="") as f:
            f.write(text)


if __name__ == "__main__":
    for kind, writer in (("png", write_pngs), ("code", write_codes)):
        directory = os.path.join(HERE, "corpus", kind)
        os.makedirs(directory, exist_ok=True)
        writer(directory)
