#!/usr/bin/env bash
# Animation bake speed against a baseline in the same run: `crowdbake anim` of this build and of
# a baseline crowdbake, alternating for ROUNDS rounds (who goes first swaps each round), on the
# models of lod_assets.sh and, where Blender is installed, many_clips.glb (a 23k-triangle biped
# with 24 clips, made by tests/data/blender/make_characters.py: the error budget's search over
# rates and precisions dominates it). Per model: the median over the rounds of this build's
# seconds over the baseline's, the fastest of each, and whether the two packs and reports (less
# their times and names) are the same. Writes OUT/anim_speed.csv.
# Usage: tests/bench/anim_speed.sh BASELINE_CROWDBAKE [OUT] [ROUNDS]   (ROUNDS: 3 unless given;
#   a baseline from an earlier commit: git worktree add /tmp/base REV && cmake -S /tmp/base \
#     -B /tmp/base/build -G Ninja -DCROWD_TESTS=OFF && cmake --build /tmp/base/build --target crowdbake)
set -euo pipefail
cd "$(dirname "$0")/../.."
base=$(realpath "$1")
out=${2:-out/bench}
rounds=${3:-3}
[ -x build/bin/crowdbake ] || { echo "build/bin/crowdbake is missing: ./run build" >&2; exit 1; }
source tests/bench/lod_assets.sh "$out"
if command -v blender >/dev/null; then
  CROWD_BLENDER_OUT=$(realpath "$out") blender -b --factory-startup \
    --python tests/data/blender/make_characters.py -- many_clips > "$out/many_clips.log" 2>&1
  assets+=("$out/many_clips.glb")
else
  echo "note: blender is not installed: no many_clips.glb" >&2
fi
work=$out/anim_speed
rm -rf "$work" && mkdir -p "$work"
for r in $(seq "$rounds"); do
  order="this baseline"; [ $((r % 2)) = 0 ] && order="baseline this"
  for who in $order; do
    bin=build/bin/crowdbake; [ $who = baseline ] && bin=$base
    for a in "${assets[@]}"; do
      name=$(basename "${a%.*}")
      start=$EPOCHREALTIME
      "$bin" anim "$a" -o "$work/$name.$who.crowdpack" --report "$work/$name.$who.json" -q
      echo "$name,$who,$r,$start,$EPOCHREALTIME" >> "$work/times.csv"
    done
  done
  echo "round $r of $rounds" >&2
done
python3 - "$out" "$work" "${assets[@]}" <<'PY'
import csv, filecmp, json, os, statistics, sys
out, work, assets = sys.argv[1], sys.argv[2], sys.argv[3:]
times = {}
for name, who, r, start, end in csv.reader(open(f"{work}/times.csv")):
    times.setdefault((name, who), {})[r] = float(end) - float(start)
def plain(x):  # a report less its times and file names
    if isinstance(x, dict):
        return {k: plain(v) for k, v in x.items() if not k.endswith("_s") and k != "output"}
    return [plain(v) for v in x] if isinstance(x, list) else x
rows = []
for a in assets:
    name = os.path.splitext(os.path.basename(a))[0]
    this, base = times[(name, "this")], times[(name, "baseline")]
    same = filecmp.cmp(f"{work}/{name}.this.crowdpack", f"{work}/{name}.baseline.crowdpack",
                       shallow=False) and plain(json.load(open(f"{work}/{name}.this.json"))) == \
        plain(json.load(open(f"{work}/{name}.baseline.json")))
    rows.append({"asset": name, "ratio": round(statistics.median(this[r] / base[r] for r in this), 3),
                 "this_s": round(min(this.values()), 3), "baseline_s": round(min(base.values()), 3),
                 "same_pack_and_report": same})
with open(f"{out}/anim_speed.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
print(f"this / baseline, median of the rounds (fastest seconds of each in brackets)")
for r in rows:
    print(f"{r['asset']:22} {r['ratio']:.3f} ({r['baseline_s']:.2f} -> {r['this_s']:.2f})"
          f"  {'same pack and report' if r['same_pack_and_report'] else 'DIFFERENT'}")
PY
