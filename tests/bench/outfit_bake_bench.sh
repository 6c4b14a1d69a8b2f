#!/usr/bin/env bash
# The outfit bake's time per sample outfit (crowdbake outfits at default settings: every frame of
# every clip) against a baseline crowdbake, in the same run, alternating: visibility seconds (the
# report's visibility_s), the whole bake's CPU seconds at 1 thread, and wall seconds at THREADS;
# and whether both write the same bytes. Writes OUT/outfit_bake_bench.csv.
# Usage: tests/bench/outfit_bake_bench.sh BASELINE_CROWDBAKE [OUT] [THREADS]   (after ./run build;
#   a baseline: an earlier commit's build/bin/crowdbake, e.g. git worktree add /tmp/base REV,
#   then build it there)
set -euo pipefail
cd "$(dirname "$0")/../.."
base=$(realpath "$1") out=${2:-out/bench} threads=${3:-0}
new=$PWD/build/bin/crowdbake
s=$out/outfit_bake
mkdir -p "$s"
"$new" samples --no-cloth --out "$s" > /dev/null
csv=$out/outfit_bake_bench.csv
echo "outfit,binary,threads,visibility_s,cpu_s,wall_s,same_bytes" > "$csv"
for outfit in dress jumper_skirt shirt_trousers; do
  for run in base new; do
    bin=$base && [ $run = new ] && bin=$new
    for t in 1 "$threads"; do
      read -r wall cpu < <({ /usr/bin/time -f "%e %U %S" "$bin" outfits "$s/humanoid.glb" \
        --outfit "$s/outfit_$outfit.glb" -o "$s/$run.$t.crowdpack" --report "$s/$run.$t.json" \
        --threads "$t" -q 2>&1 >/dev/null; } | tail -n 1 | awk '{print $1, $2 + $3}')
      vis=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['outfits'][0]['visibility_s'])" "$s/$run.$t.json")
      same=$(cmp -s "$s/base.$t.crowdpack" "$s/$run.$t.crowdpack" && echo yes || echo no)
      echo "$outfit,$run,$t,$vis,$cpu,$wall,$same" >> "$csv"
    done
  done
done
python3 tests/bench/table.py "$csv"
python3 - "$csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for o in dict.fromkeys(r["outfit"] for r in rows):
    for t in dict.fromkeys(r["threads"] for r in rows):
        b, n = [next(r for r in rows if r["outfit"] == o and r["threads"] == t and r["binary"] == k)
                for k in ("base", "new")]
        cores = "all cores" if t == "0" else f"{t} thread(s)"
        print(f"{o}, {cores}: visibility {float(b['visibility_s']) / float(n['visibility_s']):.1f}x"
              f" faster, whole bake {float(b['wall_s']) / float(n['wall_s']):.1f}x (wall),"
              f" same bytes: {n['same_bytes']}")
PY
