#!/usr/bin/env python3
"""The reproduction scripts (scripts/tracker.sh, reproduce.sh, pipelines.sh) write into a scratch
folder: their plans (--dry-run) write nothing under docs/ by default or with --out; with
--update-docs the scripts that generate sections of docs/RESULTS.md rewrite it (their CSVs and
figures still go to the scratch folder); they refuse an --out inside docs/ or both flags at once
(exit 2). Nothing runs: --dry-run only prints the commands.

Usage: check_reproduction_scripts.py REPOSITORY_ROOT BUILD_DIR"""
import os
import subprocess
import sys
import tempfile

SCRIPTS = ["tracker.sh", "reproduce.sh", "pipelines.sh"]
# The scripts whose --update-docs rewrites generated sections of docs/RESULTS.md.
UPDATES_DOCS = ("tracker.sh", "reproduce.sh")
DOC_OUTPUTS = ("docs/results", "docs/figures", "--md docs/RESULTS.md")


def plan(root, script, *args):
    result = subprocess.run(["bash", os.path.join(root, "scripts", script), *args], cwd=root,
                            capture_output=True, text=True, timeout=120)
    return result.returncode, result.stdout + result.stderr


def main():
    root, build = sys.argv[1], os.path.abspath(sys.argv[2])
    errors = []
    with tempfile.TemporaryDirectory() as scratch:
        for script in SCRIPTS:
            for flags in ([], ["--out", scratch]):
                code, out = plan(root, script, "--dry-run", *flags, build)
                if code != 0:
                    errors.append(f"{script} --dry-run {' '.join(flags)}: exit {code}\n{out}")
                for line in out.splitlines():
                    if line.startswith("+") and any(d in line for d in DOC_OUTPUTS):
                        errors.append(f"{script} {' '.join(flags)}: writes the documents: {line}")
                if flags and scratch not in out:
                    errors.append(f"{script} --out {scratch}: the plan does not write there")
            code, out = plan(root, script, "--dry-run", "--update-docs", build)
            if code != 0 or (script in UPDATES_DOCS) != ("--md docs/RESULTS.md" in out):
                errors.append(f"{script} --update-docs: the plan should {'' if script in UPDATES_DOCS else 'not '}"
                              f"write docs/RESULTS.md (exit {code})\n{out}")
            for line in out.splitlines():
                if line.startswith("+") and "docs/results" in line:
                    errors.append(f"{script} --update-docs: writes CSVs into the source tree: {line}")
            for bad in (["--out", "docs/x"], ["--out", scratch, "--update-docs"], ["--out"]):
                code, out = plan(root, script, "--dry-run", *bad)
                if code != 2:
                    errors.append(f"{script} {' '.join(bad)}: exit {code}, expected 2")
            if os.path.exists(os.path.join(root, "docs", "x")):
                errors.append(f"{script}: created docs/x")
        if os.listdir(scratch):
            errors.append(f"--dry-run wrote into {scratch}: {os.listdir(scratch)}")
    if errors:
        print("\n".join(errors))
        return 1
    print(f"{len(SCRIPTS)} reproduction scripts write docs/ only with --update-docs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
