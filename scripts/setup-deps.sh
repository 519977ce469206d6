#!/usr/bin/env bash
# Installs the Debian 12 packages mdbrief needs to build, test, train and plot.
# Idempotent: packages already present are skipped by apt-get. Runs as root or via sudo.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git ccache
  libopencv-dev opencv-doc
  libeigen3-dev libtbb-dev libcli11-dev libhdf5-dev
  libgtest-dev libbenchmark-dev
  libyaml-cpp-dev nlohmann-json3-dev zlib1g-dev libopengv-dev libhwy-dev
  python3-opencv python3-numpy python3-matplotlib python3-h5py
  pybind11-dev python3-dev python3-pytest
  clang
  g++-aarch64-linux-gnu qemu-user-static
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "setup-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
# opencv-doc ships the sample photos compressed in some releases; the trainer wants plain files.
DOCDATA=/usr/share/doc/opencv-doc/examples/data
if [ -d "$DOCDATA" ] && compgen -G "$DOCDATA/*.gz" >/dev/null; then
  $SUDO gunzip -f "$DOCDATA"/*.gz || true
fi
