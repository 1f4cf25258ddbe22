#!/usr/bin/env python3
"""The Python module's per-call overhead on MPNet and UGNet (docs/embedding.md).

Times deixis.Mpnet.run and deixis.Ugnet.run (the shipped MoE networks) on batches of 1 and 64
windows, and in alternation with them the bare C function the module calls (deixis_mpnet_run,
deixis_ugnet_run through ctypes with the pointers prepared once), so that a shared machine's load
falls on both alike: the difference is what the module adds per call (shape and dtype checks,
the output array, the ctypes conversions). With --api-bench, the same calls from C++
(api_bench) are listed beside them.

    PYTHONPATH=build/release/python python3 bench/python_overhead.py \
        --api-bench build/release/bench/api_bench
"""

import argparse
import json
import statistics
import subprocess
import sys
import timeit

import numpy as np

import deixis


def alternating_us(first, second, repeats):
    """Median microseconds per call of each function, timed in alternation, `repeats` rounds of
    enough calls to last ~0.2 s each."""
    calls, _ = timeit.Timer(first).autorange()
    a, b = [], []
    for _ in range(repeats):
        a.append(timeit.timeit(first, number=calls) / calls * 1e6)
        b.append(timeit.timeit(second, number=calls) / calls * 1e6)
    return statistics.median(a), statistics.median(b)


def bare_call(network, x):
    """The C function the module's run() calls, with its pointers made once."""
    count = x.shape[0]
    if isinstance(network, deixis.Mpnet):
        out = np.empty((count, 3), np.float32)
        args = (network._handle, x.ctypes.data_as(deixis._float_p), count,
                out.ctypes.data_as(deixis._float_p))
        return lambda: deixis._mpnet_run(*args)
    out = np.empty((count, 24), np.float32)
    args = (network._handle, x.ctypes.data_as(deixis._float_p), None, count,
            out.ctypes.data_as(deixis._float_p))
    return lambda: deixis._ugnet_run(*args)


def c_api_us(api_bench, repeats):
    """Median microseconds per call of BM_CApiMpnetRun/B and BM_CApiUgnetRun/B."""
    out = subprocess.run(
        [api_bench, "--benchmark_filter=BM_CApi(Mpnet|Ugnet)Run", "--benchmark_format=json",
         f"--benchmark_repetitions={repeats}", "--benchmark_report_aggregates_only=true"],
        check=True, capture_output=True, text=True).stdout
    report = json.loads(out[out.index("{"):out.rindex("}") + 1])
    return {b["run_name"]: b["real_time"] for b in report["benchmarks"]
            if b.get("aggregate_name") == "median"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--api-bench", help="path of api_bench, for the C API's side")
    parser.add_argument("--repeats", type=int, default=10, help="timings per figure (median)")
    args = parser.parse_args()

    mpnet, ugnet = deixis.Mpnet(), deixis.Ugnet()
    c = c_api_us(args.api_bench, args.repeats) if args.api_bench else {}
    print(f"deixis {deixis.version()}, Python {sys.version.split()[0]}, NumPy {np.__version__}")
    print("| call | batch | module µs/call | bare C call µs | module overhead µs "
          "| C++ (api_bench) µs |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, network, columns in (("Mpnet", mpnet, 11), ("Ugnet", ugnet, 32)):
        for batch in (1, 64):
            x = np.full((batch, 30, columns), 0.1, np.float32)
            module, bare = alternating_us(lambda: network.run(x), bare_call(network, x),
                                          args.repeats)
            c_us = c.get(f"BM_CApi{name}Run/{batch}")
            c_text = f"{c_us:.2f}" if c_us is not None else "–"
            print(f"| {name}.run | {batch} | {module:.2f} | {bare:.2f} | {module - bare:.2f} "
                  f"| {c_text} |")


if __name__ == "__main__":
    main()
