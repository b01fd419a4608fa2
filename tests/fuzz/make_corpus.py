#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets: tests/fuzz/corpus/{png,tiff,code,campaign_file,
campaign_journal,campaign_check,range}/.

The files are committed; this script documents how they were made and remakes
them (python3 standard library only): python3 tests/fuzz/make_corpus.py
PNGs are small (under 2 KB) and cover every colour type and bit depth,
interlacing, tRNS, several IDAT chunks, ancillary chunks and an iCCP profile.
TIFFs are small (under 2 KB) and cover every sample type read (8, 16-bit
unsigned, 32-bit float), gray, gray + alpha, RGB and RGBA, both byte orders,
strips and tiles, contiguous and separate planes, no compression, PackBits and
Deflate, BigTIFF, and layouts that are refused (palette, signed, 64-bit float,
two pages).
Journals and results are those of small campaigns that fssim runs (its path in
$FSSIM, default build/fssim; without it they are left as they are), and
variants of them: torn, a row of another shard, a header alone, too deep.
Files named regression-* are inputs the fuzzer found; this script leaves them.
"""
import os
import shutil
import struct
import subprocess
import tempfile
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


# ---------------------------------------------------------------------------
# TIFF, written by hand: header, strip or tile data, then each page's IFD.

SHORT, LONG, LONG8 = 3, 4, 16
PACK = {SHORT: "H", LONG: "I", LONG8: "Q"}


def packbits(data):
    """PackBits: runs of 3 to 128 equal bytes replicated, the rest literal."""
    out = bytearray()
    i = 0
    while i < len(data):
        run = 1
        while i + run < len(data) and run < 128 and data[i + run] == data[i]:
            run += 1
        if run >= 3:
            out += bytes([257 - run, data[i]])
            i += run
            continue
        start = i
        while i < len(data) and i - start < 128:
            if i + 2 < len(data) and data[i] == data[i + 1] == data[i + 2]:
                break
            i += 1
        out += bytes([i - start - 1]) + data[start:i]
    return bytes(out)


def compress(raw, compression, row_bytes):
    if compression == 8:
        return zlib.compress(raw, 9)
    if compression == 32773:  # row by row, as TIFF requires
        return b"".join(packbits(raw[i:i + row_bytes]) for i in range(0, len(raw), row_bytes))
    return raw


def tiff_page(width, height, spp, bits, fmt, photometric, sample, order="<", planar=1, tile=0,
              compression=1, rows=0, extra=0, colormap=False):
    """(tags, chunks, tiled) of one page whose sample (x, y, s) is sample(x, y, s)."""
    code = {(1, 8): "B", (1, 16): "H", (3, 32): "f", (3, 64): "d", (2, 16): "h"}[(fmt, bits)]
    planes, per_pixel = (spp, 1) if planar == 2 else (1, spp)
    chunk_w, chunk_h = (tile, tile) if tile else (width, rows or height)
    chunks = []
    for plane in range(planes):
        for y0 in range(0, height, chunk_h):
            for x0 in range(0, width, chunk_w):
                values = []
                for r in range(chunk_h if tile else min(chunk_h, height - y0)):
                    for i in range(chunk_w):
                        for k in range(per_pixel):
                            inside = y0 + r < height and x0 + i < width
                            s = plane if planar == 2 else k
                            values.append(sample(x0 + i, y0 + r, s) if inside else 0)
                raw = struct.pack(order + code * len(values), *values)
                chunks.append(compress(raw, compression, len(raw) // max(len(values), 1) *
                                       chunk_w * per_pixel))
    tags = {256: (LONG, [width]), 257: (LONG, [height]), 258: (SHORT, [bits] * spp),
            259: (SHORT, [compression]), 262: (SHORT, [photometric]), 277: (SHORT, [spp]),
            284: (SHORT, [planar]), 339: (SHORT, [fmt] * spp)}
    if tile:
        tags[322] = (LONG, [tile])
        tags[323] = (LONG, [tile])
    else:
        tags[278] = (LONG, [chunk_h])
    if extra:
        tags[338] = (SHORT, [2] * extra)  # unassociated alpha
    if colormap:
        tags[320] = (SHORT, [(i * 257 * 7) % 65536 for i in range(3 << bits)])
    return tags, chunks, bool(tile)


def tiff_file(pages, order="<", big=False):
    """A TIFF (or BigTIFF) of the pages of tiff_page, IFDs after the data."""
    offset = "Q" if big else "I"
    out = bytearray(b"II" if order == "<" else b"MM")
    out += struct.pack(order + "HHHQ", 43, 8, 0, 0) if big else struct.pack(order + "HI", 42, 0)
    next_pointer = 8 if big else 4
    for tags, chunks, tiled in pages:
        offsets = []
        for data in chunks:
            offsets.append(len(out))
            out += data + b"\0" * (len(data) % 2)
        tags = dict(tags)
        kind = LONG8 if big else LONG
        tags[324 if tiled else 273] = (kind, offsets)
        tags[325 if tiled else 279] = (kind, [len(data) for data in chunks])
        inline = 8 if big else 4
        entries = []
        for tag in sorted(tags):
            kind_of, values = tags[tag]
            data = struct.pack(order + PACK[kind_of] * len(values), *values)
            if len(data) <= inline:
                value = data.ljust(inline, b"\0")
            else:
                value = struct.pack(order + offset, len(out))
                out += data + b"\0" * (len(data) % 2)
            entries.append(struct.pack(order + "HH" + offset, tag, kind_of, len(values)) + value)
        struct.pack_into(order + offset, out, next_pointer, len(out))
        out += struct.pack(order + ("Q" if big else "H"), len(entries)) + b"".join(entries)
        next_pointer = len(out)
        out += bytes(inline)
    return bytes(out)


def levels(top):
    return lambda x, y, s: (x * 37 + y * 19 + s * 71) % 251 * top // 250


def real(x, y, s):
    return (x * 3.25 - y * 1.5 + s * 40.0) - 12.0


def write_tiffs(directory):
    gray, rgb, palette = 1, 2, 3
    files = {  # name: (pages, byte order, BigTIFF)
        "gray8.tif": ([tiff_page(16, 12, 1, 8, 1, gray, levels(255), rows=4)], "<", False),
        "gray8-big-endian.tif": ([tiff_page(9, 7, 1, 8, 1, gray, levels(255), order=">")], ">",
                                 False),
        "gray16-deflate.tif": ([tiff_page(20, 10, 1, 16, 1, gray, levels(65535), compression=8,
                                          rows=3)], "<", False),
        "gray16-big-endian-packbits.tif": ([tiff_page(18, 6, 1, 16, 1, gray, levels(65535),
                                                      order=">", compression=32773)], ">", False),
        "graya8.tif": ([tiff_page(10, 8, 2, 8, 1, gray, levels(255), extra=1)], "<", False),
        "rgb8-tiled.tif": ([tiff_page(20, 18, 3, 8, 1, rgb, levels(255), tile=16,
                                      compression=8)], "<", False),
        "rgba16-separate.tif": ([tiff_page(7, 5, 4, 16, 1, rgb, levels(65535), planar=2, extra=1,
                                           rows=2)], "<", False),
        "rgb-float32.tif": ([tiff_page(8, 6, 3, 32, 3, rgb, real)], "<", False),
        "gray-float32-tiled-separate.tif": ([tiff_page(17, 3, 1, 32, 3, gray, real, tile=16,
                                                       planar=2, compression=8)], "<", False),
        "gray8-1x1.tif": ([tiff_page(1, 1, 1, 8, 1, gray, levels(255))], "<", False),
        "bigtiff-gray8.tif": ([tiff_page(12, 5, 1, 8, 1, gray, levels(255))], "<", True),
        "two-pages.tif": ([tiff_page(6, 4, 1, 8, 1, gray, levels(255))] * 2, "<", False),
        "palette8.tif": ([tiff_page(6, 4, 1, 8, 1, palette, levels(255), colormap=True)], "<",
                         False),
        "int16.tif": ([tiff_page(6, 4, 1, 16, 2, gray, levels(255))], "<", False),
        "float64.tif": ([tiff_page(6, 4, 1, 64, 3, gray, real)], "<", False),
    }
    for name, (pages, order, big) in files.items():
        data = tiff_file(pages, order, big)
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


def write_texts(directory, files):
    for name, text in files.items():
        with open(os.path.join(directory, name), "w", newline="") as f:
            f.write(text)


def write_campaign_files(directory):
    write_texts(directory, {
        "full.json": '{"input": ["images/*.png", "a.png"], "code": ["raskar", "codes/x.txt"], '
                     '"mode": ["numerical", "analog"], "velocity": "0.5:2:0.5", '
                     '"restore_velocity": [1, "1.1:1.3:0.1"], "snr": [10, "10:1000:x10"], '
                     '"dt": 1, "trials": 3, "seed": 18446744073709551615, "noise": "aggregated", '
                     '"rmse_margin": -1}\n',
        "minimal.json": '{"input": "a.png", "code": "raskar"}',
        "numbers.json": '{"velocity": [1e-100, -0.0, 1E+2, 3], "snr": 1e100, "dt": [0.1, 2]}',
        "bad-type.json": '{"trials": 1.5, "seed": -1}',
        "unknown-key.json": '{"inputs": ["a.png"]}',
        "not-object.json": '[1, 2, 3]',
        "truncated.json": '{"velocity": "1:2',
        "deep.json": '{"trials": ' + "[" * 100 + "1" + "]" * 100 + "}",
    })


# Small campaigns whose journals seed fuzz_campaign_journal: (name, options).
CAMPAIGNS = [
    ("one", ["-c", "c.txt", "snapshot", "--velocity", "0.5,1", "--trials", "1"]),
    ("shard-per-trial", ["-c", "c.txt", "--velocity", "0.5,1,2", "--trials", "2", "--per-trial",
                         "--shard", "2/2"]),
    ("sensor", ["-c", "c.txt", "--mode", "analog", "--velocity", "1", "--trials", "1",
                "--read-noise", "0,2", "--full-well", "1000", "--adc-bits", "10",
                "--adc-gain", "2"]),
]


def run_campaigns(fssim, work):
    """Runs CAMPAIGNS in `work` (relative paths, so that the journals name no
    temporary directory); the journal and results.csv of each, by name."""
    with open(os.path.join(work, "a.png"), "wb") as f:
        f.write(png(40, 2, 8, 0, lambda x, y: ((x * 7 + y * 13) % 256,)))
    with open(os.path.join(work, "c.txt"), "w") as f:
        f.write("1 0 1 1\n")
    out = {}
    for name, options in CAMPAIGNS:
        subprocess.run([fssim, "campaign", "--no-progress", "--threads", "1", "-i", "a.png",
                        "--snr", "100", "-o", name] + options, cwd=work, check=True,
                       stdout=subprocess.DEVNULL)
        with open(os.path.join(work, name, "journal.jsonl")) as f:
            journal = f.read()
        with open(os.path.join(work, name, "results.csv")) as f:
            out[name] = (journal, f.read())
    return out


def write_campaign_runs(journal_dir, check_dir):
    fssim = os.environ.get("FSSIM", os.path.join(HERE, "..", "..", "build", "fssim"))
    if not os.access(fssim, os.X_OK):
        print("make_corpus: no fssim at %s: campaign journals and results left as they are" % fssim)
        return
    work = tempfile.mkdtemp()
    try:
        runs = run_campaigns(fssim, work)
    finally:
        shutil.rmtree(work)
    journals, checks = {}, {}
    for name, (journal, results) in runs.items():
        journals[name + ".jsonl"] = journal
        lines = journal.split("\n")
        header = lines[0] + "\n"
        journals[name + "-torn.jsonl"] = journal[:len(header) + len(lines[1]) // 2]
        journals[name + "-header.jsonl"] = header
        # The first byte chooses the tolerances (fuzz_campaign_check.cpp).
        checks[name + ".csv"] = "\x00" + results
        rows = results.split("\n")
        subset = ",".join(rows[0].split(",")[:6] + ["rmse_mean"])
        picked = [row.split(",") for row in rows[1:] if row]
        index = rows[0].split(",").index("rmse_mean")
        expected = subset + "\n" + "".join(
            ",".join(r[:6] + [r[index]]) + "\n" for r in picked)
        checks[name + "-subset.csv"] = "\x05" + results + "\n--\n" + expected
    one = runs["one"][0].split("\n")
    # A row of shard 2/2 in a journal of 1/1 is fine; one of 1/2 in 2/2 is not.
    shard = runs["shard-per-trial"][0].split("\n")
    journals["foreign-row.jsonl"] = shard[0] + "\n" + one[1] + "\n"
    journals["deep.jsonl"] = one[0] + "\n" + "[" * 100 + "]" * 100 + "\n"
    checks["no-settings.csv"] = "\x00rmse_mean\n1\n--\nrmse_mean\n2\n"
    checks["quoted.csv"] = "\x03code,rmse_mean,status\n\"a,\"\"b\"\"\n\",,ok\r\n--\n" \
                           "code,rmse_mean,status\n\"a,\"\"b\"\"\n\",1,\"o\nk\"\n"
    # Quotes that hide "nan" in the text but not in the cell.
    checks["quoted-nan.csv"] = "\x03code,rmse_mean,status\n\"a)na\"n\"\",1,ok\n"
    write_texts(journal_dir, journals)
    write_texts(check_dir, checks)



def write_ranges(directory):
    # The first byte chooses the parser: even, the campaign's value list;
    # odd, the command line's range.
    write_texts(directory, {
        "list.txt": "\x001,2.5,-3,1e-5",
        "arithmetic.txt": "\x000:1:0.1,5",
        "geometric.txt": "\x001:1000:x10",
        "geometric-upper.txt": "\x000.5:4:X2,7",
        "cli-single.txt": "\x01+1.5",
        "cli-range.txt": "\x010.5:3:0.25",
        "cli-bad.txt": "\x011:2",
        "empty-item.txt": "\x001,,2",
    })


if __name__ == "__main__":
    for kind, writer in (("png", write_pngs), ("tiff", write_tiffs), ("code", write_codes),
                         ("campaign_file", write_campaign_files), ("range", write_ranges)):
        directory = os.path.join(HERE, "corpus", kind)
        os.makedirs(directory, exist_ok=True)
        writer(directory)
    journal_dir = os.path.join(HERE, "corpus", "campaign_journal")
    check_dir = os.path.join(HERE, "corpus", "campaign_check")
    os.makedirs(journal_dir, exist_ok=True)
    os.makedirs(check_dir, exist_ok=True)
    write_campaign_runs(journal_dir, check_dir)
