#!/usr/bin/env bash
# crowdbake's allocator settings (malloc_tuning.h): started without glibc.malloc.hugetlb in
# GLIBC_TUNABLES, it runs itself again with it set (glibc's loader starts the program twice, in
# one process), also where the variable sets other tunables; where the user set it, once. The
# packs do not depend on it.
set -euo pipefail
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
starts() { # how many times glibc's loader starts the program, with GLIBC_TUNABLES=$1
  env GLIBC_TUNABLES="$1" LD_DEBUG=libs "$bin/crowdbake" --version 2>&1 >/dev/null |
    grep -c 'initialize program' || true
}
ldd "$bin/crowdbake" | grep -q 'libc\.so\.6' || { echo "SKIP: crowdbake is not linked to glibc"; exit 0; }
[ "$(starts '')" = 2 ] || fail "not started again to set glibc.malloc.hugetlb"
[ "$(starts glibc.malloc.mmap_threshold=65536)" = 2 ] || fail "not started again with other tunables set"
[ "$(starts glibc.malloc.hugetlb=0)" = 1 ] || fail "started again though the user set glibc.malloc.hugetlb"
[ "$(starts glibc.malloc.mmap_threshold=65536:glibc.malloc.hugetlb=0)" = 1 ] ||
  fail "started again though the user set glibc.malloc.hugetlb among others"

"$bin/crowdbake" samples --no-cloth --out s >/dev/null
"$bin/crowdbake" lod s/humanoid.glb --fps 30 --precision qts -q -o huge.crowdpack
GLIBC_TUNABLES=glibc.malloc.hugetlb=0 "$bin/crowdbake" lod s/humanoid.glb --fps 30 \
  --precision qts -q -o small.crowdpack
cmp huge.crowdpack small.crowdpack || fail "the pack differs with and without huge pages"
echo "allocator: ok"
