// The docstrings of the image file functions (image_bindings.cpp), numpydoc, each beginning with
// its text signature ("name(sig)\n--\n\n", which inspect.signature reads).
#pragma once

namespace fss::python {

inline constexpr const char* kReadPngDoc =
    R"(read_png(path, *, max_memory=0)
--

A PNG file's samples, as fssim reads the file.

Any colour type and bit depth, interlaced or not, as fssim --input reads it: gray stays one
channel, a palette becomes RGB, alpha is dropped (gray + alpha is gray, RGBA is RGB), gray of 1,
2 or 4 bits is scaled to 8 bits.

Parameters
----------
path : str, bytes or os.PathLike
max_memory : int, default 0
    Bytes the call may use (the file, its decoding and the array); 0: no limit. A file that
    needs more is refused from its size and header, before it is decoded.

Returns
-------
numpy.ndarray
    uint8 (files of 1 to 8 bits) or uint16 (16 bits), H x W (gray) or H x W x 3 (colour), so
    that ``simulate(read_png(p))`` is ``fssim --input p``.

Raises
------
RuntimeError
    A file that is missing, a directory, not a PNG, truncated or corrupt, or over
    `max_memory`; one line naming the file.
ValueError
    max_memory out of range.
TypeError
    A path or max_memory of the wrong type.

See Also
--------
read_image : a PNG or a TIFF, by its signature.

Examples
--------
>>> image = fss.read_png('data/camera.png')  # doctest: +SKIP
>>> image.dtype, image.shape  # doctest: +SKIP
(dtype('uint8'), (512, 512))
)";

inline constexpr const char* kReadTiffDoc =
    R"(read_tiff(path, *, max_memory=0)
--

A TIFF file's samples, as fssim reads the file.

One page of 8- or 16-bit unsigned or 32-bit float samples, gray (min-is-black) or RGB (further
samples such as alpha dropped), in strips or tiles, contiguous or planar, uncompressed,
PackBits, LZW or Deflate; other TIFFs and non-finite floats are refused as fssim refuses them.

Parameters
----------
path : str, bytes or os.PathLike
max_memory : int, default 0
    Bytes the call may use; 0: no limit. Checked from the file's size and header, before it is
    decoded.

Returns
-------
numpy.ndarray
    uint8, uint16 or float32 as stored, H x W or H x W x 3. A float TIFF holds gray levels as
    fssim's ``--save-float`` writes them: simulate it with ``data_range=255``.

Raises
------
RuntimeError
    A file that is missing, a directory, not a TIFF, of a kind fssim does not read, truncated
    or corrupt, or over `max_memory`; one line naming the file.
ValueError
    max_memory out of range.
TypeError
    A path or max_memory of the wrong type.

Examples
--------
>>> fss.write_tiff('restored.tif', result.restored, data_range=255)  # doctest: +SKIP
>>> fss.read_tiff('restored.tif').dtype  # doctest: +SKIP
dtype('float32')
)";

inline constexpr const char* kReadImageDoc =
    R"(read_image(path, *, max_memory=0)
--

A PNG or TIFF file's samples, told apart by the file's signature whatever its name.

As ``fssim --input`` reads its input: read_png for a PNG, read_tiff for a TIFF.

Parameters
----------
path : str, bytes or os.PathLike
max_memory : int, default 0
    Bytes the call may use; 0: no limit.

Returns
-------
numpy.ndarray
    uint8, uint16 or float32 as stored, H x W or H x W x 3.

Raises
------
RuntimeError
    A file that is missing, a directory, neither a PNG nor a TIFF, unreadable, or over
    `max_memory`; one line naming the file.
ValueError
    max_memory out of range.
TypeError
    A path or max_memory of the wrong type.

Examples
--------
>>> result = fss.simulate(fss.read_image('data/camera.png'), velocity=0.5)  # doctest: +SKIP
)";

inline constexpr const char* kWritePngDoc =
    R"(write_png(path, image, *, data_range=None, bit_depth=8)
--

Writes an image as an 8- or 16-bit PNG, as fssim writes its images.

Each gray level g = value * 255 / data_range is stored rounded (halves away from zero) and
clamped: at 8 bits to [0, 255], at 16 bits g * 257 to [0, 65535]. So a uint8 array written at 8
bits, or a uint16 array at 16 bits, is stored as it is, and read_png gives it back. The file is
written whole or not at all (a hidden temporary renamed over `path`, which is replaced).

Parameters
----------
path : str, bytes or os.PathLike
image : array_like
    H x W (gray) or H x W x 3 (RGB), any real dtype and memory layout; never modified.
data_range : float, optional
    The value of gray level 255 (255 for gray levels, 1 for floats on [0, 1]). None: 255 for
    uint8, 65535 for uint16; other dtypes need it.
bit_depth : {8, 16}, default 8

Returns
-------
None

Raises
------
ValueError
    An image of another shape or dtype, a value that is not finite, a float image without
    data_range, a bit_depth other than 8 or 16; one line naming the keyword.
RuntimeError
    A file that cannot be written (the old file, if any, is left as it was).
TypeError
    A keyword of the wrong type.

Examples
--------
>>> result = fss.simulate(fss.read_png('data/camera.png'))  # doctest: +SKIP
>>> fss.write_png('restored.png', result.restored, data_range=255)  # doctest: +SKIP
)";

inline constexpr const char* kWriteTiffDoc =
    R"(write_tiff(path, image, *, data_range=None)
--

Writes an image as a 32-bit float TIFF of gray levels, as ``fssim --save-float`` writes.

Each gray level value * 255 / data_range is stored as the nearest float, neither rounded nor
clamped (little-endian, uncompressed, gray or RGB). The file is written whole or not at all.

Parameters
----------
path : str, bytes or os.PathLike
image : array_like
    H x W or H x W x 3, any real dtype and memory layout; never modified.
data_range : float, optional
    The value of gray level 255; None: 255 for uint8, 65535 for uint16; other dtypes need it.

Returns
-------
None

Raises
------
ValueError
    An image of another shape or dtype, a value that is not finite, a float image without
    data_range; one line naming the keyword.
RuntimeError
    A file that cannot be written (the old file, if any, is left as it was).
TypeError
    A keyword of the wrong type.

Examples
--------
>>> fss.write_tiff('restored.tif', result.restored, data_range=255)  # doctest: +SKIP
>>> fss.read_tiff('restored.tif')  # float32 gray levels  # doctest: +SKIP
)";

}  // namespace fss::python
