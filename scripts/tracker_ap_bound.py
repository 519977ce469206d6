#!/usr/bin/python3
"""How high a data set's mean AP can reach with the methods measured: for each pair the best AP
of any pipeline in the tracker benchmark's per-pair table, and their mean (docs/RESULTS.md
"Targets"). Ratios are to the reference pipeline's mean AP.

Usage: /usr/bin/python3 scripts/tracker_ap_bound.py [PAIRS_CSV] [--group oxford] [--reference AKAZE]
           [--perfect SEQ:A-B ...]
PAIRS_CSV defaults to docs/results/tracker/tracker_pairs.csv (scripts/tracker.sh writes it).
--perfect also prints the bound with those pairs (sequence, then images a-b, e.g. graf:1-4) at AP 1.
"""
import argparse
import csv
import sys
from collections import defaultdict


def read_ap(path, group):
    """{(sequence, image_a, image_b): {pipeline: AP}} of one group; AP does not depend on the ratio."""
    table = defaultdict(dict)
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["group"] == group:
                table[(row["sequence"], row["image_a"], row["image_b"])][row["pipeline"]] = float(row["average_precision"])
    return table


def pipeline_means(table):
    sums, counts = defaultdict(float), defaultdict(int)
    for per_pipeline in table.values():
        for pipeline, ap in per_pipeline.items():
            sums[pipeline] += ap
            counts[pipeline] += 1
    return {p: sums[p] / counts[p] for p in sums}


def best_of_all(table, perfect=()):
    """Mean over the pairs of the best AP any pipeline reached (1 on the `perfect` pairs)."""
    return sum(1.0 if pair in perfect else max(aps.values()) for pair, aps in table.items()) / len(table)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("pairs", nargs="?", default="docs/results/tracker/tracker_pairs.csv")
    ap.add_argument("--group", default="oxford")
    ap.add_argument("--reference", default="AKAZE")
    ap.add_argument("--perfect", nargs="*", default=[], metavar="SEQ:A-B")
    args = ap.parse_args(argv)
    try:
        table = read_ap(args.pairs, args.group)
    except (OSError, KeyError, ValueError) as e:
        print(f"tracker_ap_bound: {args.pairs}: {e}", file=sys.stderr)
        return 2
    if not table:
        print(f"tracker_ap_bound: {args.pairs} has no pair of group '{args.group}'", file=sys.stderr)
        return 2
    means = pipeline_means(table)
    if not means.get(args.reference, 0.0) > 0.0:
        print(f"tracker_ap_bound: no pipeline '{args.reference}' with a mean AP above 0; there are: "
              f"{', '.join(sorted(means))}",
              file=sys.stderr)
        return 2
    perfect = set()
    for spec in args.perfect:
        sequence, _, images = spec.rpartition(":")
        pair = (sequence, *images.partition("-")[::2])
        if pair not in table:
            print(f"tracker_ap_bound: --perfect {spec}: no such pair in group '{args.group}'", file=sys.stderr)
            return 2
        perfect.add(pair)
    reference = means[args.reference]
    print(f"{args.group}: {len(table)} pairs, mean AP per pipeline (x {args.reference}):")
    for pipeline, mean in sorted(means.items(), key=lambda kv: -kv[1]):
        print(f"  {pipeline:40s} {mean:.3f}  {mean / reference:.2f}x")
    bound = best_of_all(table)
    print(f"  {'best of all, per pair':40s} {bound:.3f}  {bound / reference:.2f}x")
    if perfect:
        with_perfect = best_of_all(table, perfect)
        print(f"  {'... and AP 1 on ' + ' '.join(args.perfect):40s} {with_perfect:.3f}  {with_perfect / reference:.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
