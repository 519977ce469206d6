#!/usr/bin/env bash
# Packaging checks (README "Build and install"), run by CI after the test suite:
#  1. the .deb CPack makes of BUILD_DIR (library, tools, Python module; under /usr) is unpacked with dpkg -x
#     into a scratch root (no root rights, the machine's packages untouched): its mdbrief tool
#     converts an installed example camera, and /usr/bin/python3 imports its module and loads it;
#  2. a library-only build with -DBUILD_SHARED_LIBS=ON is installed, and the test consumer
#     (tests/consumer) is built against libmdbrief.so with find_package and with pkg-config alone
#     (which names only libmdbrief and the OpenCV modules it uses), and run;
#  3. CMake's project version, the .deb's, pkg-config's and Python's __version__ agree.
# Usage: scripts/test-packages.sh BUILD_DIR [SHARED_BUILD_DIR]   (default: BUILD_DIR-shared)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=$(realpath "$1")
SHARED_DIR=$(realpath -m "${2:-$1-shared}")
SCRATCH=$(mktemp -d)
trap 'rm -rf "$SCRATCH"' EXIT

# 1. The .deb.
(cd "$BUILD_DIR" && cpack -G DEB -B "$SCRATCH/deb" >/dev/null)
deb=$(ls "$SCRATCH"/deb/*.deb)
dpkg-deb --field "$deb" Package Version Depends
# Debian's layout whatever the build's prefix: everything under /usr, the module where
# /usr/bin/python3 looks for /usr's packages.
outside=$(dpkg -c "$deb" | awk '{print $6}' | grep -v '^\./usr/' | grep -v '^\./$' || true)
[ -z "$outside" ] || { echo "the .deb installs outside /usr: $outside" >&2; exit 1; }
dpkg -x "$deb" "$SCRATCH/root"
python_dir=lib/python3/dist-packages
root="$SCRATCH/root/usr"
camera="$root/share/mdbrief/cameras/lafida_fisheye0.yaml"
"$root/bin/mdbrief" camera convert "$camera" -o "$SCRATCH/camera.yaml"
env -i PATH=/usr/bin:/bin PYTHONPATH="$root/$python_dir" /usr/bin/python3 -c "
import sys, mdbrief
assert mdbrief.__file__.startswith('$root'), mdbrief.__file__
camera = mdbrief.load_camera(sys.argv[1])
assert camera.to_yaml() == open(sys.argv[2]).read()
print('deb: import mdbrief from', mdbrief.__file__, '->', camera)" "$camera" "$SCRATCH/camera.yaml"

# 2. The shared library.
cmake -S . -B "$SHARED_DIR" -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON -DMDBRIEF_BUILD_TOOLS=OFF \
  -DMDBRIEF_BUILD_TESTS=OFF -DMDBRIEF_BUILD_BENCH=OFF >/dev/null
cmake --build "$SHARED_DIR" -j"$(nproc)"
cmake --install "$SHARED_DIR" --component library --prefix "$SCRATCH/shared" >/dev/null
lib=$(find "$SCRATCH/shared" -name 'libmdbrief.so*' -type f)
test -n "$lib"
export LD_LIBRARY_PATH=$(dirname "$lib")
cmake -S tests/consumer -B "$SCRATCH/consumer" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$SCRATCH/shared" >/dev/null
cmake --build "$SCRATCH/consumer" >/dev/null
ldd "$SCRATCH/consumer/consumer" | grep "libmdbrief\.so" >/dev/null || { echo "the consumer did not link libmdbrief.so" >&2; exit 1; }
"$SCRATCH/consumer/consumer" "$SCRATCH/shared/share/mdbrief/cameras/lafida_fisheye0.yaml"
pc_flags=$(PKG_CONFIG_PATH=$(dirname "$lib")/pkgconfig pkg-config --cflags --libs mdbrief)
echo "pkg-config --cflags --libs mdbrief: $pc_flags"
# The shared library's consumers link the OpenCV modules the library uses, and none of its
# private dependencies (OpenGV above all, whose development package they need not have).
extra_libs=$(tr ' ' '\n' <<<"$pc_flags" | grep '^-l' |
  grep -v -x -e -lmdbrief -e -lopencv_core -e -lopencv_imgproc -e -lopencv_features2d -e -lopencv_calib3d || true)
[ -z "$extra_libs" ] || { echo "pkg-config --libs mdbrief names more than it should:" $extra_libs >&2; exit 1; }
c++ -std=c++17 -O1 tests/consumer/main.cpp -o "$SCRATCH/pc_consumer" $pc_flags
"$SCRATCH/pc_consumer"
# 3. One version everywhere: CMake's project version, the .deb's, pkg-config's and Python's.
project_version=$(sed -n 's/^project(mdbrief VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
deb_version=$(dpkg-deb --field "$deb" Version)
pc_version=$(PKG_CONFIG_PATH=$(dirname "$lib")/pkgconfig pkg-config --modversion mdbrief)
python_version=$(env -i PATH=/usr/bin:/bin PYTHONPATH="$root/$python_dir" /usr/bin/python3 -c "import mdbrief; print(mdbrief.__version__)")
echo "versions: CMake $project_version, .deb $deb_version, pkg-config $pc_version, Python $python_version"
[ -n "$project_version" ] && [ "${deb_version%%-*}" = "$project_version" ] && [ "$pc_version" = "$project_version" ] &&
  [ "$python_version" = "$project_version" ] || { echo "the versions disagree" >&2; exit 1; }
echo "packages: .deb imports, shared library consumers build and run, one version"
