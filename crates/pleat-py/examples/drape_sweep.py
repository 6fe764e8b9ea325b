"""Bend compliance times substeps on the drape scene, swept on Ray.

Runs the default scene (a cloth draped over a sphere onto the ground) for
every pair of bend compliance and substeps, prints the table and, where
matplotlib is installed, plots max stretch, kinetic energy and time per
frame against bend compliance, one line per substep count
(OUT/sweep.png). Each variant's report, scene and final mesh are in OUT;
run it again after an interruption and only the missing variants run.

    python drape_sweep.py [--out out/drape_sweep] [--frames 120] [--serial]
"""

import argparse
import os

import pleat

BEND = [1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0]
SUBSTEPS = [5, 10, 20]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out/drape_sweep")
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--serial", action="store_true", help="run without Ray")
    parser.add_argument("--address", help="a Ray cluster (default: a local Ray)")
    args = parser.parse_args()

    table = pleat.sweep(
        pleat.Scene.default(),
        {"cloths[0].material.bend_compliance": BEND, "solver.substeps": SUBSTEPS},
        frames=args.frames,
        out=args.out,
        serial=args.serial,
        address=args.address,
    )
    rows = table if isinstance(table, list) else table.to_dict("records")
    print(f"{'bend':>8} {'substeps':>8} {'exit':>4} {'max stretch':>11} {'energy (J)':>11} {'ms/frame':>9}")
    for r in rows:
        print(
            f"{r['cloths[0].material.bend_compliance']:>8g} {r['solver.substeps']:>8} {r['exit_code']:>4} "
            f"{r['max_stretch'] or float('nan'):>11.4f} {r['kinetic_energy'] or float('nan'):>11.2e} "
            f"{r['ms_per_frame'] or float('nan'):>9.2f}"
        )
    plot(rows, os.path.join(args.out, "sweep.png"))


def plot(rows, path):
    """Three panels against bend compliance, one line per substep count."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot")
        return
    panels = [("max_stretch", "max stretch"), ("kinetic_energy", "kinetic energy (J)"), ("ms_per_frame", "ms per frame")]
    fig, axes = plt.subplots(1, len(panels), figsize=(13, 3.8))
    for substeps in SUBSTEPS:
        mine = [r for r in rows if r["solver.substeps"] == substeps and r["exit_code"] == 0]
        x = [r["cloths[0].material.bend_compliance"] for r in mine]
        for ax, (key, label) in zip(axes, panels):
            ax.plot(x, [r[key] for r in mine], marker="o", label=f"{substeps} substeps")
            ax.set_xscale("log")
            ax.set_xlabel("bend compliance")
            ax.set_ylabel(label)
    axes[1].set_yscale("log")
    axes[0].legend()
    fig.suptitle("drape: bend compliance x substeps")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
