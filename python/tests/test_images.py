"""fss.read_png, read_tiff, read_image, write_png and write_tiff: the samples as the file stores
them, read as fssim reads the file (simulate(read_png(p)) is fssim --input p); writing as fssim
writes its images, atomically; hostile files refused in one line naming the file."""

import os
import struct
import zlib

import numpy as np
import pytest

import fss
from conftest import png8_samples, read_png8, read_report, run_fssim

RNG = np.random.default_rng(28)


def png16_samples(values):
    """What fssim writes to a 16-bit PNG: value x 257 rounded (halves away from zero), clamped to
    [0, 65535]."""
    scaled = np.asarray(values, dtype=np.float64) * 257.0
    whole = np.trunc(scaled)
    rounded = whole + (scaled - whole >= 0.5)
    return np.where(~(scaled >= 0.5), 0, np.where(scaled >= 65535, 65535, rounded)).astype(
        np.uint16)


def png_file(path, width, height, depth, colour, rows, palette=None):
    """A PNG of our own: IHDR, PLTE, one IDAT of the raw rows (filter 0), IEND."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(
            ">I", zlib.crc32(kind + body))
    data = b"".join(b"\0" + row for row in rows)
    body = chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0))
    if palette is not None:
        body += chunk(b"PLTE", bytes(palette.astype(np.uint8).ravel()))
    body += chunk(b"IDAT", zlib.compress(data)) + chunk(b"IEND", b"")
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + body)
    return path


def tiff_file(path, array):
    """An uncompressed little-endian TIFF of a uint8 or uint16 array, gray or RGB, one strip."""
    height, width = array.shape[:2]
    channels = 1 if array.ndim == 2 else array.shape[2]
    bits = array.dtype.itemsize * 8
    pixels = np.ascontiguousarray(array.astype(array.dtype.newbyteorder("<"))).tobytes()
    strip_bytes = len(pixels)
    pixels += b"\0" * (len(pixels) % 2)  # offsets on word boundaries
    bits_offset = 8 + len(pixels)
    entries = [(256, 4, 1, width), (257, 4, 1, height),
               (258, 3, channels, bits if channels == 1 else bits_offset),
               (259, 3, 1, 1), (262, 3, 1, 1 if channels == 1 else 2), (273, 4, 1, 8),
               (277, 3, 1, channels), (278, 4, 1, height), (279, 4, 1, strip_bytes),
               (284, 3, 1, 1), (339, 3, channels, 1 if channels == 1 else bits_offset + 8)]
    extra = b""
    if channels == 3:
        extra = struct.pack("<3H", bits, bits, bits) + b"\0\0" + struct.pack("<3H", 1, 1, 1)
        extra += b"\0\0"
    ifd_offset = bits_offset + len(extra)
    ifd = struct.pack("<H", len(entries))
    for tag, kind, count, value in entries:
        packed = struct.pack("<H", value) + b"\0\0" if kind == 3 and count == 1 else struct.pack(
            "<I", value)
        ifd += struct.pack("<HHI", tag, kind, count) + packed
    ifd += struct.pack("<I", 0)
    path.write_bytes(b"II*\0" + struct.pack("<I", ifd_offset) + pixels + extra + ifd)
    return path


# ---------------------------------------------------------------------------
# Round trips


@pytest.mark.parametrize("shape", [(7, 300), (5, 40, 3)])
def test_png_round_trip_uint8_and_uint16(tmp_path, shape):
    for dtype, depth in ((np.uint8, 8), (np.uint16, 16)):
        image = RNG.integers(0, np.iinfo(dtype).max + 1, size=shape, dtype=dtype)
        for layout in (image, np.asfortranarray(image), image[::-1, ::-1]):
            kept = layout.copy()
            fss.write_png(tmp_path / "x.png", layout, bit_depth=depth)
            read = fss.read_png(tmp_path / "x.png")
            assert read.dtype == dtype and read.shape == shape
            np.testing.assert_array_equal(read, layout)
            np.testing.assert_array_equal(layout, kept)  # never modified
            np.testing.assert_array_equal(fss.read_image(tmp_path / "x.png"), layout)


def test_png_uint16_every_value_round_trips(tmp_path):
    image = np.arange(65536, dtype=np.uint16).reshape(256, 256)
    fss.write_png(tmp_path / "x.png", image, bit_depth=16)
    np.testing.assert_array_equal(fss.read_png(tmp_path / "x.png"), image)


def test_write_png_stores_what_fssim_writes(tmp_path):
    halves = np.arange(-2, 258, 0.5)
    values = np.concatenate([halves, RNG.uniform(-50, 300, 740), [1e300, -1e300, 254.49999]])
    image = values[:1000].reshape(4, 250)
    fss.write_png(tmp_path / "x.png", image, data_range=255)
    np.testing.assert_array_equal(read_png8(tmp_path / "x.png"), png8_samples(image))
    fss.write_png(tmp_path / "y.png", image, data_range=255, bit_depth=16)
    np.testing.assert_array_equal(fss.read_png(tmp_path / "y.png"), png16_samples(image))
    # data_range: gray level = value x 255 / data_range
    unit = RNG.uniform(0, 1, (6, 20))
    fss.write_png(tmp_path / "u.png", unit, data_range=1)
    np.testing.assert_array_equal(read_png8(tmp_path / "u.png"), png8_samples(unit * 255))
    # across depths: uint8 at 16 bits is 257 g; uint16 at 8 bits is g / 257 rounded
    gray = RNG.integers(0, 256, (3, 30), dtype=np.uint8)
    fss.write_png(tmp_path / "g.png", gray, bit_depth=16)
    np.testing.assert_array_equal(fss.read_png(tmp_path / "g.png"), gray.astype(np.uint16) * 257)
    wide = RNG.integers(0, 65536, (3, 30), dtype=np.uint16)
    fss.write_png(tmp_path / "w.png", wide)
    np.testing.assert_array_equal(read_png8(tmp_path / "w.png"), png8_samples(wide / 257.0))


def test_tiff_round_trip(tmp_path):
    for shape in ((6, 50), (4, 30, 3)):
        image = RNG.uniform(-20, 300, shape)
        fss.write_tiff(tmp_path / "x.tif", image, data_range=255)
        read = fss.read_tiff(tmp_path / "x.tif")
        assert read.dtype == np.float32 and read.shape == shape
        np.testing.assert_array_equal(read, image.astype(np.float32))
        np.testing.assert_array_equal(fss.read_image(tmp_path / "x.tif"), read)
        fss.write_tiff(tmp_path / "y.tif", image / 255.0, data_range=1)
        np.testing.assert_allclose(fss.read_tiff(tmp_path / "y.tif"), read, rtol=1e-6)
    for dtype in (np.uint8, np.uint16):
        for shape in ((5, 9), (5, 9, 3)):
            image = RNG.integers(0, np.iinfo(dtype).max + 1, size=shape, dtype=dtype)
            read = fss.read_tiff(tiff_file(tmp_path / "i.tif", image))
            assert read.dtype == dtype
            np.testing.assert_array_equal(read, image)
            np.testing.assert_array_equal(fss.read_image(tmp_path / "i.tif"), image)


def test_png_kinds_as_fssim_reads_them(tmp_path):
    """Palette -> RGB, gray + alpha -> gray, RGBA -> RGB, 1-bit gray -> 0 or 255."""
    palette = RNG.integers(0, 256, (16, 3))
    index = RNG.integers(0, 16, (4, 6), dtype=np.uint8)
    read = fss.read_png(png_file(tmp_path / "p.png", 6, 4, 8, 3, [bytes(r) for r in index],
                                 palette))
    assert read.dtype == np.uint8
    np.testing.assert_array_equal(read, palette[index])
    gray_alpha = RNG.integers(0, 65536, (4, 6, 2), dtype=np.uint16)
    rows = [r.astype(">u2").tobytes() for r in gray_alpha]
    read = fss.read_png(png_file(tmp_path / "ga.png", 6, 4, 16, 4, rows))
    assert read.dtype == np.uint16
    np.testing.assert_array_equal(read, gray_alpha[:, :, 0])
    rgba = RNG.integers(0, 256, (4, 6, 4), dtype=np.uint8)
    read = fss.read_png(png_file(tmp_path / "rgba.png", 6, 4, 8, 6, [bytes(r) for r in rgba]))
    np.testing.assert_array_equal(read, rgba[:, :, :3])
    bits = RNG.integers(0, 2, (3, 16), dtype=np.uint8)
    read = fss.read_png(png_file(tmp_path / "b.png", 16, 3, 1, 0,
                                 [bytes(np.packbits(r)) for r in bits]))
    np.testing.assert_array_equal(read, bits * 255)


# ---------------------------------------------------------------------------
# Against fssim


@pytest.mark.parametrize("kind", ["png16", "rgb8", "tiff16", "float_tiff"])
def test_simulate_of_read_equals_fssim_input(fssim, tmp_path, camera_array, astronaut, kind):
    if kind == "png16":
        image = camera_array[200:232, 100:400].astype(np.uint16) * 251 + 17
        path = tmp_path / "in.png"
        fss.write_png(path, image, bit_depth=16)
    elif kind == "rgb8":
        path = tmp_path / "in.png"
        fss.write_png(path, fss.read_png(astronaut)[100:124, 50:350])
    elif kind == "tiff16":
        image = camera_array[300:324, :300].astype(np.uint16) * 250 + 99
        path = tiff_file(tmp_path / "in.tif", image)
    else:
        path = tmp_path / "in.tif"
        fss.write_tiff(path, camera_array[10:40, 50:350] / 1.7, data_range=255)
    run_fssim(fssim, "--input", path, "--outdir", tmp_path / "out", "--no-plots", "--seed", "2",
              "--velocity", "0.8", "--rmse-margin", "40")
    image = fss.read_image(path)
    data_range = 255 if image.dtype == np.float32 else None
    result = fss.simulate(image, data_range=data_range, seed=2, velocity=0.8, rmse_margin=40)
    cli = read_report(tmp_path / "out")
    assert result.metrics == cli["metrics"]
    assert result.prediction == cli["prediction"]


def test_writers_write_what_fssim_writes(fssim, tmp_path, camera_array):
    image = camera_array[:40, :300]
    fss.write_png(tmp_path / "in.png", image)
    run_fssim(fssim, "--input", tmp_path / "in.png", "--outdir", tmp_path / "out", "--no-plots",
              "--save-float", "--png-depth", "16", "--rmse-margin", "40")
    result = fss.simulate(image, rmse_margin=40)
    fss.write_tiff(tmp_path / "restored.tif", result.restored, data_range=255)
    written = (tmp_path / "restored.tif").read_bytes()
    assert written == (tmp_path / "out" / "restored.tif").read_bytes()
    fss.write_png(tmp_path / "restored.png", result.restored, data_range=255, bit_depth=16)
    np.testing.assert_array_equal(fss.read_png(tmp_path / "restored.png"),
                                  fss.read_png(tmp_path / "out" / "restored.png"))


# ---------------------------------------------------------------------------
# Atomic writes, hostile files, the memory limit


def test_write_is_atomic(tmp_path):
    path = tmp_path / "x.png"
    old = np.full((3, 4), 7, dtype=np.uint8)
    fss.write_png(path, old)
    before = path.read_bytes()
    with pytest.raises(ValueError, match="bit_depth = 12: must be 8 or 16"):
        fss.write_png(path, old, bit_depth=12)
    with pytest.raises(ValueError, match="image: dtype float64 needs data_range="):
        fss.write_png(path, np.zeros((3, 4)))
    assert path.read_bytes() == before
    fss.write_png(path, old + 1)  # replaced
    np.testing.assert_array_equal(fss.read_png(path), old + 1)
    with pytest.raises(RuntimeError, match="cannot write"):
        fss.write_png(tmp_path, old)  # a directory
    with pytest.raises(RuntimeError, match="x.png"):
        fss.write_tiff(path / "y.tif", old)  # under a file
    assert sorted(os.listdir(tmp_path)) == ["x.png"]  # no temporary left


def hostile_files(tmp_path, camera):
    data = camera.read_bytes()
    (tmp_path / "truncated.png").write_bytes(data[:len(data) // 3])
    (tmp_path / "text.png").write_text("not an image\n")
    (tmp_path / "empty.tif").write_bytes(b"")
    (tmp_path / "truncated.tif").write_bytes(b"II*\0" + struct.pack("<I", 8) + b"\0" * 6)
    png_file(tmp_path / "huge.png", 60000, 60000, 16, 2, [b""])  # 3.6e9 pixels in 80 bytes
    (tmp_path / "adir.png").mkdir()
    return ["truncated.png", "text.png", "empty.tif", "truncated.tif", "huge.png", "adir.png",
            "missing.png"]


def test_hostile_files_give_one_line_naming_the_file(tmp_path, camera):
    for name in hostile_files(tmp_path, camera):
        for read in (fss.read_png, fss.read_tiff, fss.read_image):
            with pytest.raises(RuntimeError) as error:
                read(tmp_path / name)
            message = str(error.value)
            assert name in message and "\n" not in message and len(message) < 300, message


def test_max_memory_refuses_before_decoding(tmp_path, camera):
    # 3000 x 3000 zeros: a 9 MB decoding in a file of some kilobytes
    rows = [bytes(3000)] * 3000
    path = png_file(tmp_path / "big.png", 3000, 3000, 8, 0, rows)
    assert path.stat().st_size < 100_000
    with pytest.raises(RuntimeError, match=r"big\.png.*memory limit"):
        fss.read_png(path, max_memory=1_000_000)
    image = fss.read_png(camera)
    for limit in (image.size * 9 - 1, 300_000):
        with pytest.raises(RuntimeError, match="memory limit"):
            fss.read_image(camera, max_memory=limit)
    np.testing.assert_array_equal(fss.read_png(camera, max_memory=image.size * 20), image)
    with pytest.raises(ValueError, match="max_memory = -1"):
        fss.read_png(camera, max_memory=-1)
