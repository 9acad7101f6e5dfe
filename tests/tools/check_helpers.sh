# Helpers for the end-to-end shell checks, sourced by a test script: a work folder
# removed on exit, and counted checks that print what failed. The script ends with
#   echo "$passed passed, $failed failed"; [ "$failed" -eq 0 ]
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
passed=0
failed=0

failure() {  # failure "what": counts it and shows the last output
  failed=$((failed + 1))
  echo "FAILED: $1"
  sed 's/^/    /' "$WORK/out"
}
check() {  # check "description" command...: the command succeeds
  local description=$1
  shift
  if "$@" >"$WORK/out" 2>&1; then passed=$((passed + 1)); else failure "$description"; fi
}
fails_with() {  # fails_with "description" "expected text" command...: fails, saying the text
  local description=$1 expected=$2
  shift 2
  if "$@" >"$WORK/out" 2>&1; then
    failure "$description (exit code 0)"
  elif ! grep -qF -- "$expected" "$WORK/out"; then
    failure "$description (no '$expected' in:)"
  else
    passed=$((passed + 1))
  fi
}
output_has() {  # output_has "description" "text": the last command's output holds the text
  if grep -qF -- "$2" "$WORK/out"; then passed=$((passed + 1)); else failure "$1 (no '$2' in:)"; fi
}
output_lacks() {  # output_lacks "description" "text"
  if grep -qF -- "$2" "$WORK/out"; then failure "$1 ('$2' in:)"; else passed=$((passed + 1)); fi
}
report_and_exit() {  # the closing line, and the exit status: 0 only when nothing failed
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
  exit
}
