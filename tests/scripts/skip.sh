# Sourced by the test scripts: what a test does when a component it needs is missing here.
# Where CROWD_REQUIRE=all (CI, which promises every component) that is a failure naming it;
# elsewhere the test is skipped, saying why: ctest counts exit 77 as skipped (SKIP_RETURN_CODE)
# and ./run test lists each skip's "SKIP:" line after the summary.

# skip REASON: the test cannot run at all.
skip() {
  if [ "${CROWD_REQUIRE:-}" = all ]; then
    echo "FAIL: CROWD_REQUIRE=all, but $*" >&2
    exit 1
  fi
  echo "SKIP: $*"
  exit 77
}

# skip_part REASON: one check cannot run; the rest go on and end_skipped_parts, last, makes the
# test a skip rather than a pass.
skipped_parts=
skip_part() {
  if [ "${CROWD_REQUIRE:-}" = all ]; then
    echo "FAIL: CROWD_REQUIRE=all, but $*" >&2
    exit 1
  fi
  echo "SKIP: $*"
  skipped_parts+="$*; "
}
end_skipped_parts() {
  [ -z "$skipped_parts" ] || exit 77
}

# need_node_tools ROOT PACKAGE...: node and each npm package, which ./run test installs into
# ROOT/.tools; sets tools to that node_modules folder.
need_node_tools() {
  local root=$1 package
  shift
  tools=$root/.tools/node_modules
  command -v node >/dev/null || skip "node is not installed (./run test installs it)"
  for package in "$@"; do
    [ -d "$tools/$package" ] || skip "$package is not installed in $tools (./run test installs it)"
  done
}
