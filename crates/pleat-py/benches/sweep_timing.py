"""A 64-variant sweep, serial against Ray, for BENCHMARKS.md: bend
compliance (8 values) times substeps (8 values) on the drape scene; both
runs must give the same figures.

    python sweep_timing.py [--frames 60] [--workers 2]
"""

import argparse
import tempfile
import time

import pleat

FIGURES = ("max_stretch", "mean_stretch", "kinetic_energy", "collider_penetrations", "exit_code")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    grid = {
        "cloths[0].material.bend_compliance": [1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 1e-1, 1.0, 10.0],
        "solver.substeps": [4, 6, 8, 10, 12, 14, 16, 20],
    }
    scene = pleat.Scene.default()
    tables = {}
    for mode in ("serial", "ray"):
        with tempfile.TemporaryDirectory() as out:
            start = time.perf_counter()
            table = pleat.sweep(scene, grid, frames=args.frames, out=out, serial=mode == "serial", workers=args.workers)
            wall = time.perf_counter() - start
        rows = table if isinstance(table, list) else table.to_dict("records")
        tables[mode] = [tuple(r[k] for k in FIGURES) for r in rows]
        print(f"{mode}: {len(rows)} variants of {args.frames} frames in {wall:.1f} s wall")
    print("same figures:", tables["serial"] == tables["ray"])


if __name__ == "__main__":
    main()
