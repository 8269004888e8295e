#!/usr/bin/python3
"""Plots the drift experiment's CSV (bench/drift --csv FILE) as docs/drift.png.

Usage: scripts/plot_drift.py drift.csv docs/drift.png   (needs Debian's python3-matplotlib)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(source: str, target: str) -> None:
    with open(source, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], rows[1:]
    x = [float(r[0]) for r in data]
    fig, ax = plt.subplots(figsize=(9, 5.5), dpi=110)
    styles = {"none": "-", "every step": "--", "every k": ":"}
    colors = {"4x4 matrix": "tab:red", "3x4 matrix": "tab:orange", "quaternion + vector": "tab:green",
              "dual quaternion": "tab:blue", "4x4 matrix (polar)": "tab:purple", "3x4 matrix (polar)": "tab:brown"}
    for column, name in enumerate(header[1:], start=1):
        representation, policy = name.split(" / ")
        if representation.endswith("(polar)") and policy == "every k":
            continue  # keeps the plot readable; the table has every row
        y = [max(float(r[column]), 1e-9) for r in data]
        ax.plot(x, y, styles[policy], color=colors[representation], label=f"{representation}, {policy}", linewidth=1.4)
    ax.set_yscale("log")
    ax.set_xlabel("frames (% of 100,000)")
    ax.set_ylabel("end-effector position error ÷ chain reach")
    ax.set_title("Drift of a 32-link chain accumulated in float, against double")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    fig.savefig(target)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
