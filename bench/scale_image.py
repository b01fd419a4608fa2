#!/usr/bin/python3
"""Writes an image resized to WIDTH x HEIGHT as an 8-bit RGB PNG.

bench/run.sh makes its large photograph with it: data/astronaut.png (512 x 512)
resized to 4000 x 3000, stretched (the aspect ratio is not kept) with Pillow's
LANCZOS filter. Run with Debian's python3 (python3-pil).

    scale_image.py IN.png WIDTH HEIGHT OUT.png
"""

import sys

from PIL import Image


def main(argv):
    if len(argv) != 5:
        print("usage: scale_image.py IN.png WIDTH HEIGHT OUT.png", file=sys.stderr)
        return 2
    source, width, height, target = argv[1], int(argv[2]), int(argv[3]), argv[4]
    if width < 1 or height < 1:
        print("scale_image: WIDTH and HEIGHT must be positive", file=sys.stderr)
        return 2
    with Image.open(source) as image:
        image.convert("RGB").resize((width, height), Image.LANCZOS).save(target)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
