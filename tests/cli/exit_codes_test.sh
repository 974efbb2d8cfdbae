#!/usr/bin/env bash
# Runs the real `brisance` binary and checks the exit codes and stderr of DESIGN.md's CLI contract:
# 0 on success, 2 on invalid input with one line on stderr.
set -u
bin="$1"
failures=0
elements="$(dirname "$0")/../../scenes/elements"
expect() {  # expect CODE ARGS...
  local want="$1"; shift
  local err; err=$(mktemp)
  "$bin" "$@" >/dev/null 2>"$err"
  local got=$?
  local lines; lines=$(wc -l <"$err")
  if [ "$got" -ne "$want" ]; then
    echo "FAIL: brisance $* exited $got, expected $want"; cat "$err"; failures=$((failures + 1))
  elif [ "$want" -eq 2 ] && [ "$lines" -ne 1 ]; then
    echo "FAIL: brisance $* printed $lines lines on stderr, expected 1"; cat "$err"; failures=$((failures + 1))
  elif [ "$want" -eq 0 ] && [ -s "$err" ]; then
    echo "FAIL: brisance $* printed on stderr:"; cat "$err"; failures=$((failures + 1))
  fi
  rm -f "$err"
}
expect 0 version
expect 0 help
expect 0 blast --charge-kg 100 --distance-m 15
expect 0 blast --charge-kg 100 --distance-m 15 --json --burst surface --angle-deg 30
expect 0 blast --list-explosives
expect 0 blast --help
expect 2 blast --charge-kg 100
expect 2 blast --charge-kg -3 --distance-m 15
expect 2 blast --charge-kg 100 --distance-m 15 --explosive unobtainium
expect 2 blast --charge-kg 100 --distance-m 15 --bogus
expect 2 blast --charge-kg -1 --distance-m x --burst sea
expect 0 response --element "$elements/rc_wall.json" --charge-kg 100 --distance-m 15
expect 0 response --element "$elements/steel_beam.json" --pulse-peak-kpa 200 --pulse-duration-ms 10 --json
expect 0 pi --element "$elements/rc_wall.json" --ductility 3 --points 5
expect 0 response --help
expect 0 pi --help
expect 2 response --element "$elements/rc_wall.json"
expect 2 response --element /nonexistent.json --charge-kg 1 --distance-m 5
expect 2 response --element "$elements/rc_wall.json" --pulse-peak-kpa 1 --pulse-duration-ms 1e9
expect 2 pi --element "$elements/rc_wall.json" --ductility 0
expect 2 frobnicate
# A number beyond a double's range is invalid input, not an internal error (found by tests/fuzz).
huge=$(mktemp --suffix=.json)
printf '{"charges": [1e400]}' >"$huge"
expect 2 validate "$huge"
rm -f "$huge"
"$bin" >/dev/null 2>&1; code=$?
if [ "$code" -ne 2 ]; then echo "FAIL: no command exited $code, expected 2"; failures=$((failures + 1)); fi
out=$("$bin" blast --charge-kg 100 --distance-m 15 --json)
if ! printf '%s' "$out" | grep -q '"incident_overpressure_kpa"'; then
  echo "FAIL: --json output lacks incident_overpressure_kpa"; failures=$((failures + 1))
fi
echo "$((24 - failures)) passed, $failures failed"
[ "$failures" -eq 0 ]
