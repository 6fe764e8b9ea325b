"""Python's overhead, for BENCHMARKS.md: `sim.step()` of the bench cloth
called from Python against `pleat bench`'s ms/frame for the same cloth
(interleaved runs; medians and fastest rounds), and the cost of reading `positions` of a
large cloth (a view on the CPU backend: no copy per read).

    python step_overhead.py --pleat target/release/pleat [--n 128] [--rounds 5]
"""

import argparse
import json
import statistics
import subprocess
import time

import numpy as np

import pleat


def cli_ms(pleat_bin, n, frames, warmup):
    out = subprocess.run(
        [pleat_bin, "bench", "--sizes", str(n), "--frames", str(frames), "--warmup", str(warmup), "--json"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return json.loads(out.splitlines()[0])["ms_per_frame"]


def python_ms(n, frames, warmup):
    sim = pleat.Simulation(pleat.Scene.hanging_cloth(n))
    sim.step(warmup)
    times = []
    for _ in range(frames):
        start = time.perf_counter()
        sim.step()
        times.append(time.perf_counter() - start)
    return 1e3 * sum(times) / len(times)


def read_us(sim, reads=2000):
    start = time.perf_counter()
    for _ in range(reads):
        sim.positions
    return 1e6 * (time.perf_counter() - start) / reads


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pleat", required=True, help="the pleat command (a release build)")
    parser.add_argument("--n", type=int, default=128)
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--warmup", type=int, default=30)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--large", type=int, default=1024)
    args = parser.parse_args()

    cli, py = [], []
    for _ in range(args.rounds):
        cli.append(cli_ms(args.pleat, args.n, args.frames, args.warmup))
        py.append(python_ms(args.n, args.frames, args.warmup))
    c, p = statistics.median(cli), statistics.median(py)
    print(f"{args.n} x {args.n}, {args.rounds} rounds of {args.frames} frames, interleaved")
    print(f"  pleat bench: median {c:.3f} ms/frame  (rounds {', '.join(f'{x:.3f}' for x in cli)})")
    print(f"  sim.step():  median {p:.3f} ms/frame  (rounds {', '.join(f'{x:.3f}' for x in py)})")
    print(f"  Python / command: {p / c:.3f} (medians), {min(py) / min(cli):.3f} (fastest rounds)")

    big = pleat.Simulation(pleat.Scene.hanging_cloth(args.large))
    big.step()
    view = big.positions
    copies = 20
    copy_start = time.perf_counter()
    for _ in range(copies):
        np.array(view)
    copy_us = 1e6 * (time.perf_counter() - copy_start) / copies
    print(f"{args.large} x {args.large} ({len(big)} particles): positions read in {read_us(big):.2f} us "
          f"(a view: shares memory {np.shares_memory(view, big.positions)}, writeable {view.flags.writeable}); "
          f"a copy of it takes {copy_us:.0f} us")
    gpu = None
    try:
        gpu = pleat.Simulation(pleat.Scene.hanging_cloth(args.large), backend="gpu")
    except pleat.BackendError as e:
        print(f"GPU: {e}")
    if gpu is not None:
        gpu.step()
        print(f"GPU ({gpu.device}): positions read back in {read_us(gpu, 20):.0f} us (a readback into a new array)")


if __name__ == "__main__":
    main()
