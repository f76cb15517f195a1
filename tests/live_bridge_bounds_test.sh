#!/usr/bin/env bash
# live_bridge under hostile clients on 127.0.0.1 (bash's /dev/tcp, no other client needed):
#  1. 120 websocket clients one after the other, each sending the header of a 16 MB frame and
#     1 kB of it, and holding the connection: 32 are served and cut off at the header (a page's
#     message is at most 4 kB), the others refused, and the bridge's peak resident memory stays
#     under 100 MB; once they close, a page is served again;
#  2. 40 pages at once: 32 are served, the others refused with 503; once they leave, a page is
#     served again;
#  3. out of file descriptors (the bridge runs with 48), it says so once, waits instead of
#     spinning, and serves a page again once the connections that took them are gone;
#  4. SIGTERM stops it cleanly (status 0), with pages connected, cut off and refused.
# Usage: tests/live_bridge_bounds_test.sh   (RBCP_BUILD_DIR: the build, default build/)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${RBCP_BUILD_DIR:-$root/build}/bin"
case "${1:-}" in
  -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  "") ;;
  *) echo "live_bridge_bounds_test: takes no arguments, got '$1'" >&2; exit 2 ;;
esac
out="$(mktemp -d)"; echo "live_bridge_bounds_test: logs in $out"
bridge=""
cleanup() { [ -z "$bridge" ] || kill "$bridge" 2>/dev/null || true; wait 2>/dev/null || true; [ -n "${RBCP_KEEP:-}" ] || rm -rf "$out"; }
trap cleanup EXIT
fail() { echo "live_bridge_bounds_test: FAILED: $*" >&2; [ ! -f "$out/bridge.log" ] || tail -5 "$out/bridge.log" >&2; exit 1; }

# The bridge, limited to 48 file descriptors, on any free port. Its log exists before it starts:
# the background shell may open it after the first look for the port (set -e ends the test on a
# sed of a missing file).
: >"$out/bridge.log"
bash -c "ulimit -n 48; exec '$bin/live_bridge' --port 0 --lcm-url memq://" 2>"$out/bridge.log" &
bridge=$!
port=""
for _ in $(seq 1 100); do
  port="$(sed -n 's/.*listening on http:\/\/127.0.0.1:\([0-9]*\)\/.*/\1/p' "$out/bridge.log")"
  [ -z "$port" ] || break
  sleep 0.1
done
[ -n "$port" ] || fail "live_bridge did not start"

upgrade=$'GET /ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n'
# open_page: connects a page and asks for the websocket; sets fd (the connection) and code (the
# answer's status: 101 served, 503 refused, empty when none came).
open_page() {
  local line="" status=""
  code="" fd=""
  exec {fd}<>"/dev/tcp/127.0.0.1/$port" || return 0
  printf '%s' "$upgrade" >&"$fd" 2>/dev/null || return 0
  IFS= read -r -t 5 -u "$fd" line || true
  read -r _ status _ <<<"$line" || true
  code="$status"
}
peak_kb() { awk '/^VmHWM:/ {print $2}' "/proc/$bridge/status"; }

# 1. Frames claiming 16 MB: a masked text frame header with a 64-bit length of 2^24, a mask, 1 kB.
# (printf's format writes the NUL bytes a shell string cannot hold.)
big_frame_header='\x81\xff\x00\x00\x00\x00\x01\x00\x00\x00\x11\x22\x33\x44'
payload="$(head -c 1024 /dev/zero | tr '\0' 'x')"
served=0
for i in $(seq 1 120); do
  open_page
  case "$code" in
    101) served=$((served + 1)) ;;
    503) ;;  # 32 pages at once at most; a page cut off holds its place until it closes (or 30 s)
    *) fail "client $i: expected 101 or 503, got '$code'" ;;
  esac
  # shellcheck disable=SC2059  # the header is the format: its escapes are the bytes
  printf "$big_frame_header%s" "$payload" >&"$fd" 2>/dev/null || true
  eval "fds_$i=$fd"
done
sleep 0.5
kb="$(peak_kb)"
echo "live_bridge_bounds_test: 120 clients sent 16 MB frame headers ($served served); the bridge's peak resident memory: $((kb / 1024)) MB"
[ "$served" -eq 32 ] || fail "$served pages served at once, expected 32"
[ "$kb" -lt 102400 ] || fail "peak resident memory $((kb / 1024)) MB, expected under 100 MB"
for i in $(seq 1 120); do eval "exec {fds_$i}>&-"; done
sleep 0.3
open_page; exec {fd}>&-
[ "$code" = "101" ] || fail "after the large frames, a page got '$code', expected 101"

# 2. 40 pages at once: 32 served, 8 refused.
served=0 refused=0
for i in $(seq 1 40); do
  open_page
  eval "pages_$i=$fd"
  case "$code" in 101) served=$((served + 1)) ;; 503) refused=$((refused + 1)) ;; *) fail "page $i got '$code'" ;; esac
done
echo "live_bridge_bounds_test: 40 pages at once: $served served, $refused refused"
[ "$served" -eq 32 ] && [ "$refused" -eq 8 ] || fail "expected 32 served and 8 refused"
for i in $(seq 1 40); do eval "exec {pages_$i}>&-"; done
sleep 0.3
open_page; exec {fd}>&-
[ "$code" = "101" ] || fail "after the pages left, a page got '$code', expected 101"

# 3. 60 connections that say nothing take the bridge's descriptors.
for i in $(seq 1 60); do exec {c}<>"/dev/tcp/127.0.0.1/$port"; eval "idle_$i=$c"; done
for _ in $(seq 1 50); do grep -q "cannot accept a connection" "$out/bridge.log" && break; sleep 0.1; done
grep -q "cannot accept a connection (.*): waiting" "$out/bridge.log" || fail "the bridge did not say it was out of descriptors"
said="$(grep -c "cannot accept a connection" "$out/bridge.log")"
[ "$said" -eq 1 ] || fail "said $said times that it cannot accept, expected once"
for i in $(seq 1 60); do eval "exec {idle_$i}>&-"; done
code=""
for _ in $(seq 1 50); do
  open_page 2>/dev/null
  [ -z "$fd" ] || exec {fd}>&-
  [ "$code" != "101" ] || break
  sleep 0.2
done
[ "$code" = "101" ] || fail "once the idle connections closed, a page got '$code', expected 101"
kill -0 "$bridge" 2>/dev/null || fail "the bridge died"
echo "live_bridge_bounds_test: out of descriptors the bridge waited and served again"
# It stops cleanly with every kind of connection open: pages, pages cut off, a page refused.
for i in $(seq 1 33); do
  open_page
  # shellcheck disable=SC2059
  [ $((i % 2)) -eq 0 ] || printf "$big_frame_header%s" "$payload" >&"$fd" 2>/dev/null || true
  eval "last_$i=$fd"
done
[ "$code" = "503" ] || fail "page 33 got '$code', expected 503"
sleep 0.3
kill -TERM "$bridge"
rc=0
wait "$bridge" || rc=$?
bridge=""
[ "$rc" -eq 0 ] || fail "the bridge exited with status $rc on SIGTERM"
echo "live_bridge_bounds_test: passed"
