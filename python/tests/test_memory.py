"""Memory: an allocation that fails is a MemoryError with a one-line message
(never "Internal error"), and max_memory refuses a run from the array's shape
before the array is converted. Each case runs in a child interpreter, under
its own address-space limit or with its own peak RSS."""

import os
import subprocess
import sys
import textwrap

import pytest

PRELUDE = textwrap.dedent("""
    import resource
    import numpy as np
    import fss

    def limit_address_space(extra_bytes):
        # the address space mapped now plus extra_bytes
        with open("/proc/self/status") as status:
            kib = next(int(line.split()[1]) for line in status if line.startswith("VmSize:"))
        hard = resource.getrlimit(resource.RLIMIT_AS)[1]
        resource.setrlimit(resource.RLIMIT_AS, (kib * 1024 + extra_bytes, hard))

    def outcome(call):
        try:
            call()
            return "no error"
        except Exception as error:
            return type(error).__name__ + ": " + str(error)
""")


def run_child(body):
    """Runs PRELUDE + body in a fresh interpreter; returns its stdout lines."""
    environment = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    result = subprocess.run([sys.executable, "-c", PRELUDE + textwrap.dedent(body)],
                            capture_output=True, text=True, env=environment, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout.splitlines()


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="needs /proc")
@pytest.mark.parametrize("call", [
    "fss.simulate(image, code=[1, 0, 1, 1], threads=1)",
    "fss.transfer_function('raskar', image.ravel())",
], ids=["simulate", "transfer_function"])
def test_allocation_failure_is_a_memory_error(call):
    lines = run_child(f"""
        image = np.full((2000, 2000), 100, dtype=np.uint8)
        limit_address_space(16 << 20)  # the image as doubles alone takes 32 MB
        print(outcome(lambda: {call}))
    """)
    assert len(lines) == 1, lines
    assert lines[0].startswith("MemoryError: "), lines[0]
    assert "Internal error" not in lines[0] and "memory" in lines[0]
    assert len(lines[0]) < 300


def test_max_memory_refuses_before_converting_the_array():
    # 12000 x 12000 8-bit samples, 144 MB: converted to doubles they would
    # take 1.15 GB, twice (a float64 copy, then the image).
    lines = run_child("""
        image = np.full((12000, 12000), 100, dtype=np.uint8)  # every page touched
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        print(outcome(lambda: fss.simulate(image, max_memory=100 << 20)))
        print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)
    """)
    assert lines[0].startswith("RuntimeError: a run on this 12000 x 12000 x 1 image needs about "), \
        lines[0]
    assert lines[0].endswith("more than the memory limit of 100.0 MiB"), lines[0]
    growth_kib = int(lines[1])
    assert growth_kib < 16 * 1024, f"peak RSS grew by {growth_kib} KiB during the refusal"


def test_max_memory_refuses_broadcast_and_rgb_arrays_at_once():
    lines = run_child("""
        # one byte of memory seen as 60000 x 60000 x 3 samples
        huge = np.broadcast_to(np.uint8(7), (60000, 60000, 3))
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        print(outcome(lambda: fss.simulate(huge, max_memory=1 << 30)))
        half = np.broadcast_to(np.float16(7), (2, 600, 3))  # converted by numpy, not here
        print(outcome(lambda: fss.simulate(half, data_range=255, max_memory=1 << 20)))
        print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)
    """)
    assert lines[0].startswith("RuntimeError: a run on this 60000 x 60000 x 3 image needs about ")
    assert lines[1].startswith("RuntimeError: a run on this 600 x 2 x 3 image needs about ")
    assert int(lines[2]) < 16 * 1024


def test_read_png_max_memory_refuses_a_larger_file_before_reading(tmp_path):
    # a valid PNG followed by 64 MiB of padding: refused from its size
    import fss
    import numpy as np
    png = tmp_path / "padded.png"
    source = os.path.join(os.path.dirname(__file__), "..", "..", "data", "camera.png")
    with open(source, "rb") as f:
        data = f.read()
    with open(png, "wb") as f:
        f.write(data)
        f.truncate(len(data) + (64 << 20))
    with pytest.raises(RuntimeError, match=r"is 6[45]\.\d+ MiB, more than the memory limit of 32\.0 MiB"):
        fss.read_png(str(png), max_memory=32 << 20)
    image = fss.read_png(source, max_memory=64 << 20)
    assert isinstance(image, np.ndarray) and image.shape == (512, 512)
