# Helpers for the end-to-end shell tests; source after setting WORK (a scratch folder).
# They count into passed and failed; end the test with report_and_exit.
passed=0
failed=0

check() {  # check "description" command...
  local description=$1
  shift
  if "$@" >"$WORK/out" 2>&1; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAILED: $description"
    sed 's/^/    /' "$WORK/out"
  fi
}
fails_with() {  # fails_with "description" "expected text" command...
  local description=$1 expected=$2
  shift 2
  if "$@" >"$WORK/out" 2>&1; then
    failed=$((failed + 1)); echo "FAILED: $description (exit code 0)"
  elif ! grep -qF -- "$expected" "$WORK/out"; then
    failed=$((failed + 1)); echo "FAILED: $description (no '$expected' in:)"; sed 's/^/    /' "$WORK/out"
  else
    passed=$((passed + 1))
  fi
}
report_and_exit() {
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
  exit
}
