#!/usr/bin/python3
"""Draws the tracker benchmark (`mdbrief-eval tracker`, tracker_summary.csv) as one PNG: per data
set, for each pipeline at its shown ratio, the share of pairs whose homography fit is right
within 3 px and within 1 px, the precision of the kept matches and the mean average precision,
with the keypoints per image and the correct matches per pair written above the bars. With
--md, also regenerates the section "## Tracker benchmark (generated)" of that markdown file.

Usage: scripts/plot_tracker.py SUMMARY_CSV OUT_PNG [--md docs/RESULTS.md]. Needs Debian's
python3-matplotlib (/usr/bin/python3).
"""
import argparse
import csv
import os
import sys
import textwrap
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METRICS = [("homography_right_3px", "fit right, 3 px"), ("homography_right_1px", "fit right, 1 px"),
           ("precision", "precision of kept matches"), ("mean_ap", "mean AP")]
COLORS = ["#1b9e77", "#66c2a5", "#d95f02", "#7570b3"]


SECTION = "## Tracker benchmark (generated)"


def pct(value):
    return "-" if float(value) < 0 else "%.0f %%" % (100 * float(value))


def section(groups, figure):
    """The tables of the section: every pipeline at its shown ratio, per data set."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from plot_results import md_table  # noqa: E402 (the sibling script's table format)
    header = ["pipeline", "ratio", "mean AP", "PR AUC", "repeatability", "correct / pair", "precision",
              "H right 3 px", "H right 1 px", "H inliers", "E right 3 px", "E right 1 px"]
    text = [SECTION, "",
            "Written by `scripts/tracker.sh` (`mdbrief-eval tracker`, then `scripts/plot_tracker.py`): every",
            "pipeline on its own keypoints at its shown ratio (its own for the library's presets, otherwise",
            "the best of the sweep by right fits); what the columns mean is in \"Real images: what a tracker",
            "keeps\". Figure: `%s`." % figure, ""]
    for group, members in groups.items():
        text += ["### %s (%s pairs)" % (group, members[0]["pairs"]), ""]
        rows = [[m["pipeline"], m["ratio"], "%.3f" % float(m["mean_ap"]), "%.3f" % float(m["pr_auc"]),
                 "%.3f" % float(m["repeatability"]), "%.1f" % float(m["correct_per_pair"]),
                 "%.3f" % float(m["precision"]), pct(m["homography_right_3px"]), pct(m["homography_right_1px"]),
                 "%.1f" % float(m["homography_inliers"]), pct(m["essential_right_3px"]),
                 pct(m["essential_right_1px"])] for m in members]
        text += [md_table(header, rows), ""]
    return "\n".join(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("summary")
    ap.add_argument("png")
    ap.add_argument("--md", help="markdown file whose generated section is rewritten")
    args = ap.parse_args()
    with open(args.summary, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["shown"] == "1"]
    if not rows:
        sys.exit(f"{args.summary}: no rows")
    groups = OrderedDict()
    for r in rows:
        groups.setdefault(r["group"], []).append(r)
    fig, axes = plt.subplots(len(groups), 1, figsize=(11, 3.6 * len(groups)), squeeze=False)
    fig.subplots_adjust(hspace=0.6)
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
        # Wrapped: the library's pipeline names are wider than their bars.
        ax.set_xticklabels([textwrap.fill(m["pipeline"], 12, break_long_words=False) for m in members], fontsize=8)
        ax.set_ylim(0, 1.25)
        ax.set_yticks([0, 0.25, 0.5, 0.75, 1.0])
        ax.grid(axis="y", alpha=0.3)
        ax.set_title("%s (%s pairs)" % (group, members[0]["pairs"]), fontsize=10)
    axes[0, 0].legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
    tmp = args.png + ".tmp.png"
    fig.savefig(tmp, dpi=90, bbox_inches="tight")
    os.replace(tmp, args.png)
    print(f"{args.png}: {len(groups)} data sets")
    if args.md:
        from plot_results import update_markdown  # noqa: E402
        figure = os.path.relpath(os.path.abspath(args.png), os.path.dirname(os.path.abspath(args.md)))
        update_markdown(args.md, {SECTION: section(groups, figure)})
        print(f"{args.md}: {SECTION}")


if __name__ == "__main__":
    main()
