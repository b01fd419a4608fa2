#!/usr/bin/python3
"""Compares two folders of fssim outputs by content rather than by bytes.

    scripts/compare_outputs.py BEFORE AFTER [--rel 1e-9] [--abs 1e-9]

BEFORE and AFTER are folders kept by `KEEP=DIR scripts/output_matrix.sh ...`
(one sub-folder a case), or two output folders of single runs. For a change
that is meant to move only the last bits of doubles (another FFT size, another
summation order), byte hashes differ while the results do not: this tells how
much. Every file present in either folder is compared:

- PNG images: the decoded samples (not the compressed bytes); reports the
  number of samples that differ and the largest difference.
- report.json: every number, within --rel relative or --abs absolute
  tolerance; strings and the structure exactly (fssim_version left out).
- other text (stdout, stderr, .txt, .csv, .html): every number within the
  tolerances, the text between numbers exactly.
- anything else: bytes.

Prints one line per file that differs beyond the tolerances, then a summary,
and exits 1 when any did. Uses Debian's python3 with python3-numpy and
python3-pil (scripts/install-deps.sh).
"""

import argparse
import json
import math
import os
import re
import sys

import numpy as np
from PIL import Image

NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|[-+]?(?:inf|nan)")


def close(a, b, rel, absolute):
    if a == b or (math.isnan(a) and math.isnan(b)):
        return True
    return abs(a - b) <= max(absolute, rel * max(abs(a), abs(b)))


def compare_numbers(a, b, rel, absolute):
    """Largest relative difference of two equally long lists, or None when one is beyond."""
    worst = 0.0
    ok = True
    for x, y in zip(a, b):
        if not close(x, y, rel, absolute):
            ok = False
        if x != y and max(abs(x), abs(y)) > 0:
            worst = max(worst, abs(x - y) / max(abs(x), abs(y)))
    return ok, worst


def compare_text(path_a, path_b, rel, absolute):
    with open(path_a, encoding="utf-8", errors="replace") as f:
        text_a = f.read()
    with open(path_b, encoding="utf-8", errors="replace") as f:
        text_b = f.read()
    if text_a == text_b:
        return None
    if NUMBER.split(text_a) != NUMBER.split(text_b):
        return "text differs (not only in numbers)"
    a = [float(x) for x in NUMBER.findall(text_a)]
    b = [float(x) for x in NUMBER.findall(text_b)]
    ok, worst = compare_numbers(a, b, rel, absolute)
    return None if ok else f"numbers differ, largest relative difference {worst:.3g}"


def flatten_json(value, prefix, numbers, rest):
    if isinstance(value, dict):
        for key in sorted(value):
            if key != "fssim_version":
                flatten_json(value[key], f"{prefix}.{key}", numbers, rest)
    elif isinstance(value, list):
        for i, item in enumerate(value):
            flatten_json(item, f"{prefix}[{i}]", numbers, rest)
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        numbers.append((prefix, float(value)))
    else:
        rest.append((prefix, value))


def compare_json(path_a, path_b, rel, absolute):
    with open(path_a) as f:
        a = json.load(f)
    with open(path_b) as f:
        b = json.load(f)
    na, ra, nb, rb = [], [], [], []
    flatten_json(a, "", na, ra)
    flatten_json(b, "", nb, rb)
    if ra != rb or [k for k, _ in na] != [k for k, _ in nb]:
        return "structure or strings differ"
    bad = [k for (k, x), (_, y) in zip(na, nb) if not close(x, y, rel, absolute)]
    if bad:
        return f"{len(bad)} numbers differ beyond the tolerance, first {bad[0]}"
    return None


def compare_png(path_a, path_b):
    a = np.asarray(Image.open(path_a)).astype(np.int64)
    b = np.asarray(Image.open(path_b)).astype(np.int64)
    if a.shape != b.shape:
        return f"shapes differ: {a.shape} and {b.shape}"
    diff = np.abs(a - b)
    count = int(np.count_nonzero(diff))
    if count == 0:
        return None
    return f"{count} of {diff.size} samples differ, by at most {int(diff.max())}"


def compare_file(path_a, path_b, rel, absolute):
    name = os.path.basename(path_a)
    with open(path_a, "rb") as f:
        bytes_a = f.read()
    with open(path_b, "rb") as f:
        bytes_b = f.read()
    if bytes_a == bytes_b:
        return None
    if bytes_a.startswith(b"\x89PNG"):
        return compare_png(path_a, path_b)
    if name.endswith(".json"):
        return compare_json(path_a, path_b, rel, absolute)
    if name.endswith((".stdout", ".stderr", ".txt", ".csv", ".html", ".jsonl", ".md")):
        return compare_text(path_a, path_b, rel, absolute)
    return "bytes differ"


def files_under(root):
    found = set()
    for folder, _, names in os.walk(root):
        for name in names:
            found.add(os.path.relpath(os.path.join(folder, name), root))
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--rel", type=float, default=1e-9, help="relative tolerance of numbers")
    parser.add_argument("--abs", type=float, default=1e-9, help="absolute tolerance of numbers")
    args = parser.parse_args()
    a_files = files_under(args.before)
    b_files = files_under(args.after)
    problems = 0
    for rel_path in sorted(a_files | b_files):
        if rel_path not in a_files or rel_path not in b_files:
            print(f"{rel_path}: only in {'after' if rel_path in b_files else 'before'}")
            problems += 1
            continue
        message = compare_file(os.path.join(args.before, rel_path),
                               os.path.join(args.after, rel_path), args.rel, args.abs)
        if message:
            print(f"{rel_path}: {message}")
            problems += 1
    total = len(a_files | b_files)
    print(f"compare_outputs: {total} files, {problems} differ beyond the tolerances")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
