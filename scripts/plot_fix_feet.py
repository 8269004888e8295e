#!/usr/bin/python3
"""Draws docs/fix_feet.png: the toes of a capture before and after `dqkit fix-feet`, from two CSVs
of `dqkit fk FILE --all --joint LeftToeBase --joint RightToeBase`.

    /usr/bin/python3 scripts/plot_fix_feet.py before.csv after.csv docs/fix_feet.png [first last]
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    out = defaultdict(lambda: defaultdict(list))
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            for k in ("frame", "x", "y", "z"):
                out[r["joint"]][k].append(float(r[k]))
    return out


def steps(d, sel):
    return [max(((d["x"][i] - d["x"][i - 1]) ** 2 + (d["z"][i] - d["z"][i - 1]) ** 2) ** 0.5, 1e-9) for i in sel]


def main(before_path, after_path, png, first=1, last=700):
    before, after = read(before_path), read(after_path)
    joints = sorted(before)
    fig, axes = plt.subplots(2, len(joints), figsize=(7 * len(joints), 8), squeeze=False)
    for c, joint in enumerate(joints):
        b, a = before[joint], after[joint]
        sel = [i for i, f in enumerate(b["frame"]) if first <= f <= last and i > 0]
        frames = [b["frame"][i] for i in sel]
        ax = axes[0][c]
        ax.semilogy(frames, steps(b, sel), label="before", linewidth=1)
        ax.semilogy(frames, steps(a, sel), label="after", linewidth=1)
        ax.set_ylabel("horizontal travel per frame (log)")
        ax.set_xlabel("frame")
        ax2 = ax.twinx()
        ax2.plot(frames, [b["y"][i] for i in sel], color="grey", linewidth=0.8, label="height")
        ax2.set_ylabel("height (grey)")
        ax.legend(loc="lower right", fontsize=8)
        ax.set_title(f"{joint}: the foot during contacts (low height) no longer moves")
        # Seen from above, the first 200 frames (one contact): a slide before, one point after.
        ax = axes[1][c]
        zoom = [i for i in sel if b["frame"][i] <= first + 200]
        ax.plot([b["x"][i] for i in zoom], [b["z"][i] for i in zoom], ".-", markersize=2, label="before", linewidth=0.8)
        ax.plot([a["x"][i] for i in zoom], [a["z"][i] for i in zoom], "o", markersize=5, fillstyle="none", label="after")
        ax.set_xlabel("x")
        ax.set_ylabel("z")
        ax.legend(fontsize=8)
        ax.set_title(f"seen from above, frames {first}-{first + 200} (in contact)")
    fig.tight_layout()
    fig.savefig(png, dpi=80)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], *map(int, sys.argv[4:6]))
