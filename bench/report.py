#!/usr/bin/python3
"""Renders docs/performance.md from the results file of bench/run.sh.

    bench/report.py [RESULTS] [-o OUTPUT]

RESULTS defaults to build-bench/results.tsv (bench/run.sh's BENCH_RESULTS),
OUTPUT to docs/performance.md ("-" for standard output). Python 3 standard
library only.
"""

import argparse
import math
import os
import sys
import textwrap

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Descriptions of the micro-benchmarks (bench/micro_bench.cpp), by the name
# before any "/argument"; a benchmark not listed here shows its name alone.
MICRO = {
    "BM_ScalarPoissonSNR": "photon noise, scalar `PoissonSNR` per pixel, row of {n}",
    "BM_PoissonRowSampler": "photon noise, `PoissonRowSampler` (batched, vectorized), row of {n}",
    "BM_PoissonRowSamplerShifted":
        "the same, shifted exposures (intensities computed once a row, windowed), row of {n}",
    "BM_AggregatedRowSampler":
        "aggregated noise, `AggregatedRowSampler`, 52 frames of a row of {n}",
    "BM_Xoshiro": "xoshiro256**",
    "BM_InlineXoshiro": "xoshiro256**, inline generator",
    "BM_BoxMullerRow": "normals as the per-frame sampler draws them (uniforms + libmvec "
                       "Box-Muller), row of {n}",
    "BM_ZigguratRow": "ziggurat normal (bench/ziggurat.h), library stream, row of {n}",
    "BM_ZigguratRowInline": "ziggurat normal (bench/ziggurat.h), inline generator, row of {n}",
    "BM_StdNormalDistribution": "`std::normal_distribution`",
    "BM_StdPoissonRow": "`std::poisson_distribution`, row of {n} at snr 100",
    "gsl_gaussian_ziggurat": "GSL ziggurat normal",
    "BM_GslPoissonRow": "GSL Poisson, row of {n} at snr 100",
    "BM_ScalarBoxMuller": "Box-Muller, scalar",
    "BM_BoxMullerBatch": "Box-Muller, batch of given uniforms (glibc libmvec `log`, `sin`, `cos`)",
    "BM_RowFFTBatch": "512 row FFT pairs (r2c + c2r), n = {n}",
    "BM_RowRestorer": "a row restored (`RowRestorer`), W = {n}",
    "BM_RmseContrastInvariant": "RMSE_CI",
}

METHOD_6C = "method.md#6c-aggregated-photon-noise---noise-aggregated-numerical-mode-only"


def read_results(path):
    """meta, cases, generators, micro and extra: extra["campaign"] the campaign lines,
    extra["loop"] the Python-loop lines, in their order."""
    meta, cases, generators, micro = {}, {}, [], []
    extra = {"campaign": [], "loop": []}
    order = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            fields = line.rstrip("\n").split("\t")
            kind = fields[0]
            if kind == "meta" and len(fields) >= 2:
                meta[fields[1]] = fields[2] if len(fields) > 2 else ""
            elif kind == "case" and len(fields) == 7:
                name, program, runs, seconds, megabytes, arguments = fields[1:]
                if name not in cases:
                    cases[name] = {}
                    order.append(name)
                cases[name][program] = {
                    "runs": int(runs), "seconds": float(seconds),
                    "megabytes": int(megabytes), "arguments": arguments}
            elif kind == "campaign" and len(fields) == 7:
                name, runs, seconds, megabytes, settings, arguments = fields[1:]
                extra["campaign"].append({
                    "name": name, "runs": int(runs), "seconds": float(seconds),
                    "megabytes": int(megabytes), "settings": int(settings),
                    "arguments": arguments})
            elif kind == "loop" and len(fields) == 7:
                name, program, runs, per_second, median, arguments = fields[1:]
                extra["loop"].append({
                    "name": name, "program": program, "runs": int(runs),
                    "per_second": float(per_second), "median": float(median),
                    "arguments": arguments})
            elif kind == "numpy_generator" and len(fields) == 3:
                generators.append((fields[1], float(fields[2])))
            elif kind == "micro" and len(fields) == 5:
                items = float(fields[4]) if fields[4] else None
                micro.append((fields[1], float(fields[2]), fields[3], items))
            else:
                raise SystemExit(f"report: {path}:{number}: not a line of bench/run.sh's results")
    return meta, [(name, cases[name]) for name in order], generators, micro, extra


def cell(measure):
    if measure is None:
        return ""
    return f"{measure['seconds']:.3f} s, {measure['megabytes']} MB"


