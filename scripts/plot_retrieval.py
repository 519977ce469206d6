#!/usr/bin/python3
"""Draws the place-recognition evaluation (`mdbrief-eval retrieval`: retrieval.csv) as one PNG:
per data set, recall@k of every method (bars side by side), and prints the recall and speed
tables (retrieval.csv, retrieval_speed.csv) as markdown for docs/RESULTS.md.

Usage: scripts/plot_retrieval.py OUT_DIR OUT_PNG, OUT_DIR holding both CSVs. Needs Debian's
python3-matplotlib (/usr/bin/python3).
"""
import argparse
import csv
import os
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_results import md_table  # noqa: E402 (the sibling script's table format)

COLORS = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no rows")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("png")
    args = ap.parse_args()
    recall = read(os.path.join(args.out_dir, "retrieval.csv"))
    speed = read(os.path.join(args.out_dir, "retrieval_speed.csv"))
    ks = [c for c in recall[0] if c.startswith("recall_at_")]
    groups = OrderedDict()
    for r in recall:
        groups.setdefault(r["group"], []).append(r)
    methods = list(OrderedDict.fromkeys(r["method"] for r in recall))

    fig, axes = plt.subplots(1, len(ks), figsize=(5.5 * len(ks), 3.6), squeeze=False)
    width = 0.8 / len(methods)
    for ax, k in zip(axes[0], ks):
        for j, method in enumerate(methods):
            xs, ys = [], []
            for i, members in enumerate(groups.values()):
                for m in members:
                    if m["method"] == method:
                        xs.append(i + (j - (len(methods) - 1) / 2) * width)
                        ys.append(float(m[k]))
            words = next(r["words"] for r in recall if r["method"] == method)
            ax.bar(xs, ys, width, label="%s (%s words)" % (method, words), color=COLORS[j % len(COLORS)])
        ax.set_xticks(range(len(groups)))
        ax.set_xticklabels(["%s\n(%s queries)" % (g, m[0]["queries"]) for g, m in groups.items()], fontsize=8)
        ax.set_ylim(0, 1.05)
        ax.grid(axis="y", alpha=0.3)
        ax.set_title(k.replace("recall_at_", "recall@"), fontsize=10)
    axes[0, -1].legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
    tmp = args.png + ".tmp.png"
    fig.savefig(tmp, dpi=90, bbox_inches="tight")
    os.replace(tmp, args.png)
    print(f"{args.png}: {len(groups)} groups, {len(methods)} methods\n")

    print(md_table(["method", "group", "words", "queries"] + [k.replace("recall_at_", "recall@") for k in ks],
                   [[r["method"], r["group"], r["words"], r["queries"]] + ["%.3f" % float(r[k]) for k in ks]
                    for r in recall]))
    print()

    def optional(value, fmt):
        return "-" if float(value) < 0 else fmt % float(value)

    print(md_table(["method", "words", "features / query", "transform ms / 1000 features", "query ms",
                    "binary bytes", "binary load ms", "DBoW2 text bytes", "DBoW2 text load ms"],
                   [[s["method"], s["words"], "%.0f" % float(s["query_features"]),
                     "%.3f" % float(s["transform_ms_per_1000_features"]), "%.3f" % float(s["query_ms"]),
                     "%.0f" % float(s["binary_bytes"]), "%.2f" % float(s["binary_load_ms"]),
                     optional(s["dbow2_text_bytes"], "%.0f"), optional(s["dbow2_text_load_ms"], "%.1f")]
                    for s in speed]))


if __name__ == "__main__":
    main()
