#!/usr/bin/python3
"""Runs per second of a Python loop over fss.simulate, and of the same loop over numpy.

In one process: the image is read once (fss.read_image for fss, the numpy
program's own reader for numpy), then RUNS calls of fss.simulate with the
given code and mode and the default options, seeds 1..RUNS, and RUNS calls of
bench/numpy_flutter.py's simulate() (the same model written with numpy, in
memory, no files) with the same seeds. Prints, for each, the runs per second
(RUNS over the loop's wall time, the first call included) and the median
wall time of a call. The fss module is found on PYTHONPATH (the build's
python/ directory, e.g. build-bench/python).

    python_loop.py [--input data/camera.png] [--code raskar] [--mode numerical]
                   [--runs 50] [--numpy-runs RUNS] [--results FILE] [--name NAME]

--numpy-runs 0 leaves numpy out. --results appends one tab-separated line per
program to FILE, the `loop` lines of bench/run.sh's results:
    loop  NAME  PROGRAM  RUNS  RUNS_PER_S  MEDIAN_S  ARGUMENTS
"""

import argparse
import os
import statistics
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))


def timed_loop(call, runs):
    """(runs per second, median seconds a call) of call(seed) for seeds 1..runs."""
    times = []
    start = time.perf_counter()
    for seed in range(1, runs + 1):
        begin = time.perf_counter()
        call(seed)
        times.append(time.perf_counter() - begin)
    total = time.perf_counter() - start
    return runs / total, statistics.median(times)


def fss_loop(args):
    try:
        import fss
    except ImportError as error:
        raise SystemExit(f"python_loop: cannot import fss ({error}): set PYTHONPATH to the "
                         "build's python/ directory (e.g. build-bench/python)")
    image = fss.read_image(args.input)
    return timed_loop(lambda seed: fss.simulate(image, code=args.code, mode=args.mode,
                                                seed=seed), args.runs)


def numpy_loop(args):
    sys.path.insert(0, BENCH)
    import numpy_flutter
    image = numpy_flutter.read_image(args.input)
    gains = numpy_flutter.read_code(args.code)
    return timed_loop(lambda seed: numpy_flutter.simulate(image, gains, mode=args.mode,
                                                          seed=seed), args.numpy_runs)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--input",
                        default=os.path.normpath(os.path.join(BENCH, "..", "data", "camera.png")))
    parser.add_argument("--code", default="raskar")
    parser.add_argument("--mode", choices=["numerical", "analog"], default="numerical")
    parser.add_argument("--runs", type=int, default=50)
    parser.add_argument("--numpy-runs", type=int, default=None)
    parser.add_argument("--results", help="file to append the loop lines to")
    parser.add_argument("--name", help="the case's name in the results (default from the input)")
    args = parser.parse_args(argv[1:])
    if args.numpy_runs is None:
        args.numpy_runs = args.runs
    if args.runs < 1 or args.numpy_runs < 0:
        parser.error("--runs must be at least 1 and --numpy-runs at least 0")
    if not os.path.isfile(args.input):
        parser.error(f"--input {args.input}: no such file")
    name = args.name or f"{os.path.basename(args.input)}, {args.mode}"
    arguments = f"--input {args.input} --code {args.code} --mode {args.mode}"

    measures = [("fss", args.runs, fss_loop(args))]
    if args.numpy_runs > 0:
        measures.append(("numpy", args.numpy_runs, numpy_loop(args)))
    print(f"Python loop, {name}: {args.code}, default options, distinct seeds, one process")
    for program, runs, (per_second, median) in measures:
        label = "fss.simulate" if program == "fss" else "numpy_flutter.simulate"
        print(f"  {label:<24} {runs:4d} runs  {per_second:7.2f} runs/s  "
              f"median {1e3 * median:8.1f} ms a call")
    if len(measures) == 2:
        print(f"  fss / numpy, runs per second: {measures[0][2][0] / measures[1][2][0]:.1f}x")
    if args.results:
        with open(args.results, "a", encoding="utf-8") as results:
            for program, runs, (per_second, median) in measures:
                print("\t".join(["loop", name, program, str(runs), f"{per_second:.3f}",
                                 f"{median:.4f}", arguments]), file=results)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