def ratio(numpy, fssim):
    if numpy is None or fssim is None or fssim["seconds"] <= 0:
        return ""
    return f"{numpy['seconds'] / fssim['seconds']:.1f}×"


def rate(items_per_second):
    if items_per_second is None:
        return ""
    for scale, unit in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if items_per_second >= scale:
            return f"{items_per_second / scale:.3g} {unit}/s"
    return f"{items_per_second:.3g} /s"


def duration(value, unit):
    """A time of Google Benchmark's JSON, in the unit that reads best, 3 significant digits."""
    seconds = value * {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}.get(unit, float("nan"))
    if math.isnan(seconds):
        return f"{value:.3g} {unit}"
    for scale, name in ((1.0, "s"), (1e-3, "ms"), (1e-6, "µs")):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {name}"
    return f"{seconds / 1e-9:.3g} ns"


# BM_RmseContrastInvariant's arguments (bench/micro_bench.cpp): its case 0 is
# camera.png's window, its case 1 the generated 4000 x 3000 image's.
RMSE_CI_CASES = {"0": "camera.png's window", "1": "the generated 4000×3000 image's window"}


def micro_description(name):
    base, _, argument = name.partition("/")
    text = MICRO.get(base)
    if text is None:
        return f"`{name}`"
    if "{n}" in text:
        text = text.replace("{n}", argument or "?")
    elif base == "BM_RmseContrastInvariant":
        named = dict(part.split(":", 1) for part in argument.split("/") if ":" in part)
        threads = named.get("threads", "?")
        text += (f", {RMSE_CI_CASES.get(named.get('case'), 'case ' + named.get('case', '?'))}, "
                 f"{threads} thread{'s' if threads != '1' else ''}")
    elif argument:
        text += f", {argument}"
    return f"{text} (`{name}`)"


def wrap(text, indent=""):
    """A paragraph or a list item wrapped at 100 columns."""
    return textwrap.fill(text, width=100, initial_indent="", subsequent_indent=indent,
                         break_long_words=False, break_on_hyphens=False)


def runs_text(count):
    return "a single run, no median" if count == "1" else f"median of {count} runs"


def render_campaigns(campaigns, add):
    """The campaign-throughput section: settings per second of `fssim campaign`."""
    add("## Campaign throughput")
    add("")
    add("`fssim campaign` ([campaign.md](campaign.md)) on camera.png, raskar, numerical mode, the "
        "default sampler, one trial a setting, into a fresh directory each run (the journal, "
        "its fsync per setting and the result files included): whole-process wall time, "
        "settings per second = settings / median wall time.")
    add("")
    add("| campaign | runs | settings | median wall time, peak memory | settings per second | "
        "arguments |")
    add("|---|---:|---:|---:|---:|---|")
    for c in campaigns:
        per_second = c["settings"] / c["seconds"] if c["seconds"] > 0 else 0.0
        add(f"| {c['name']} | {c['runs']} | {c['settings']} | {c['seconds']:.3f} s, "
            f"{c['megabytes']} MB | {per_second:.1f} | `{c['arguments']}` |")
    add("")


def render_loops(loops, add):
    """The Python-loop section: runs per second of fss.simulate and numpy's simulate()."""
    add("## Python loop")
    add("")
    add("`bench/python_loop.py`: in one Python process, the image read once, then repeated calls "
        "of `fss.simulate` (raskar, default options, seeds 1, 2, …) and of "
        "`bench/numpy_flutter.py`'s `simulate()` (the same model in numpy, in memory, no files): "
        "runs per second (the calls over the loop's wall time, the first call included) and "
        "the median wall time of a call.")
    add("")
    add("| loop | program | calls | runs per second | median per call |")
    add("|---|---|---:|---:|---:|")
    for loop in loops:
        program = {"fss": "`fss.simulate`", "numpy": "`numpy_flutter.simulate`"}.get(
            loop["program"], loop["program"])
        add(f"| {loop['name']} | {program} | {loop['runs']} | {loop['per_second']:.2f} | "
            f"{1e3 * loop['median']:.1f} ms |")
    by_name = {}
    for loop in loops:
        by_name.setdefault(loop["name"], {})[loop["program"]] = loop["per_second"]
    ratios = [f"{name}: {p['fss'] / p['numpy']:.1f}×" for name, p in by_name.items()
              if p.get("fss") and p.get("numpy")]
    if ratios:
        add("")
        add("Runs per second of fss over numpy: " + "; ".join(ratios) + ".")
    add("")


