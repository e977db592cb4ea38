# shellcheck shell=bash
# Sourced by the end-to-end tests of the CLI (cli_test.sh, views_test.sh): a scratch folder
# $work removed at exit, quiet progress, and the two checks they share.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export SHADOWBENCH_QUIET=1
fail() { echo "FAIL: $*" >&2; exit 1; }
# refused TEXT COMMAND…: exit status 2 and one line on stderr that contains TEXT.
refused() {
  local text=$1 rc
  shift
  set +e
  "$@" > /dev/null 2> "$work/err.txt"; rc=$?
  set -e
  [ $rc -eq 2 ] && [ "$(wc -l < "$work/err.txt")" -eq 1 ] && grep -qF -- "$text" "$work/err.txt" ||
    fail "'$*': rc $rc, expected 2 and '$text', got: $(cat "$work/err.txt")"
}
