#!/usr/bin/env bash
# Installs exactly the Debian 12 packages OCG-SLAM needs to build, test and run.
# Idempotent: does nothing (and needs no privileges) when everything is present.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libopencv-dev        # OpenCV 4.6: images, FAST/BRIEF, RANSAC helpers
  libeigen3-dev        # Eigen 3.4: all linear algebra
  libceres-dev         # Ceres 2.1: all optimization
  libyaml-cpp-dev      # settings files
  libosmesa6-dev       # off-screen OpenGL rendering
  libgtest-dev libgmock-dev
  libbenchmark-dev
  nlohmann-json3-dev
  libcereal-dev        # map files (docs/sessions.md): binary archives, header-only
  libcli11-dev
  libspdlog-dev libfmt-dev
  clang libclang-rt-14-dev  # libFuzzer and the sanitizers of tools/fuzz.sh
  python3-dev pybind11-dev python3-pybind11  # the Python module ocg (docs/python.md)
  python3-numpy python3-pytest               # its arrays and its tests
  python3-matplotlib   # ocg_eval ate --plot and the batch's plots
  snakemake            # tools/ocg_batch (docs/batch.md)
)

missing=()
for package in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install_deps: installing ${#missing[@]} missing package(s): ${missing[*]}"

if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  SUDO=(sudo -n)
else
  echo "install_deps: need root to install packages. Run as root, or give this user" >&2
  echo "password-less sudo, or install these yourself and rerun:" >&2
  echo "  sudo apt-get install ${missing[*]}" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
# A fresh machine has no package lists: refresh them before installing.
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/tmp/ocg-install-deps.log 2>&1 || {
  echo "install_deps: apt-get install failed; last lines of /tmp/ocg-install-deps.log:" >&2
  tail -n 20 /tmp/ocg-install-deps.log >&2
  exit 1
}
echo "install_deps: done"
