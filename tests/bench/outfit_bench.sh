#!/usr/bin/env bash
# Clothed crowds, tagged against naive (the WSCG 2009 clothed-crowds seed reports tagged about
# 20% faster): samples/scenes/clothed10k.json at 1k, 2.5k, 5k and 10k characters, each in one
# of the three sample outfits, drawn tagged (each outfit's visible sub-meshes through per-sub-mesh
# render queues) and naive (--whole-body: the whole body under the garments), geometry only (the
# pack also has walk impostors, which would take the far ones), same binary, same
# run. Frame time, GPU time, triangles and vertex shader invocations (as the driver counts them)
# per frame. Each pair runs REPEATS times, naive and tagged alternating, and the table keeps each
# one's fastest run (llvmpipe on a shared machine is noisy). Writes OUT/outfit_bench.csv.
# Usage: tests/bench/outfit_bench.sh [OUT] [FRAMES] [SIZE] [REPEATS]   (after ./run demo)
# crowdplay --headless needs no display where EGL offers a device (a GPU's driver, Mesa); else
# it runs under tests/scripts/xvfb.sh.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
frames=${2:-4}
size=${3:-640x360}
repeats=${4:-2}
mkdir -p "$out"
[ -f out/library/clothed.crowdpack ] ||
  { echo "run ./run demo first (it builds out/library/clothed.crowdpack)" >&2; exit 1; }
display=()
command -v Xvfb >/dev/null && display=(tests/scripts/xvfb.sh)
csv=$out/outfit_bench.csv
echo "instances,method,run,frames,frame_ms,gpu_ms,cull_select_ms,draw_calls,triangles,vertices" > "$csv"
for n in 1000 2500 5000 10000; do
  for run in $(seq "$repeats"); do for method in naive tagged; do
    flag=""; [ $method = naive ] && flag=--whole-body
    stats=$out/outfit_${n}_$method.json
    "${display[@]}" build/bin/crowdplay samples/scenes/clothed10k.json --headless \
      --frames "$frames" --size "$size" --instances $n $flag --geometry --stats "$stats" >/dev/null
    python3 - "$stats" $n $method $run >> "$csv" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["summary"]
print(",".join(sys.argv[2:5] + [str(s["frames"]), f'{s["frame_ms"]:.1f}', f'{s["gpu_ms"]:.1f}',
                f'{s["cull_select_ms"]:.3f}', f'{s["draw_calls"]:.0f}', f'{s["triangles"]:.0f}',
                f'{s["vertices"]:.0f}' if "vertices" in s else ""]))
PY
  done; done
done
python3 tests/bench/table.py "$csv"
python3 - "$csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
def best(n, m):
    return min((r for r in rows if r["instances"] == n and r["method"] == m),
               key=lambda r: float(r["frame_ms"]))
for n in dict.fromkeys(r["instances"] for r in rows):
    t, v = best(n, "tagged"), best(n, "naive")
    ratio = lambda k: float(t[k]) / float(v[k])
    print(f"{n}: fastest frame ms tagged {t['frame_ms']}, naive {v['frame_ms']}: tagged/naive "
          f"frame time {ratio('frame_ms'):.3f}, gpu time {ratio('gpu_ms'):.3f}, triangles "
          f"{ratio('triangles'):.3f}" + (f", vertices {ratio('vertices'):.3f}" if t["vertices"] else ""))
PY
