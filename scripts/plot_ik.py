#!/usr/bin/python3
"""Draws docs/ik_paths.png and docs/ik_errors.png from the CSV of bench/ik_experiment.

The paths redraw the Kenwright paper's figure: the ideal end effector (red) and the computed one
(green), for the arm, the leg and the biped, with dual quaternions. The errors: position error
per frame, every solver.

    /usr/bin/python3 scripts/plot_ik.py ik_experiment.csv docs/
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, out_dir):
    rows = defaultdict(list)
    with open(csv_path, newline="") as f:
        for r in csv.DictReader(f):
            rows[(r["scenario"], r["solver"])].append(r)
    scenarios = sorted({s for s, _ in rows}, key=["arm", "leg", "biped"].index)

    fig = plt.figure(figsize=(15, 5))
    for k, scenario in enumerate(scenarios):
        data = rows[(scenario, "LM (dual quaternions)")]
        ax = fig.add_subplot(1, len(scenarios), k + 1, projection="3d")
        for (x, y, z), colour, label in (
            (("tx", "ty", "tz"), "red", "ideal (target)"),
            (("x", "y", "z"), "green", "computed (dual quaternions)"),
        ):
            ax.plot([float(r[x]) for r in data], [float(r[y]) for r in data], [float(r[z]) for r in data],
                    color="red" if colour == "red" else "limegreen", linewidth=4 if colour == "red" else 1.2,
                    linestyle="-" if colour == "red" else "--", label=label)
        worst = max(float(r["position_error"]) for r in data)
        ax.set_title(f"{scenario}: {len(data)} frames\nworst position error {worst:.1e} m (the lines coincide)", fontsize=10)
        ax.legend(loc="upper left", fontsize=8)
    fig.suptitle("End effector following a moving 6-DOF target (the Kenwright experiment)")
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    fig.savefig(f"{out_dir}/ik_paths.png", dpi=90)

    fig, axes = plt.subplots(1, len(scenarios), figsize=(15, 4), sharey=True)
    for ax, scenario in zip(axes, scenarios):
        for (s, solver), data in sorted(rows.items()):
            if s != scenario:
                continue
            ax.semilogy([int(r["frame"]) for r in data], [max(float(r["position_error"]), 1e-17) for r in data],
                        label=solver, linewidth=0.8)
        ax.axhline(1e-10, color="grey", linestyle=":", linewidth=0.8)
        ax.set_title(scenario)
        ax.set_xlabel("frame")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("position error (m); dotted: the 1e-10 tolerance")
    fig.tight_layout()
    fig.savefig(f"{out_dir}/ik_errors.png", dpi=90)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
