#!/usr/bin/python3
"""Checks that includes between the project's folders point one way (README, "Where things
are"): a file may include from its own folder and from folders below it, never from above.
bench/ and tests/ are included by nothing outside them. Exit 1 with the offending lines."""
import pathlib
import re
import sys

# Lower number = lower layer. Folders on one level do not include each other.
LAYER = {
    "patterns": 0,
    "mdbrief": 1,  # libmdbrief/include/mdbrief and libmdbrief/internal/mdbrief
    "toolkit": 2,
    "patchextract": 3,
    "trainer": 4,
    "vocabulary": 4,
    "eval": 5,  # trains the vocabularies it compares
    "cli": 6,
}
# Where each source folder sits; its files may include what lies strictly below, plus itself.
FOLDER = {
    "patterns": "patterns",
    "libmdbrief": "mdbrief",
    "toolkit": "toolkit",
    "patchextract": "patchextract",
    "trainer": "trainer",
    "vocabulary": "vocabulary",
    "eval": "eval",
    "cli": "cli",
}
# Consumers above every library: they may include any of them, but not bench/ or tests/.
TOP = ("python", "fuzz", "examples", "bench", "tests")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SOURCES = ("*.cpp", "*.hpp", "*.h", "*.in")


def problems(root: pathlib.Path):
    for top in list(FOLDER) + list(TOP):
        for pattern in SOURCES:
            for path in sorted((root / top).rglob(pattern)):
                text = path.read_text(errors="replace")
                for m in INCLUDE.finditer(text):
                    target = m.group(1)
                    first = target.split("/")[0]
                    line = text.count("\n", 0, m.start()) + 1
                    where = f"{path.relative_to(root)}:{line}: includes \"{target}\""
                    if first in ("bench", "tests") and top != first:
                        yield f"{where}: {first}/ is private to itself"
                    if target == "test_data.hpp" and top != "tests":
                        yield f"{where}: tests/ is private to itself"
                    if top in TOP or first not in LAYER:
                        continue
                    own = FOLDER[top]
                    if first != own and LAYER[first] >= LAYER[own]:
                        yield f"{where}: {first}/ is not below {top}/"


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    found = list(problems(root))
    for p in found:
        print(p)
    print(f"check_layering: {len(found)} include(s) against the layering")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
