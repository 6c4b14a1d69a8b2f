#!/usr/bin/env bash
# crowdbake's allocator settings (malloc_tuning.h): a bake started without glibc.malloc.hugetlb
# in GLIBC_TUNABLES runs itself again with it set (glibc's loader starts the program twice, in
# one process), also where the variable sets other tunables; where the user set it, once. The
# quick commands start once. The packs do not depend on it.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
starts() { # how many times glibc's loader starts crowdbake ${@:2}, with GLIBC_TUNABLES=$1
  env GLIBC_TUNABLES="$1" LD_DEBUG=libs "$bin/crowdbake" "${@:2}" 2>&1 >/dev/null |
    grep -c 'initialize program' || true
}
# ldd's whole output first: grep -q stopping early would fail the pipe (pipefail) by SIGPIPE.
libraries=$(ldd "$bin/crowdbake")
grep -q 'libc\.so\.6' <<< "$libraries" || skip "crowdbake is not linked to glibc"
for bake in build anim lod outfits impostor cloth terrain; do
  [ "$(starts '' $bake --help)" = 2 ] || fail "$bake not started again to set glibc.malloc.hugetlb"
done
[ "$(starts glibc.malloc.mmap_threshold=65536 lod --help)" = 2 ] ||
  fail "not started again with other tunables set"
[ "$(starts glibc.malloc.hugetlb=0 lod --help)" = 1 ] ||
  fail "started again though the user set glibc.malloc.hugetlb"
[ "$(starts glibc.malloc.mmap_threshold=65536:glibc.malloc.hugetlb=0 lod --help)" = 1 ] ||
  fail "started again though the user set glibc.malloc.hugetlb among others"
for quick in --version inspect verify diff pose export report; do
  [ "$(starts '' $quick --help)" = 1 ] || fail "$quick started twice"
done

"$bin/crowdbake" samples --no-cloth --out s >/dev/null
"$bin/crowdbake" lod s/humanoid.glb --fps 30 --precision qts -q -o huge.crowdpack
GLIBC_TUNABLES=glibc.malloc.hugetlb=0 "$bin/crowdbake" lod s/humanoid.glb --fps 30 \
  --precision qts -q -o small.crowdpack
cmp huge.crowdpack small.crowdpack || fail "the pack differs with and without huge pages"
echo "allocator: ok"
