#!/bin/bash
# `flexsens study` on a full disk exits 4 and passes nothing off as written (issue 34; the
# reproducer study_disk_full.sh). Needs root to mount a 16 KiB tmpfs, filled before the
# study starts; exits 77 (ctest: skipped) otherwise. A disk filling up half-way through the
# study's writes: tests/test_output_safety.cpp, CheckedWrites.*.
#   bash tests/scripts/study_disk_full.sh <build>/flexsens <checkout>
set -u
FLEXSENS=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
[ "$(id -u)" = 0 ] || { echo "SKIP: needs root to mount a small tmpfs"; exit 77; }
W=$(mktemp -d)
mkdir "$W/m"
if ! mount -t tmpfs -o size=16k tmpfs "$W/m" 2> /dev/null; then
  rmdir "$W/m"; rm -rf "$W"; echo "SKIP: cannot mount a tmpfs here"; exit 77
fi
trap 'umount "$W/m"; rm -rf "$W"' EXIT
dd if=/dev/zero of="$W/m/filler" bs=4k 2> /dev/null  # until the disk is full
"$FLEXSENS" study --quick --out "$W/m/st" --source "$SRC" > "$W/out" 2> "$W/err"
rc=$?
cat "$W/err"
fails=0
check() { if eval "$2"; then echo "ok:   $1"; else echo "FAIL: $1"; fails=$((fails + 1)); fi; }
check "exit 4 (got $rc)" '[ $rc = 4 ]'
check "the reason is named" 'grep -q "No space left on device" "$W/err"'
check "no 'study report written'" '! grep -q "report written" "$W/out"'
check "no study folder, no staging folder left" '[ ! -e "$W/m/st" ] && [ -z "$(ls -A "$W/m" | grep staging)" ]'
[ $fails = 0 ]
