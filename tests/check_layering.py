#!/usr/bin/python3
"""Checks that includes between the project's folders point one way (README, "Where things
are"): a file may include from its own folder and from folders below it, never from above.
Inside the runtime library the parts do the same (PART below). bench/ and tests/ are included by
nothing outside them. Exit 1 with the offending lines."""
import pathlib
import re
import sys

# Lower number = lower layer. Folders on one level do not include each other.
LAYER = {
    "patterns": 0,
    "mdbrief": 1,  # libmdbrief/include/mdbrief and libmdbrief/internal/mdbrief
    "toolkit": 2,
    "scenes": 2,
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
    "scenes": "scenes",
    "patchextract": "patchextract",
    "trainer": "trainer",
    "vocabulary": "vocabulary",
    "eval": "eval",
    "cli": "cli",
}
# Consumers above every library: they may include any of them, but not bench/ or tests/.
TOP = ("python", "fuzz", "examples", "bench", "tests")
# The runtime library's parts, lowest first; a part includes only its own and lower parts. A
# file's part is its folder under include/mdbrief/, internal/mdbrief/internal/ or src/; the one
# header at the top of include/mdbrief/ is the umbrella (mdbrief.hpp), above every part.
PART_LAYER = {"base": 0, "camera": 1, "detect": 2, "geometry": 2, "describe": 3, "match": 3, "recognition": 4,
              "api": 5, "umbrella": 6}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SOURCES = ("*.cpp", "*.hpp", "*.h", "*.in")


def library_part(relative: str) -> str:
    """The part of libmdbrief a file (libmdbrief/src/..., libmdbrief/include/mdbrief/...) or an
    include ("mdbrief/...", or a path under src/) belongs to: the folder it sits in; None for a
    file in no part's folder."""
    umbrella = False
    for prefix in ("libmdbrief/include/mdbrief/", "libmdbrief/internal/mdbrief/internal/", "libmdbrief/src/",
                   "mdbrief/internal/", "mdbrief/"):
        if relative.startswith(prefix):
            relative = relative[len(prefix):]
            umbrella = prefix in ("libmdbrief/include/mdbrief/", "mdbrief/")
            break
    folder, _, rest = relative.partition("/")
    if not rest:
        return "umbrella" if umbrella else None
    return folder if folder in PART_LAYER else None


def library_problems(root: pathlib.Path):
    lib = root / "libmdbrief"
    for pattern in SOURCES:
        for path in sorted(lib.rglob(pattern)):
            relative = str(path.relative_to(root))
            own = library_part(relative)
            if own is None:
                yield f"{relative}: in no part's folder of the library (PART_LAYER)"
                continue
            text = path.read_text(errors="replace")
            for m in INCLUDE.finditer(text):
                target = m.group(1)
                if target.startswith("patterns/"):
                    continue
                if not target.startswith("mdbrief/") and not (lib / "src" / target).exists():
                    continue
                part = library_part(target)
                line = text.count("\n", 0, m.start()) + 1
                if part is None:
                    yield f"{relative}:{line}: includes \"{target}\", in no part of the library"
                elif part != own and PART_LAYER[part] >= PART_LAYER[own]:
                    yield f"{relative}:{line}: includes \"{target}\": {part} is not below {own}"


def problems(root: pathlib.Path):
    yield from library_problems(root)
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
