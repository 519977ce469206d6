#!/usr/bin/env python3
"""The user guide's code is the examples' code, part for part, so it cannot rot: the examples in
examples/guide are built and run by the tests, and every C++ or Python block of docs/guide/*.md
(and shell block) follows a line <!-- example: examples/guide/FILE#PART --> and equals the lines of FILE between
"[guide:PART]" and "[guide]" (indentation removed). Every marked part of an example is shown
somewhere in the guide, and every C++ or Python block of the guide is such a part.

Usage: check_guide_snippets.py REPOSITORY_ROOT [--update]   (--update copies the parts into the
guide's marked blocks, after an example changed)"""
import os
import re
import sys
import textwrap

MARKER = re.compile(r"<!--\s*example:\s*(\S+?)#(\S+)\s*-->")
FENCE = re.compile(r"^```(\w*)\s*$")
START = re.compile(r"^\s*(?://|#)\s*\[guide:([\w-]+)\]\s*$")
END = re.compile(r"^\s*(?://|#)\s*\[guide\]\s*$")
CODE_LANGUAGES = ("cpp", "c++", "python", "py", "sh", "bash")


def parts(path):
    """{part: text} of one example; a part opened twice or never closed is an error."""
    out, name, lines, errors = {}, None, [], []
    for number, line in enumerate(open(path, encoding="utf-8").read().split("\n"), 1):
        start, end = START.match(line), END.match(line)
        if start:
            if name:
                errors.append(f"{path}:{number}: part {start.group(1)} opens inside part {name}")
            name, lines = start.group(1), []
            if name in out:
                errors.append(f"{path}:{number}: part {name} appears twice")
        elif end:
            if not name:
                errors.append(f"{path}:{number}: [guide] closes no part")
            else:
                out[name] = textwrap.dedent("\n".join(lines)).strip("\n")
                name = None
        elif name:
            lines.append(line)
    if name:
        errors.append(f"{path}: part {name} is never closed")
    return out, errors


def blocks(path):
    """(line, language, marker or None, text) of every fenced block of a markdown file."""
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if not fence:
            i += 1
            continue
        j = i + 1
        while j < len(lines) and not lines[j].startswith("```"):
            j += 1
        previous = next((lines[k] for k in range(i - 1, -1, -1) if lines[k].strip()), "")
        marker = MARKER.search(previous)
        yield i + 1, fence.group(1), marker, "\n".join(lines[i + 1:j]).strip("\n")
        i = j + 1


def update(path, known):
    """Rewrites the marked blocks of one guide page with their parts."""
    lines = open(path, encoding="utf-8").read().split("\n")
    out, i = [], 0
    while i < len(lines):
        out.append(lines[i])
        marker = MARKER.search(lines[i])
        if marker and i + 1 < len(lines) and FENCE.match(lines[i + 1]):
            j = i + 2
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            key = (marker.group(1), marker.group(2))
            body = known[key].split("\n") if key in known else lines[i + 2:j]
            out += [lines[i + 1]] + body + [lines[j] if j < len(lines) else "```"]
            i = j + 1
            continue
        i += 1
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out))


def main():
    root = sys.argv[1]
    updating = sys.argv[2:] == ["--update"]
    guide = os.path.join(root, "docs", "guide")
    examples = os.path.join(root, "examples", "guide")
    errors, shown, known = [], set(), {}
    for name in sorted(os.listdir(examples)):
        if name.endswith((".cpp", ".hpp", ".py", ".sh")):
            found, problems = parts(os.path.join(examples, name))
            errors += problems
            for part, text in found.items():
                known[(f"examples/guide/{name}", part)] = text
    count = 0
    for name in sorted(os.listdir(guide)):
        if not name.endswith(".md"):
            continue
        path = os.path.join(guide, name)
        if updating:
            update(path, known)
        for line, language, marker, text in blocks(path):
            where = f"docs/guide/{name}:{line}"
            if not marker:
                if language in CODE_LANGUAGES:
                    errors.append(f"{where}: a {language} block without <!-- example: FILE#PART --> before it")
                continue
            key = (marker.group(1), marker.group(2))
            if key not in known:
                errors.append(f"{where}: {key[0]}#{key[1]}: no such part")
                continue
            count += 1
            shown.add(key)
            if text != known[key]:
                errors.append(f"{where}: differs from {key[0]}#{key[1]}; copy the part again")
    for key in sorted(set(known) - shown):
        errors.append(f"{key[0]}#{key[1]}: a part the guide does not show")
    if errors:
        print("the guide and its examples disagree:\n  " + "\n  ".join(errors))
        return 1
    print(f"{count} blocks of the guide equal their examples' parts")
    return 0


if __name__ == "__main__":
    sys.exit(main())
