"""The GIL is released while the library computes, and concurrent calls give
the results of sequential ones."""

import sys
import threading

import numpy as np

import fss
from conftest import read_png8


def test_gil_is_released_during_simulate(camera):
    gray = read_png8(camera)
    started = threading.Event()
    done = []

    def worker():
        started.set()
        fss.simulate(gray, trials=8, threads=1)
        done.append(True)

    # With a switch interval of an hour the interpreter never takes the GIL
    # from a thread: this thread runs again before the worker ends only if
    # fss.simulate gives the GIL up itself.
    interval = sys.getswitchinterval()
    sys.setswitchinterval(3600)
    try:
        thread = threading.Thread(target=worker)
        thread.start()
        started.wait()
        running_while_computing = not done
    finally:
        sys.setswitchinterval(interval)
    thread.join()
    assert done
    assert running_while_computing, "fss.simulate held the GIL"


def test_concurrent_calls_equal_sequential_ones(camera):
    gray = read_png8(camera)
    seeds = [0, 1, 2, 3]
    expected = [fss.simulate(gray, seed=seed, threads=1) for seed in seeds]
    results = [None] * len(seeds)

    def worker(i):
        results[i] = fss.simulate(gray, seed=seeds[i], threads=1)

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(len(seeds))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for result, reference in zip(results, expected):
        np.testing.assert_array_equal(result.restored, reference.restored)
        assert result.report == reference.report
