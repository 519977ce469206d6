#!/usr/bin/env python3
"""Every section of docs/RESULTS.md that the code points to by name (docs/RESULTS.md "Heading",
or a quoted heading on the comment lines that follow) exists, so a header's "why" never points
at a section that was renamed or removed.

Usage: check_results_references.py REPOSITORY_ROOT"""
import os
import re
import sys

FOLDERS = ["libmdbrief", "eval", "cli", "trainer", "patchextract", "toolkit", "python", "bench"]
QUOTED = re.compile(r'"([^"]+)"')


def headings(results):
    out = set()
    for line in open(results, encoding="utf-8"):
        m = re.match(r"#+\s+(.*\S)\s*$", line)
        if m:
            out.add(m.group(1))
    return out


def references(path):
    """Quoted names in the comment run that mentions docs/RESULTS.md, from the mention on."""
    lines = open(path, encoding="utf-8", errors="replace").read().split("\n")
    for i, line in enumerate(lines):
        if "RESULTS.md" not in line:
            continue
        text = line[line.index("RESULTS.md"):]
        j = i + 1
        while j < len(lines) and lines[j].strip().startswith(("//", "#")) and "RESULTS.md" not in lines[j]:
            text += " " + lines[j].strip().lstrip("/#").strip()
            j += 1
        # A name may wrap onto the next comment line: join first, then take the quotes.
        for name in QUOTED.findall(text):
            yield i + 1, " ".join(name.split())


def main():
    root = sys.argv[1]
    known = headings(os.path.join(root, "docs", "RESULTS.md"))
    missing = []
    count = 0
    for folder in FOLDERS:
        for base, _, files in os.walk(os.path.join(root, folder)):
            for name in files:
                if not name.endswith((".hpp", ".cpp", ".py")):
                    continue
                path = os.path.join(base, name)
                for line, ref in references(path):
                    # Only names that read like headings: a capital letter first.
                    if not ref[:1].isupper():
                        continue
                    count += 1
                    if ref not in known:
                        missing.append(f"{os.path.relpath(path, root)}:{line}: \"{ref}\"")
    if missing:
        print("sections of docs/RESULTS.md that do not exist:\n  " + "\n  ".join(missing))
        return 1
    print(f"{count} references to docs/RESULTS.md sections, all found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
