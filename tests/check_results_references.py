#!/usr/bin/env python3
"""Every section of docs/RESULTS.md or docs/HISTORY.md that the code or the documents point to by
name (docs/RESULTS.md "Heading", or a quoted heading on the comment lines that follow) exists, so
a "why" never points at a section that was renamed or removed. The guide and the README may
write RESULTS "Heading" for the results page. The results page's own headings
are stable names: none carries an issue number (the history keeps those), and the code and the
installed headers point to the results, not to the history.

Usage: check_results_references.py REPOSITORY_ROOT"""
import os
import re
import sys

FOLDERS = ["libmdbrief", "eval", "cli", "trainer", "patchextract", "toolkit", "python", "bench"]
DOCUMENTS = ["README.md", "docs"]
QUOTED = re.compile(r'"([^"]+)"')
TARGETS = {"RESULTS.md": "RESULTS.md", "HISTORY.md": "HISTORY.md"}
ISSUE = re.compile(r"\bissues? [0-9]")


def headings(path):
    out = set()
    for line in open(path, encoding="utf-8"):
        m = re.match(r"#+\s+(.*\S)\s*$", line)
        if m:
            out.add(m.group(1))
    return out


def references(path, target):
    """Quoted names in the comment run that mentions TARGET, from the mention on."""
    lines = open(path, encoding="utf-8", errors="replace").read().split("\n")
    for i, line in enumerate(lines):
        if target not in line:
            continue
        text = line[line.index(target):]
        j = i + 1
        while j < len(lines) and lines[j].strip().startswith(("//", "#")) and target not in lines[j]:
            text += " " + lines[j].strip().lstrip("/#").strip()
            j += 1
        # A name may wrap onto the next comment line: join first, then take the quotes.
        for name in QUOTED.findall(text):
            yield i + 1, " ".join(name.split())


def document_references(path):
    """In markdown, a name follows its file on the same paragraph: 'RESULTS.md "Heading"' or
    '[HISTORY.md](HISTORY.md) "Heading"', possibly wrapped; a bare quoted heading inside a
    results file points into that file."""
    text = open(path, encoding="utf-8").read()
    own = os.path.basename(path)
    # RESULTS alone is the results page too (the guide's and the README's short form); a heading
    # list after it ("A", "B" and "C") names sections of the same page.
    pattern = re.compile(r'\b(RESULTS(?:\.md)?|HISTORY\.md)(?:\]\([^)]*\))?[)"]?[,;:]?\s+(?:sections?\s+)?'
                         r'("[^"]+"(?:(?:,|\s+and|\s+or)?\s+"[^"]+")*)')
    for m in pattern.finditer(text):
        target = "RESULTS.md" if m.group(1).startswith("RESULTS") else m.group(1)
        for name in QUOTED.findall(m.group(2)):
            yield text.count("\n", 0, m.start()) + 1, target, " ".join(name.split())
    if own in TARGETS:
        for m in re.finditer(r'"([^"]+)"', text):
            name = " ".join(m.group(1).split())
            before = text[max(0, m.start() - 30):m.start()]
            if "HISTORY.md" in before or "RESULTS.md" in before:
                continue
            yield text.count("\n", 0, m.start()) + 1, own, name


def main():
    root = sys.argv[1]
    known = {name: headings(os.path.join(root, "docs", name)) for name in TARGETS}
    all_headings = known["RESULTS.md"] | known["HISTORY.md"]
    missing = []
    count = 0
    for heading in sorted(known["RESULTS.md"]):
        if ISSUE.search(heading):
            missing.append(f"docs/RESULTS.md: heading \"{heading}\" names an issue; the history keeps those")
    for folder in FOLDERS:
        for base, _, files in os.walk(os.path.join(root, folder)):
            for name in files:
                if not name.endswith((".hpp", ".cpp", ".py")):
                    continue
                path = os.path.join(base, name)
                rel = os.path.relpath(path, root)
                if "HISTORY.md" in open(path, encoding="utf-8", errors="replace").read():
                    missing.append(f"{rel}: points to docs/HISTORY.md; the code points to RESULTS.md or the guide")
                for line, ref in references(path, "RESULTS.md"):
                    # Only names that read like headings: a capital letter first.
                    if not ref[:1].isupper():
                        continue
                    count += 1
                    if ref not in known["RESULTS.md"]:
                        missing.append(f"{rel}:{line}: \"{ref}\" (docs/RESULTS.md)")
    paths = []
    for entry in DOCUMENTS:
        full = os.path.join(root, entry)
        if os.path.isfile(full):
            paths.append(full)
        for base, _, files in os.walk(full) if os.path.isdir(full) else []:
            paths += [os.path.join(base, f) for f in files if f.endswith(".md")]
    for path in sorted(paths):
        for line, target, ref in document_references(path):
            # Names that read like headings (a capital first) and, inside the results files,
            # only those that are some section's name (the rest are quoted terms).
            if not ref[:1].isupper():
                continue
            if os.path.basename(path) == target and ref not in all_headings and not ISSUE.search(ref):
                continue
            count += 1
            if ref not in known[target]:
                missing.append(f"{os.path.relpath(path, root)}:{line}: \"{ref}\" (docs/{target})")
    if missing:
        print("references that do not hold:\n  " + "\n  ".join(missing))
        return 1
    print(f"{count} references to sections of docs/RESULTS.md and docs/HISTORY.md, all found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
