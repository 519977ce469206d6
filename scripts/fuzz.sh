#!/usr/bin/env bash
# Fuzzes every parser of outside input (fuzz/fuzz_targets.hpp) with libFuzzer under ASan + UBSan,
# starting from fuzz/seeds/<target> (plus the calibrations of ../shared/data/fisheye for
# `camera`). A crash, hang or sanitizer report is kept in fuzz/regressions/<target>/, which
# tests/test_fuzz_regressions.cpp replays in every build; the script then exits 1. Prints one
# summary line per target (executions, corpus).
# Usage: scripts/fuzz.sh [long | ci | SECONDS] [BUILD_DIR]   (BUILD_DIR default build-fuzz)
#   long     every parser for 10 minutes (the default)
#   ci       every parser for 60 s with libFuzzer's seed fixed to 1, so a run repeats (CI's step)
#   SECONDS  every parser for that long
# The parsers are the folders of fuzz/seeds (one per target of fuzz/fuzz_targets.cpp; the tests
# check that none is missing); FUZZ_TARGETS="keypoints camera" takes a subset. FUZZ_SEED fixes
# libFuzzer's random seed (unset outside ci: every run explores anew). FUZZ_DRY_RUN=1 prints the
# plan, one "fuzz plan: <target> <seconds> s" line per target, and exits before building.
set -euo pipefail
cd "$(dirname "$0")/.."
MODE=${1:-long}
case "$MODE" in
  long) SECONDS_PER_TARGET=600 ;;
  ci) SECONDS_PER_TARGET=60 && FUZZ_SEED=${FUZZ_SEED:-1} ;;
  *[!0-9]* | '' | 0) echo "fuzz.sh: '$MODE' is neither long, ci nor a positive number of seconds" >&2 && exit 2 ;;
  *) SECONDS_PER_TARGET=$MODE ;;
esac
BUILD_DIR=${2:-build-fuzz}
all_targets=$(cd fuzz/seeds && ls -d -- */ | tr -d /)
targets=(${FUZZ_TARGETS:-$all_targets})
if [ -n "${FUZZ_DRY_RUN:-}" ]; then
  for t in "${targets[@]}"; do echo "fuzz plan: $t ${SECONDS_PER_TARGET} s${FUZZ_SEED:+, seed $FUZZ_SEED}"; done
  exit 0
fi
bash scripts/setup-deps.sh
# -O1 -g1, as for the sanitizer suite (scripts/test-sanitizers.sh): half the build time, and the
# reports keep their lines.
CC=clang CXX=clang++ cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMDBRIEF_BUILD_FUZZERS=ON \
  -DMDBRIEF_SANITIZE=ON -DMDBRIEF_BUILD_TESTS=OFF -DMDBRIEF_BUILD_BENCH=OFF \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" > /dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)" --target "${targets[@]/#/fuzz_}"
DATA=${MDBRIEF_DATA:-../shared/data}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
# The targets' scratch files (fuzz/fuzz_targets.cpp) go under $WORK, so even a run that crashes
# leaves nothing in the machine's temporary directory.
mkdir "$WORK/tmp"
export TMPDIR="$WORK/tmp"
# allocator_may_return_null: a request no machine can serve (libhdf5 asks for 2^54 bytes on a
# damaged file, fuzz/regressions/patch_set/crash-a71af91d...) fails as glibc's malloc fails it,
# with NULL, which the caller checks; ASan's default is to abort instead.
# max_allocation_size_mb: libhdf5 also asks for what a damaged object header claims, 4 GiB for
# fuzz/regressions/patch_set/oom-1c797357; the release build gets untouched virtual memory and
# fails cleanly (exit 2 in 0.14 s, 56 MB resident), but ASan would poison 512 MB of shadow for
# it (7 s). Such requests fail with NULL too; no test needs 2 GiB in one allocation.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:allocator_may_return_null=1:max_allocation_size_mb=2048
export LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# One target a core (FUZZ_JOBS, default nproc): each libFuzzer run is one process, so the same
# seconds per target cost half the time on 2 cores, and a fixed seed still repeats each run.
fuzz_one() {
  local t=$1 corpus="$WORK/$1" log="$WORK/$1.log"
  mkdir -p "$corpus" "fuzz/regressions/$t"
  cp fuzz/seeds/"$t"/* "$corpus"/
  if [ "$t" = camera ] && [ -d "$DATA/fisheye" ]; then
    find "$DATA/fisheye" \( -name '*.yml' -o -name '*.yaml' -o -name 'calib_results.txt' \) -exec cp --backup=numbered {} "$corpus"/ \;
  fi
  local status=0
  "$BUILD_DIR/fuzz/fuzz_$t" "$corpus" -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=4096 \
    -artifact_prefix="fuzz/regressions/$t/" -print_final_stats=1 ${FUZZ_SEED:+-seed=$FUZZ_SEED} > "$log" 2>&1 || status=1
  if [ $status = 1 ]; then
    echo "fuzz: $t: FINDING kept in fuzz/regressions/$t/ ($(grep -m1 -E 'ERROR|runtime error|deadly signal|timeout' "$log"))"
  fi
  local execs
  execs=$(grep -m1 'stat::number_of_executed_units' "$log" | awk '{print $2}')
  echo "fuzz: $t: ${SECONDS_PER_TARGET} s, ${execs:-?} executions, corpus $(ls "$corpus" | wc -l) inputs"
  echo $status > "$WORK/$t.status"
}
jobs_at_once=${FUZZ_JOBS:-$(nproc)}
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_at_once" ]; do wait -n || true; done
  fuzz_one "$t" &
done
wait
found=0
for t in "${targets[@]}"; do
  [ "$(cat "$WORK/$t.status" 2>/dev/null)" = 0 ] || found=1
done
exit $found
