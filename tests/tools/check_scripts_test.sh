#!/usr/bin/env bash
# tools/check_scripts.sh: the project's scripts pass it, and it finds each fault it is
# for in a constructed script, naming the file and line. The fault itself is shown
# first: under pipefail, a writer outlived by `head` fails the pipe.
#   check_scripts_test.sh <source dir>
set -uo pipefail
SRC=$1
source "$(dirname "$0")/check_helpers.sh"
CHECK="$SRC/tools/check_scripts.sh"

# The mechanism: seq writes far more than a pipe holds, head takes one line and exits,
# seq dies of SIGPIPE, and pipefail makes the pipe fail (141) though head succeeded.
status=0
bash -c 'set -o pipefail; seq 200000 | head -n 1 >/dev/null' || status=$?  # check_scripts: allow
check "a pipe into head fails under pipefail (exit $status)" test "$status" -eq 141
status=0
bash -c 'set -o pipefail; seq 200000 | awk "NR == 1" >/dev/null' || status=$?
check "a pipe into awk reading all does not (exit $status)" test "$status" -eq 0

check "the project's scripts pass" "$CHECK"

# The constructed script (not *.sh, so that the project's check passes): lines 4-7 are
# faults, lines 3 and 8-10 are not.
cp "$SRC/tests/data/check_scripts/faults.bash" "$WORK/bad.sh"
fails_with "a pipe into head is found" "bad.sh:4:" "$CHECK" "$WORK/bad.sh"
output_has "a pipe into grep -q is found" "bad.sh:5:"
output_has "a pipe into grep -m is found" "bad.sh:6:"
output_has "a pipe into sed 1q is found" "bad.sh:7:"
output_lacks "a comment is not a finding" "bad.sh:3:"
output_lacks "|| is not a pipe" "bad.sh:8:"
output_lacks "awk reads its whole input" "bad.sh:9:"
output_lacks "|| true tolerates the failure" "bad.sh:10:"
output_has "the count is given" "4 finding(s) in 1 script(s)"

# Without pipefail the same pipes are harmless.
grep -v pipefail "$WORK/bad.sh" >"$WORK/plain.sh"
check "without pipefail nothing is found" "$CHECK" "$WORK/plain.sh"

printf '#!/usr/bin/env bash\nif true; then\n  echo unclosed\n' >"$WORK/syntax.sh"
fails_with "a syntax error is found" "syntax.sh: syntax:" "$CHECK" "$WORK/syntax.sh"

status=0
"$CHECK" "$WORK/missing.sh" >"$WORK/out" 2>&1 || status=$?
output_has "a missing file is named" "no such file: $WORK/missing.sh"
check "a missing file is exit code 2 (got $status)" test "$status" -eq 2

report_and_exit
