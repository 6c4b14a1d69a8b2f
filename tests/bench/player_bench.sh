#!/usr/bin/env bash
# Player benchmark: the sample humanoid at 1k, 5k, 10k and 30k instances along the demo scene's
# camera path, instanced against naive (one draw per instance per sub-mesh) in the same binary
# and the same run. Prints a table and writes OUT/player_bench.csv.
# Usage: tests/bench/player_bench.sh [OUT] [FRAMES] [SIZE]   (after ./run demo, which bakes out/)
# crowdplay --headless needs no display where EGL offers a device (a GPU's driver, Mesa); else
# it runs under tests/scripts/xvfb.sh.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
frames=${2:-4}
size=${3:-640x360} # llvmpipe's fill cost stays small
mkdir -p "$out"
[ -f out/humanoid.crowdpack ] || { echo "run ./run demo first (it bakes out/humanoid.crowdpack)" >&2; exit 1; }
display=()
command -v Xvfb >/dev/null && display=(tests/scripts/xvfb.sh)
csv=$out/player_bench.csv
echo "instances,path,frames,frame_ms,gpu_ms,draw_calls,triangles,renderer" > "$csv"
for n in 1000 5000 10000 30000; do
  for path in instanced naive; do
    flag=""; [ $path = naive ] && flag=--naive
    stats=$out/stats_${n}_$path.json
    # 2 s steps walk the 8 s camera path.
    "${display[@]}" build/bin/crowdplay samples/scenes/demo.json --headless --frames "$frames" \
      --step 2 --size "$size" --instances $n $flag --stats "$stats" >/dev/null
    python3 - "$stats" $n $path >> "$csv" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["summary"]
print(",".join([sys.argv[2], sys.argv[3], str(s["frames"]), f'{s["frame_ms"]:.1f}',
                f'{s["gpu_ms"]:.1f}', f'{s["draw_calls"]:.0f}', f'{s["triangles"]:.0f}',
                json.dumps(s["renderer"])]))
PY
  done
done
python3 tests/bench/table.py "$csv"
python3 - "$csv" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))[1:]
for n in ["1000", "5000", "10000", "30000"]:
    i = next(r for r in rows if r[0] == n and r[1] == "instanced")
    v = next(r for r in rows if r[0] == n and r[1] == "naive")
    print(f"{n}: naive/instanced draw calls {float(v[5]) / float(i[5]):.0f}x, frame time "
          f"{float(v[3]) / float(i[3]):.2f}x, gpu time {float(v[4]) / float(i[4]):.2f}x")
PY
