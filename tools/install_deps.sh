#!/usr/bin/env bash
# Installs exactly the Debian 12 packages OCG-SLAM needs to build, test and run.
# Idempotent: does nothing (and needs no privileges) when everything is present.
set -euo pipefail

if [ "${1:-}" = "--help" ] || [ "${1:-}" = "-h" ]; then
  cat <<EOF
usage: tools/install_deps.sh

Installs the Debian 12 packages OCG-SLAM needs (apt-get, as root or with password-less
sudo); does nothing when they are all present. While another process holds the package
manager's lock (a fresh machine's unattended upgrades), it waits up to OCG_APT_LOCK_WAIT
seconds (default 900) instead of failing. The default detector is a separate step:
tools/get_detector.sh (docs/detector.md).
EOF
  exit 0
fi

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
  python3-onnx         # tools/get_detector.sh builds the default detector (docs/detector.md)
)

# A fresh machine often runs unattended-upgrades or cloud-init's apt for minutes after
# boot: apt-get then stops at once with "Could not get lock". Wait for the lock instead,
# up to OCG_APT_LOCK_WAIT seconds (default 900), saying who holds it.
LOCK_WAIT="${OCG_APT_LOCK_WAIT:-900}"
LOCK_POLL="${OCG_APT_LOCK_POLL:-5}"

# Runs apt-get with the given arguments, retrying while another process holds apt's or
# dpkg's lock. Output goes to the log file given first.
apt_get_waiting() {
  local log="$1"; shift
  local waited=0 status
  while true; do
    status=0
    "${SUDO[@]}" apt-get -o DPkg::Lock::Timeout="${LOCK_POLL}" "$@" >"${log}" 2>&1 || status=$?
    if [ "${status}" -eq 0 ]; then return 0; fi
    if ! grep -qiE "could not get lock|unable to lock|unable to acquire the dpkg frontend lock" "${log}"; then
      return "${status}"
    fi
    if [ "${waited}" -ge "${LOCK_WAIT}" ]; then
      echo "install_deps: the package manager is still locked after ${waited} s:" >&2
      grep -m 2 -iE "lock" "${log}" >&2 || true
      echo "install_deps: wait for that process to finish (or raise OCG_APT_LOCK_WAIT) and rerun" >&2
      return "${status}"
    fi
    if [ $((waited % 30)) -eq 0 ]; then
      holder="$(grep -m 1 -oiE "held by process [0-9]+( \([^)]*\))?" "${log}" || true)"
      echo "install_deps: waiting for the package manager lock${holder:+ (${holder})}, ${waited} s so far"
    fi
    sleep "${LOCK_POLL}"
    waited=$((waited + LOCK_POLL))
  done
}

missing=()
for package in "${PACKAGES[@]}"; do
  # Matched in the shell, not by `| grep -q`, which under pipefail may fail the pipe.
  case "$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)" in
    *"install ok installed"*) ;;
    *) missing+=("$package") ;;
  esac
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
LOG="$(mktemp "${TMPDIR:-/tmp}/ocg-install-deps.XXXXXX.log")"
# A fresh machine has no package lists: refresh them before installing.
apt_get_waiting "${LOG}" update -qq || {
  echo "install_deps: apt-get update failed; last lines of ${LOG}:" >&2
  tail -n 20 "${LOG}" >&2
  exit 1
}
apt_get_waiting "${LOG}" install -y -qq --no-install-recommends "${missing[@]}" || {
  echo "install_deps: apt-get install failed; last lines of ${LOG}:" >&2
  tail -n 20 "${LOG}" >&2
  exit 1
}
echo "install_deps: done"
