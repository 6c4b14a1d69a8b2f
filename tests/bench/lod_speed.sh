#!/usr/bin/env bash
# LOD speed against a baseline in the same run: this build's lod_bench and a
# baseline's, both in --times-only mode on the models of lod_assets.sh, alternating for ROUNDS
# rounds (who goes first swaps each round). Per model and figure, the median over the rounds of
# this build's time over the baseline's: on a noisy machine single timings move by 30%, these
# ratios by a few %. meshopt's four calls are the same library in both builds, so their ratio is
# the control: it says how far the machine alone moved the others. Writes OUT/lod_speed.csv.
# Usage: tests/bench/lod_speed.sh BASELINE_LOD_BENCH [OUT] [ROUNDS]   (ROUNDS: 20 unless given;
#   the baseline a lod_bench that has --times-only, from an earlier commit:
#   git worktree add /tmp/base REV && cmake -S /tmp/base -B /tmp/base/build -G Ninja \
#     -DCROWD_TESTS=OFF && cmake --build /tmp/base/build --target lod_bench)
set -euo pipefail
cd "$(dirname "$0")/../.."
base=$(realpath "$1")
out=${2:-out/bench}
rounds=${3:-20}
[ -x build/bin/lod_bench ] || {
  echo "build/bin/lod_bench is missing: apt-get install libmeshoptimizer-dev libcgal-dev, then ./run build" >&2
  exit 1
}
source tests/bench/lod_assets.sh "$out"
rm -rf "$out/lod_speed" && mkdir -p "$out/lod_speed"
for r in $(seq "$rounds"); do
  order="this baseline"; [ $((r % 2)) = 0 ] && order="baseline this"
  for who in $order; do
    bin=build/bin/lod_bench; [ $who = baseline ] && bin=$base
    "$bin" --times-only "$out/lod_speed/$r.$who.csv" "${assets[@]}" 2>/dev/null
  done
  echo "round $r of $rounds" >&2
done
python3 - "$out" "$rounds" <<'PY'
import csv, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
def times(r, who):
    return {row["asset"]: row for row in csv.DictReader(open(f"{out}/lod_speed/{r}.{who}.csv"))}
runs = [(times(r, "this"), times(r, "baseline")) for r in range(1, rounds + 1)]
columns = [("ours_s", "ours"), ("ours_bind_only_s", "bind_only"), ("meshopt_4_calls_s", "meshopt")]
rows = []
for asset, first in runs[0][0].items():
    row = {"asset": asset, "triangles": first["triangles"]}
    for key, name in columns:
        ratios = [float(t[asset][key]) / float(b[asset][key]) for t, b in runs]
        row[f"{name}_ratio"] = round(statistics.median(ratios), 3)
        row[f"{name}_ms"] = round(1e3 * min(float(t[asset][key]) for t, b in runs), 3)
        row[f"{name}_baseline_ms"] = round(1e3 * min(float(b[asset][key]) for t, b in runs), 3)
    row["ours_mtris_per_s"] = round(int(first["triangles"]) / row["ours_ms"] / 1e3, 3)
    rows.append(row)
with open(f"{out}/lod_speed.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
print(f"this / baseline, median of {rounds} rounds (fastest ms of each in brackets); "
      "meshopt is the control")
print(f"{'asset':22} {'triangles':>9} {'ours, 16 poses':>24} {'bind pose only':>24} {'meshopt':>24}")
for r in rows:
    cell = lambda n: f"{r[n + '_ratio']:.3f} ({r[n + '_baseline_ms']:.2f} -> {r[n + '_ms']:.2f})"
    print(f"{r['asset']:22} {r['triangles']:>9} {cell('ours'):>24} {cell('bind_only'):>24} "
          f"{cell('meshopt'):>24}")
PY
