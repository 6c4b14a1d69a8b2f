#!/usr/bin/env bash
# The SDK as a studio gets it: `cmake --install` into a prefix whose path holds a space, nothing
# under it naming the build tree; the installed tools run from the prefix; examples/ copied out of
# the source tree and built against the prefix alone (CMake package; read_pack also through
# pkg-config), then run: read_pack prints a baked pack (and refuses one newer than it, naming the
# chunk), draw_crowd draws a crowd of it in its own EGL context and writes a PNG. Then formats/ alone (-DCROWD_FORMATS_ONLY=ON) configured where no
# package, header or library can be found, built, installed, and read_pack built against it.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
build=$(realpath "$1") root=$(realpath "$2") work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
prefix="$work/pre fix"

cmake --install "$build" --prefix "$prefix" >install.log
if grep -rlF -e "$build/" -e "$root/" "$prefix"; then fail "installed files name the source or build tree"; fi
"$prefix/bin/crowdbake" --version | grep -q "chunks read" || fail "crowdbake --version"
"$prefix/bin/crowdplay" --version | grep -q "^crowdplay " || fail "crowdplay --version"
"$prefix/bin/crowdbake" samples --no-cloth --out s >/dev/null
"$prefix/bin/crowdbake" lod s/humanoid.glb -o h.crowdpack -q
# export writes images through the module the installed tools find under <libdir>/crowdbake.
"$prefix/bin/crowdbake" export h.crowdpack --images textures >/dev/null
ls textures/*.png >/dev/null || fail "installed crowdbake export wrote no image"

cp -r "$root/examples" src
cmake -S src -B ex -DCMAKE_PREFIX_PATH="$prefix" >ex.log
cmake --build ex >>ex.log 2>&1 || { cat ex.log; fail "examples did not build against the prefix"; }
for tree in "$root/formats/include" "$root/runtime/include" "$build/generated" "$build/bin"; do
  if grep -rlF "$tree" ex; then fail "the examples' build names $tree"; fi
done
ex/read_pack h.crowdpack | tee read.txt
grep -q "^joints: " read.txt && grep -q "^clips: 3" read.txt || fail "read_pack"
if ex/draw_crowd h.crowdpack crowd.png 2>err.txt | tee draw.txt; then
  covered=$(sed -n 's/.*, \([0-9]*\) of \([0-9]*\) pixels covered/\1/p' draw.txt)
  [ "${covered:-0}" -gt 5000 ] || fail "draw_crowd covered ${covered:-no} pixels"
  [ -s crowd.png ] || fail "draw_crowd wrote no PNG"
elif grep -q "no EGL device" err.txt; then
  skip_part "draw_crowd: $(cat err.txt)"
else
  fail "draw_crowd: $(cat err.txt)"
fi
# A pack newer than the installed reader: its SKEL chunk at version 99 (the table's checksum
# made right again), refused naming the chunk and the versions this reader knows.
python3 - h.crowdpack newer.crowdpack <<'PY'
import struct, sys, zlib
b = bytearray(open(sys.argv[1], 'rb').read())
count = struct.unpack_from('<I', b, 12)[0]
for i in range(count):
    at = 32 + 32 * i
    if b[at:at + 4] == b'SKEL':
        struct.pack_into('<I', b, at + 4, 99)
struct.pack_into('<I', b, 24, zlib.crc32(bytes(b[32:32 + 32 * count])))
open(sys.argv[2], 'wb').write(b)
PY
if ex/read_pack newer.crowdpack 2>err.txt; then fail "read_pack read a pack with SKEL version 99"; fi
grep -q "chunk SKEL: chunk version 99 is not supported (this build reads 1..1)" err.txt ||
  fail "read_pack on a newer pack: $(cat err.txt)"
echo "ok: $(cat err.txt)"
# pkg-config (its flags do not survive a space in a path: a prefix without one).
cmake --install "$build" --prefix "$work/pc" >/dev/null
PKG_CONFIG_PATH="$work/pc/lib/pkgconfig" g++ -std=c++20 src/read_pack/read_pack.cpp -o read_pc \
  $(PKG_CONFIG_PATH="$work/pc/lib/pkgconfig" pkg-config --cflags --libs crowdbake-formats)
./read_pc h.crowdpack | grep -q "^joints: " || fail "read_pack built through pkg-config"
PKG_CONFIG_PATH="$work/pc/lib/pkgconfig" pkg-config --exists crowdbake-runtime || fail "crowdbake-runtime.pc"

# formats/ alone: every package, header and library search looks under an empty root, so any
# dependency would fail to configure (programs, the compiler and make, are found as usual).
nothing="$work/nothing" && mkdir -p "$nothing"
cmake -S "$root" -B fo -DCROWD_FORMATS_ONLY=ON -DCMAKE_FIND_ROOT_PATH="$nothing" \
  -DCMAKE_FIND_ROOT_PATH_MODE_PACKAGE=ONLY -DCMAKE_FIND_ROOT_PATH_MODE_INCLUDE=ONLY --no-warn-unused-cli \
  -DCMAKE_FIND_ROOT_PATH_MODE_LIBRARY=ONLY >fo.log
cmake --build fo -j2 >>fo.log 2>&1 || { cat fo.log; fail "the formats-only build"; }
cmake --install fo --prefix "$work/fo prefix" >/dev/null
[ ! -e "$work/fo prefix/bin" ] || fail "the formats-only install holds programs"
cmake -S src -B fo_ex -DCMAKE_PREFIX_PATH="$work/fo prefix" >fo_ex.log
cmake --build fo_ex >>fo_ex.log 2>&1 || { cat fo_ex.log; fail "read_pack against formats alone"; }
[ ! -e fo_ex/draw_crowd ] || fail "draw_crowd built without crowd::runtime"
fo_ex/read_pack h.crowdpack | grep -q "^joints: " || fail "read_pack against formats alone"
echo "sdk: installed, examples built and run against '$prefix'; formats alone built"
end_skipped_parts
