#!/usr/bin/env bash
# xvfb.sh COMMAND [ARGS...]: COMMAND under a fresh Xvfb display (640x480x24), its exit code passed
# on. Where it fails (other than 77, ctest's skip), the X server's own log follows on stderr.
# Xvfb picks its display number itself (-displayfd): it takes the first one whose lock it gets
# and says which once it accepts connections. xvfb-run -a picks the number in the shell first,
# and two of them starting at once under ctest -j2 can race for it; twice a player under it
# could not open its display ("X11: Failed to open display :99") with nothing in the server's
# log.
set -uo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
command -v Xvfb >/dev/null || skip "Xvfb is not installed (apt-get install xvfb)"
dir=$(mktemp -d "${TMPDIR:-/tmp}/xvfb.XXXXXX")
server=
cleanup() {
  [ -n "$server" ] && kill "$server" 2>/dev/null && wait "$server" 2>/dev/null
  rm -rf "$dir"
}
trap cleanup EXIT
mkfifo "$dir/display"
Xvfb -displayfd 3 -screen 0 640x480x24 -nolisten tcp -noreset 3>"$dir/display" 2>"$dir/log" &
server=$!
# The number comes once the server is ready; if it dies first, the pipe closes empty.
read -r -t 60 number <"$dir/display" || number=
if [ -z "$number" ]; then
  echo "xvfb.sh: Xvfb did not start; its log:" >&2
  sed 's/^/  Xvfb: /' "$dir/log" >&2
  exit 1
fi
# -noreset: by default the server resets each time its last client leaves, and a client that
# connects during the reset is refused (xorg/xserver issue 1102). Twice a CI run lost
# preview_keys to it: "Failed to open display :0" with -displayfd's number in hand, a client
# already seen to connect, and an empty server log. Where xdotool is installed, a client must
# still connect (up to 10 s) before the command runs; one that never does is said so here.
if command -v xdotool >/dev/null; then
  for _ in $(seq 100); do
    DISPLAY=:$number xdotool getdisplaygeometry >/dev/null 2>&1 && break
    sleep 0.1
  done
  if ! DISPLAY=:$number xdotool getdisplaygeometry >/dev/null 2>&1; then
    echo "xvfb.sh: display :$number accepts no client after 10 s; the X server's log:" >&2
    if [ -s "$dir/log" ]; then sed 's/^/  Xvfb: /' "$dir/log" >&2; else echo "  (empty)" >&2; fi
    exit 1
  fi
fi
DISPLAY=:$number "$@"
rc=$?
if [ "$rc" != 0 ] && [ "$rc" != 77 ]; then
  echo "xvfb.sh: '$1' exited $rc on display :$number; the X server's log:" >&2
  if [ -s "$dir/log" ]; then sed 's/^/  Xvfb: /' "$dir/log" >&2; else echo "  (empty)" >&2; fi
fi
exit "$rc"
