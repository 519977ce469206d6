#!/usr/bin/env bash
# The whole test suite (library, tools and their tests) under AddressSanitizer + UBSan, with
# leak detection on and every report fatal: the second step of .ci/run. The one suppression (fuzz/lsan.supp) is a leak inside libhdf5.
# Usage: scripts/test-sanitizers.sh [build-dir]   (default: build-asan). About 13 minutes on
# 2 cores: 10 of build, 3 of tests.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build-asan}
bash scripts/setup-deps.sh
# -O1 and line tables only (-g1), as the sanitizers' documentation advises: the reports keep their
# files and lines, and the build takes half the compiler time of -O2 -g (17.9 against 34.7
# CPU-minutes; 9.8 minutes on 2 cores) for the same test time (163 s).
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMDBRIEF_SANITIZE=ON -DMDBRIEF_BUILD_BENCH=OFF \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
cmake --build "$BUILD_DIR" -j"$(nproc)"
# allocator_may_return_null: a request no machine can serve (libhdf5 asks for 2^54 bytes on a
# damaged file, fuzz/regressions/patch_set/crash-a71af91d...) fails as glibc's malloc fails it,
# with NULL, which the caller checks; ASan's default is to abort instead.
# max_allocation_size_mb: libhdf5 also asks for what a damaged object header claims, 4 GiB for
# fuzz/regressions/patch_set/oom-1c797357; the release build gets untouched virtual memory and
# fails cleanly (exit 2 in 0.14 s, 56 MB resident), but ASan would poison 512 MB of shadow for
# it (7 s). Such requests fail with NULL too; no test needs 2 GiB in one allocation.
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=1:allocator_may_return_null=1:max_allocation_size_mb=2048
export LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# cv::ORB probes OpenCL, which dlopens the ICD loader (libOpenCL.so.1); LeakSanitizer then reads
# a bogus dynamic-TLS range of it and crashes at exit ("Tracer caught signal 11", DTLS at
# 0x1fb3), after the test itself passed (DescriptorSupport.OrbAndModOrb..., every run on an AMD
# EPYC Zen 5). No test uses OpenCL.
export OPENCV_OPENCL_RUNTIME=disabled
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)"
