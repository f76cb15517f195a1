#!/usr/bin/env bash
# Every script in tools/ answers --help (exit 0, text on stdout) without building or running
# anything, and exits 2 on a bad argument, also before building anything. Every built program
# answers --help, exits 2 on a bad argument, and either takes --lcm-url or says that it talks no
# LCM.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
failed=0
scripts=()
for f in "$root"/tools/* "$root"/tools/viewer/*; do
  [ -f "$f" ] && [ -x "$f" ] && scripts+=("$f")
done
for f in "${scripts[@]}"; do
  name="${f#"$root"/}"
  # An empty build folder: a script that built anything would leave something in it.
  empty="$(mktemp -d)"
  rc=0; out="$(RBCP_BUILD_DIR="$empty" timeout 20 "$f" --help 2>/dev/null)" || rc=$?
  if [ $rc -ne 0 ] || [ -z "$out" ]; then echo "FAILED: $name --help exited $rc (output: ${#out} bytes)"; failed=$((failed + 1)); fi
  rc=0; RBCP_BUILD_DIR="$empty" timeout 20 "$f" --no-such-option >/dev/null 2>&1 || rc=$?
  if [ $rc -ne 2 ]; then echo "FAILED: $name --no-such-option exited $rc, expected 2"; failed=$((failed + 1)); fi
  if [ -n "$(ls -A "$empty")" ]; then echo "FAILED: $name wrote into the build folder: $(ls -A "$empty" | head -3 | tr '\n' ' ')"; failed=$((failed + 1)); fi
  rm -rf "$empty"
done
programs=0
for f in "${RBCP_BUILD_DIR:-$root/build}"/bin/*; do
  name="$(basename "$f")"
  case "$name" in *_bench) [ "$name" = sim_bench ] || continue ;; esac  # Google Benchmark's own help
  programs=$((programs + 1))
  rc=0; out="$("$f" --help 2>&1)" || rc=$?
  if [ $rc -ne 0 ]; then echo "FAILED: $name --help exited $rc"; failed=$((failed + 1)); continue; fi
  rc=0; "$f" --no-such-option >/dev/null 2>&1 || rc=$?
  if [ $rc -ne 2 ]; then echo "FAILED: $name --no-such-option exited $rc, expected 2"; failed=$((failed + 1)); fi
  if ! grep -q -- "--lcm-url" <<<"$out" && ! grep -qi "talks no LCM" <<<"$out"; then
    echo "FAILED: $name --help neither offers --lcm-url nor says that it talks no LCM"; failed=$((failed + 1))
  fi
done
echo "tools_help_test: ${#scripts[@]} scripts, $programs programs, $failed failures"
[ $failed -eq 0 ]
