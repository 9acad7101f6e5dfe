#!/usr/bin/env bash
# tools/install_deps.sh waits while another process holds the package manager's lock, and
# gives up with a message naming the holder after OCG_APT_LOCK_WAIT seconds. apt-get,
# dpkg-query and id are stand-ins on PATH (nothing is installed); the lock is a real lock
# file held by a background process, and the stand-in apt-get fails as apt does while it
# cannot take it.
set -euo pipefail
SOURCE_DIR="${1:?usage: install_deps_lock_test.sh SOURCE_DIR}"
command -v flock >/dev/null || { echo "SKIP: needs flock (util-linux)"; exit 0; }
WORK="$(mktemp -d)"
HOLDER=""
# The holders write nothing to the test's output: an orphaned `sleep 30` that held it kept
# ctest waiting for the output to close, 28 of the test's 33 s. The sleep goes with flock.
trap '[ -n "${HOLDER}" ] && { pkill -P "${HOLDER}" || true; kill "${HOLDER}" || true; } 2>/dev/null; rm -rf "${WORK}"' EXIT
mkdir -p "${WORK}/bin"
LOCK="${WORK}/lock-frontend"
touch "${LOCK}"
cat > "${WORK}/bin/apt-get" <<STUB
#!/usr/bin/env bash
echo "apt-get \$*" >> "${WORK}/calls"
if ! flock -n "${LOCK}" true; then
  echo "E: Could not get lock ${LOCK}. It is held by process 4242 (unattended-upgr)" >&2
  echo "E: Unable to acquire the dpkg frontend lock (${LOCK}), is another process using it?" >&2
  exit 100
fi
STUB
printf '#!/bin/sh\nexit 1\n' > "${WORK}/bin/dpkg-query"  # every package missing
printf '#!/bin/sh\necho 0\n' > "${WORK}/bin/id"            # as root
chmod +x "${WORK}/bin/"*
export PATH="${WORK}/bin:${PATH}" OCG_APT_LOCK_POLL=1

fail() { echo "FAIL: $1"; [ -f "$2" ] && cat "$2"; exit 1; }

# 1. The lock is held for 3 s: the script waits, then installs.
flock "${LOCK}" sleep 3 >/dev/null 2>&1 &
HOLDER=$!
sleep 0.3
start=$(date +%s)
OCG_APT_LOCK_WAIT=30 bash "${SOURCE_DIR}/tools/install_deps.sh" > "${WORK}/out1" 2>&1 ||
  fail "install_deps failed while the lock was held for 3 s" "${WORK}/out1"
elapsed=$(( $(date +%s) - start ))
grep -q "waiting for the package manager lock (held by process 4242 (unattended-upgr))" \
  "${WORK}/out1" || fail "no waiting message naming the holder" "${WORK}/out1"
grep -q "install_deps: done" "${WORK}/out1" || fail "did not finish" "${WORK}/out1"
[ "${elapsed}" -ge 2 ] || fail "finished after ${elapsed} s, before the lock was released" /dev/null
grep -q "install -y" "${WORK}/calls" || fail "apt-get install never ran" "${WORK}/calls"
wait "${HOLDER}" || true

# 2. The lock is never released: the script gives up after OCG_APT_LOCK_WAIT, naming it.
flock "${LOCK}" sleep 30 >/dev/null 2>&1 &
HOLDER=$!
sleep 0.3
status=0
OCG_APT_LOCK_WAIT=2 bash "${SOURCE_DIR}/tools/install_deps.sh" > "${WORK}/out2" 2>&1 || status=$?
[ "${status}" -ne 0 ] || fail "succeeded although the lock was held" "${WORK}/out2"
grep -q "still locked after" "${WORK}/out2" || fail "no give-up message" "${WORK}/out2"
grep -q "held by process 4242" "${WORK}/out2" || fail "the holder is not named" "${WORK}/out2"
echo "install_deps lock test: OK (waited ${elapsed} s for a 3 s lock; gave up on a held one)"
