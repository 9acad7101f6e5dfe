#!/usr/bin/env bash
# Checks the project's bash scripts for two faults that pass on a quiet machine and fail
# at random on a loaded one, or not at all until the day they do:
#   - a syntax error (bash -n);
#   - under `set -o pipefail`, a pipe into a reader that stops early: head, `grep -q`,
#     `grep -m N`, `sed Nq`. When it exits before the writer has written its last block,
#     the writer dies of SIGPIPE (exit 141), pipefail makes that the pipe's status, and
#     `set -e` ends the script without a word. Read the whole input instead (awk, `sed -n`,
#     grep -m on a file, a here-string) or add `|| true` where a failure does not
#     matter.
# Usage: tools/check_scripts.sh [FILE...]   (default: every *.sh under tools/, tests/,
#        bench/ and python/, and .ci/run). Prints FILE:LINE: TEXT for each finding; exit
#        code 1 if there is any, 0 if none, 2 for a file that does not exist.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
case "${1:-}" in
  -h | --help)
    sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    exit 0 ;;
esac

files=("$@")
if [ ${#files[@]} -eq 0 ]; then
  while IFS= read -r -d '' file; do files+=("$file"); done < <(
    find "$ROOT/tools" "$ROOT/tests" "$ROOT/.ci" "$ROOT/bench" "$ROOT/python" \
      \( -name '*.sh' -o -path "$ROOT/.ci/run" \) -type f -print0 2>/dev/null | sort -z)
fi

findings=0
for file in "${files[@]}"; do
  [ -f "$file" ] || { echo "check_scripts: no such file: $file" >&2; exit 2; }
  if ! syntax=$(bash -n "$file" 2>&1); then
    echo "$file: syntax: $syntax"
    findings=$((findings + 1))
  fi
  grep -q 'pipefail' "$file" || continue
  # Comments are dropped (a `#` at the start of a line or after a blank); `||` is not a
  # pipe; a line with `|| true` tolerates the failure; a line that says
  # `# check_scripts: allow` is meant (a test showing the fault).
  while IFS= read -r hit; do
    echo "$file:$hit"
    findings=$((findings + 1))
  done < <(awk '
    {
      if ($0 ~ /# check_scripts: allow/) next
      line = $0
      sub(/(^|[ \t])#.*$/, "", line)
      if (line ~ /\|\|[ \t]*true/) next
      gsub(/\|\|/, "  ", line)
      if (line ~ /\|[ \t]*(head([ \t]|$)|grep[ \t]+(-[a-zA-Z]*[qm]|--quiet|--max-count)|sed[ \t]+(-n[ \t]+)?\047?[0-9]+q)/)
        printf "%d: %s\n", NR, $0
    }' "$file")
done

if [ "$findings" -gt 0 ]; then
  echo "check_scripts: $findings finding(s) in ${#files[@]} script(s)"
  exit 1
fi
echo "check_scripts: ${#files[@]} script(s), no finding"
