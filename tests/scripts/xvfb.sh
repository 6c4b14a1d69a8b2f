#!/usr/bin/env bash
# xvfb.sh COMMAND [ARGS...]: COMMAND under a fresh Xvfb display (xvfb-run -a, 640x480x24), its exit
# code passed on. Where it fails (other than 77, ctest's skip), the X server's own log follows
# on stderr: xvfb-run throws it away, and a player that once could not reach its display under
# ctest -j2 ("cannot initialise GLFW") left no cause behind.
set -uo pipefail
log=$(mktemp "${TMPDIR:-/tmp}/xvfb.XXXXXX.log")
trap 'rm -f "$log"' EXIT
xvfb-run -a -e "$log" -s "-screen 0 640x480x24" "$@"
rc=$?
if [ "$rc" != 0 ] && [ "$rc" != 77 ]; then
  if [ -s "$log" ]; then
    echo "xvfb.sh: '$1' exited $rc; the X server's log:" >&2
    sed 's/^/  Xvfb: /' "$log" >&2
  else
    echo "xvfb.sh: '$1' exited $rc; the X server logged nothing" >&2
  fi
fi
exit "$rc"