def render_extra(extra, lines):
    """The campaign and Python-loop sections, when the results have them, after the cases."""
    if not extra.get("campaign") and not extra.get("loop"):
        return
    lines.append("")
    if extra.get("campaign"):
        render_campaigns(extra["campaign"], lines.append)
    if extra.get("loop"):
        render_loops(extra["loop"], lines.append)
    lines.pop()  # the blank line that ends a section: the next section adds its own


def render(meta, cases, generators, micro, extra=None):
    lines = []
    add = lines.append
    add("<!-- Generated by bench/report.py from the results of bench/run.sh; do not edit: run "
        "`bench/run.sh && bench/report.py` to regenerate it. -->")
    add("")
    add("# Performance")
    add("")
    add("The figures below are from **one run** of `bench/run.sh` on one machine. Compare them "
        "with each other, side by side; never with figures from another run, another day or "
        "another machine: to measure a change, build both versions and run them side by side "
        "in one session on an otherwise idle machine "
        "([CONTRIBUTING.md](../CONTRIBUTING.md#benchmarking)).")
    add("")
    add("## The run")
    add("")
    commit = meta.get("commit", "unknown")
    if meta.get("dirty") == "yes":
        commit += " with uncommitted changes"
    runs, big_runs = meta.get("runs", "?"), meta.get("big_runs", "?")
    rows = [
        ("date (UTC)", meta.get("date", "unknown")),
        ("commit", commit),
        ("fssim", meta.get("fssim_version", "unknown")),
        ("processor", meta.get("cpu", "unknown")),
        ("cores", meta.get("cores", "?")),
        ("memory", f"{meta['memory_gib']} GiB" if "memory_gib" in meta else "unknown"),
        ("runs", f"RUNS={runs} ({runs_text(runs)}); BIG_RUNS={big_runs} for the 4000×3000 and "
                 f"100-trial cases{' and the campaigns' if extra and extra.get('campaign') else ''}"
                 f" ({runs_text(big_runs)})"),
        ("load average (1, 5, 15 min)", f"{meta.get('load_start', '?')} at the start, "
                                         f"{meta.get('load_end', '?')} at the end"),
    ]
    if meta.get("note"):
        rows.append(("conditions", meta["note"]))
    add("| | |")
    add("|---|---|")
    for key, value in rows:
        add(f"| {key} | {value} |")
    add("")
    add("## What is measured")
    add("")
    add("`bench/run.sh` builds fssim in Release (`build-bench/`) and measures, for each case, "
        "the median wall time (the shell's microsecond clock, around GNU time) and the peak "
        "resident memory (GNU time, the largest of the runs) of:")
    add("")
    add("- **fssim per-frame**: fssim with its per-frame photon noise (`--noise poisson`, the "
        "default), one Poisson variate per frame and pixel;")
    add("- **fssim aggregated**: fssim with `--noise aggregated` (numerical mode only, "
        f"[method.md §6c]({METHOD_6C})): one exact Poisson variate per pixel for each set of "
        "frames of equal gains (every frame of raskar), and, for the other frames, one normal "
        "per pixel for those whose expected photon count is at least 50 and Knuth's method "
        "frame by frame for the rest;")
    add("- **numpy per-frame**: `bench/numpy_flutter.py`, the same model written with numpy as "
        "a user would (Debian's python3-numpy): per-frame `Generator.poisson`, `rfft`, the "
        "four image PNGs, no plots. It measures what a plain numpy program costs, not the "
        "fastest numpy possible. The ratio columns are its time over fssim's.")
    add("")
    add("Every case uses the raskar code, velocity 1, snr 100 and the default options: fssim "
        "draws its plots (code.png, spectrum.png) but in the \"no plots\" rows; the numpy "
        "program draws none, so the rows of a case with and without plots share one numpy "
        "measurement. Both write the observed, restored, residual and ground-truth PNGs.")
    add("")
    add("- **camera.png** (512×512 gray) and **astronaut.png** (512×512 RGB), in `data/`: a "
        "run of this size is mostly fixed costs (process start, plans, PNG files), not the "
        "simulation.")
    add("- **4000×3000 RGB (generated)**: a synthetic image written by `bench/make_image` "
        "(edges, ramps, texture); about 1 % of its samples are below 0.1 of full scale.")
    add("- **4000×3000 RGB (photograph)**: `data/astronaut.png` resized to 4000×3000 by "
        "`bench/scale_image.py` (Pillow, LANCZOS filter; stretched, the aspect ratio is not "
        "kept). Unlike the generated image it has large dark regions (about a quarter of its "
        "samples below 0.1 of full scale), where more frames fall on Knuth's branch (fewer "
        "than 50 expected photons), which the aggregated sampler draws frame by frame instead "
        "of aggregating: both images are needed to see its cost.")
    add("- **camera.png, 100 trials** (`--trials 100`): later trials share the first one's "
        "plan and noise-free work; fssim only (numpy_flutter.py has no trials).")
    add("")
    add("## Cases")
    add("")
    add("| case (raskar, v = 1, snr 100) | runs | fssim per-frame | fssim aggregated | "
        "numpy per-frame | numpy / fssim | numpy / aggregated |")
    add("|---|---:|---:|---:|---:|---:|---:|")
    for name, measures in cases:
        frame = measures.get("fssim")
        aggregated = measures.get("fssim-aggregated")
        numpy = measures.get("numpy")
        count = max(m["runs"] for m in measures.values())
        add(f"| {name} | {count} | {cell(frame)} | {cell(aggregated) or 'n/a'} | "
            f"{cell(numpy) or 'n/a'} | {ratio(numpy, frame)} | {ratio(numpy, aggregated)} |")
    add("")
    add("Each cell: median wall time, peak resident memory. n/a: not measured (the aggregated "
        "noise is for the numerical mode only; numpy_flutter.py has no trials).")
    if generators:
        add("")
        add("numpy's own generators in the same run, per variate (the floor a numpy user starts "
            "from): " + ", ".join(f"`Generator.{name}` {value:.0f} M variates/s"
                                  for name, value in generators) + ".")
    render_extra(extra or {}, lines)
    if micro:
        add("")
        add("## Micro-benchmarks")
        add("")
        add("`bench/micro_bench` (Google Benchmark), in the same run: time per iteration "
            "and throughput in items (variates, pixel frames, draws, rows) per second.")
        add("")
        add("| benchmark | time per iteration | throughput |")
        add("|---|---:|---:|")
        for name, real_time, unit, items in micro:
            add(f"| {micro_description(name)} | {duration(real_time, unit)} | {rate(items)} |")
        add("")
        add("(Google Benchmark warns that Debian builds its own library in debug mode; that "
            "concerns its harness, not the code measured, which is built in Release.)")
    add("")
    add("## Reproducing")
    add("")
    add("```sh")
    add("scripts/install-deps.sh            # Debian packages, among them time, python3-numpy,")
    add("                                   # python3-pil, libbenchmark-dev")
    add("RUNS=5 BIG_RUNS=3 bench/run.sh     # results in build-bench/results.tsv")
    add("bench/report.py                    # renders docs/performance.md from them")
    add("```")
    add("")
    add("Environment of `bench/run.sh`: `RUNS` (runs per case, default 5), `BIG_RUNS` (runs of "
        "the 4000×3000 and 100-trial cases and the campaigns, default 1), `LOOP_RUNS` (calls "
        "of each Python loop, default 50), `SKIP_MICRO=1` (no micro-benchmarks), "
        "`BENCH_RESULTS` (the results file, default `build-bench/results.tsv`), `BENCH_NOTE` "
        "(the conditions of the run, shown above). `bench/report.py [RESULTS] [-o OUTPUT]` "
        "reads that file. A run takes several minutes: each numpy run of a 4000×3000 image "
        "takes one to two minutes and about 3 GB.")
    add("")
    return "\n".join(wrap_page(lines))


def wrap_page(lines):
    """Paragraphs and list items wrapped at 100 columns; tables, code, headings kept."""
    fenced = False
    for line in lines:
        if line.startswith("```"):
            fenced = not fenced
        if fenced or line.startswith(("```", "|", "#", "<!--")) or len(line) <= 100:
            yield line
        else:
            yield wrap(line, "  " if line.startswith("- ") else "")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", nargs="?",
                        default=os.path.join(ROOT, "build-bench", "results.tsv"))
    parser.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "performance.md"))
    args = parser.parse_args(argv[1:])
    meta, cases, generators, micro, extra = read_results(args.results)
    if not cases:
        raise SystemExit(f"report: no case in {args.results}")
    page = render(meta, cases, generators, micro, extra)
    if args.output == "-":
        sys.stdout.write(page)
    else:
        temporary = args.output + ".tmp"
        with open(temporary, "w", encoding="utf-8") as f:
            f.write(page)
        os.replace(temporary, args.output)
        print(f"report: wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
