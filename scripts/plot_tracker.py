#!/usr/bin/python3
"""Draws the tracker benchmark (`mdbrief-eval tracker`, tracker_summary.csv) as one PNG: per data
set, for each pipeline at its shown ratio, the share of pairs whose homography fit is right
within 3 px and within 1 px, the precision of the kept matches and the mean average precision,
with the keypoints per image and the correct matches per pair written above the bars.

Usage: scripts/plot_tracker.py SUMMARY_CSV OUT_PNG. Needs Debian's python3-matplotlib
(/usr/bin/python3).
"""
import csv
import os
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METRICS = [("homography_right_3px", "fit right, 3 px"), ("homography_right_1px", "fit right, 1 px"),
           ("precision", "precision of kept matches"), ("mean_ap", "mean AP")]
COLORS = ["#1b9e77", "#66c2a5", "#d95f02", "#7570b3"]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["shown"] == "1"]
    if not rows:
        sys.exit(f"{sys.argv[1]}: no rows")
    groups = OrderedDict()
    for r in rows:
        groups.setdefault(r["group"], []).append(r)
    fig, axes = plt.subplots(len(groups), 1, figsize=(11, 3.2 * len(groups)), squeeze=False)
    for ax, (group, members) in zip(axes[:, 0], groups.items()):
        n = len(members)
        width = 0.8 / len(METRICS)
        for k, (key, label) in enumerate(METRICS):
            xs = [i + (k - (len(METRICS) - 1) / 2) * width for i in range(n)]
            ax.bar(xs, [float(m[key]) for m in members], width, label=label, color=COLORS[k])
        for i, m in enumerate(members):
            ax.text(i, 1.02, "%.0f kp, %.0f correct\nratio %s" % (float(m["keypoints"]), float(m["correct_per_pair"]),
                                                                 m["ratio"]), ha="center", va="bottom", fontsize=7)
        ax.set_xticks(range(n))
        ax.set_xticklabels([m["pipeline"] for m in members], fontsize=8)
        ax.set_ylim(0, 1.25)
        ax.set_yticks([0, 0.25, 0.5, 0.75, 1.0])
        ax.grid(axis="y", alpha=0.3)
        ax.set_title("%s (%s pairs)" % (group, members[0]["pairs"]), fontsize=10)
    axes[0, 0].legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    os.makedirs(os.path.dirname(os.path.abspath(sys.argv[2])), exist_ok=True)
    tmp = sys.argv[2] + ".tmp.png"
    fig.savefig(tmp, dpi=90, bbox_inches="tight")
    os.replace(tmp, sys.argv[2])
    print(f"{sys.argv[2]}: {len(groups)} data sets")


if __name__ == "__main__":
    main()
