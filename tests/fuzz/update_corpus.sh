#!/usr/bin/env bash
# Refreshes the committed fuzz corpus, tests/fuzz/corpus/TARGET, from what `./run fuzz` kept in
# build-fuzz/corpus/TARGET: libFuzzer's merge keeps the inputs that add coverage beyond this
# checkout's seeds (build-fuzz/seeds, made fresh by each run, so never committed), up to 16 KiB
# each. Run after `./run fuzz`, look at the counts, then commit the folder.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -d build-fuzz/seeds ] || { echo "update_corpus: run ./run fuzz first" >&2; exit 1; }
for entry in pack_reader:packs:1048576 gltf_import:gltf:262144 point_cache:caches:65536 \
  pack_consumer:packs:1048576 manifest:manifests:65536 scene:scenes:65536; do
  IFS=: read -r target seeds max_len <<< "$entry"
  work=$(mktemp -d)
  cp "build-fuzz/seeds/$seeds"/* "$work/" # first: only what adds to the seeds' coverage is kept
  LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp "build-fuzz/${target}_fuzz" -merge=1 \
    -max_len="$max_len" -rss_limit_mb=2048 "$work" "tests/fuzz/corpus/$target" \
    "build-fuzz/corpus/$target" > "build-fuzz/merge_$target.log" 2>&1
  rm -rf "tests/fuzz/corpus/$target" && mkdir -p "tests/fuzz/corpus/$target"
  for f in "$work"/*; do
    [ -e "build-fuzz/seeds/$seeds/$(basename "$f")" ] && continue
    [ "$(stat -c %s "$f")" -le 16384 ] && cp "$f" "tests/fuzz/corpus/$target/"
  done
  rm -rf "$work"
  echo "$target: $(find "tests/fuzz/corpus/$target" -type f | wc -l) inputs," \
    "$(du -sb "tests/fuzz/corpus/$target" | cut -f1) bytes"
done
