#!/usr/bin/env bash
# Skinning from compressed joint tracks against the animation texture, in one run: the sample
# humanoid baked with --store both in samples/scenes/crowd10k.json at 10k and
# 30k walkers, crowdplay --skinning texture and --skinning tracks alternating, ROUNDS rounds,
# drawn as the scene is (hybrid: the far ones impostors, not skinned) and as geometry only
# (--geometry: every visible walker skinned; PATHS=hybrid leaves it out). INSTANCES="10000"
# leaves out 30k (on llvmpipe a geometry frame of 10k takes about 40 s on 2 cores).
# The tracks run once per palette slot of SLOTS (default "0 clip": every instance's exact time,
# then each clip's sample step). Prints per size, path and slot the frame and GPU times
# (medians), the instances drawn as geometry, the palettes decoded a frame and their share of
# those, and the palette pass's GPU and CPU times; writes OUT/palette_bench.csv.
# Usage: tests/bench/palette_bench.sh [OUT] [FRAMES] [ROUNDS] [SIZE]   (after ./run demo)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
frames=${2:-4}
rounds=${3:-2}
size=${4:-640x360}
paths=${PATHS:-hybrid geometry}
sizes=${INSTANCES:-10000 30000}
slots=${SLOTS:-0 clip} # the tracks' palette slots (crowdplay --palette-slot): 0, exact times
mkdir -p "$out"
[ -f out/samples/humanoid.glb ] && [ -f out/humanoid_walk.impostor.crowdpack ] ||
  { echo "run ./run demo first (it writes out/samples and the walk impostor)" >&2; exit 1; }
display=()
command -v Xvfb >/dev/null && display=(tests/scripts/xvfb.sh)
pack=$out/humanoid_tracks.crowdpack
build/bin/crowdbake lod out/samples/humanoid.glb --store both -o "$pack" --quiet
scene=$out/palette_bench_scene.json
python3 - samples/scenes/crowd10k.json "$scene" "$(realpath "$pack")" \
  "$(realpath out/humanoid_walk.impostor.crowdpack)" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["packs"][0]["path"], s["packs"][0]["impostor"] = sys.argv[3], sys.argv[4]
json.dump(s, open(sys.argv[2], "w"), indent=1)
PY
csv=$out/palette_bench.csv
echo "instances,path,skinning,slot,round,frame_ms,gpu_ms,geometry,palettes,palette_gpu_ms,palette_cpu_ms" \
  > "$csv"
for round in $(seq "$rounds"); do
  for path in $paths; do
    flag=(); [ "$path" = geometry ] && flag=(--geometry)
    for n in $sizes; do
      for run in texture:- $(for s in $slots; do echo "tracks:$s"; done); do
        skinning=${run%%:*} slot=${run#*:}
        slotFlag=(); [ "$slot" != - ] && slotFlag=(--palette-slot "$slot")
        stats=$out/palette_${path}_${n}_${skinning}_${slot}_$round.json
        "${display[@]}" build/bin/crowdplay "$scene" --headless --frames "$frames" --step 2 \
          --size "$size" --instances $n --skinning $skinning "${flag[@]}" "${slotFlag[@]}" \
          --stats "$stats" >/dev/null
        python3 - "$stats" $n "$path" $skinning "$slot" "$round" >> "$csv" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["summary"]
print(",".join(sys.argv[2:7] + [f'{s["frame_ms"]:.2f}', f'{s["gpu_ms"]:.2f}',
      f'{s["visible"] - s["impostors"]:.1f}', f'{s.get("palettes", 0):.1f}',
      f'{s.get("palette_gpu_ms", 0):.3f}', f'{s.get("palette_cpu_ms", 0):.3f}']))
PY
      done
    done
  done
done
python3 - "$csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(f"{'path':>8} {'instances':>9} {'skinning':>8} {'slot':>5} {'frame ms':>9} {'gpu ms':>8} "
      f"{'geometry':>8} {'palettes':>8} {'share':>6} {'pass gpu ms':>11} {'pass cpu ms':>11} "
      f"{'frame vs texture':>16}")
for path in dict.fromkeys(r["path"] for r in rows):
    for n in dict.fromkeys(r["instances"] for r in rows):
        pick = lambda k, slot: [r for r in rows if r["path"] == path and r["instances"] == n
                                and r["skinning"] == k and r["slot"] == slot]
        med = lambda k, slot, col: statistics.median(float(r[col]) for r in pick(k, slot))
        base = med("texture", "-", "frame_ms")
        for k, slot in dict.fromkeys((r["skinning"], r["slot"]) for r in rows):
            f, g, pg = med(k, slot, "frame_ms"), med(k, slot, "gpu_ms"), med(k, slot, "palette_gpu_ms")
            geo, pal = med(k, slot, "geometry"), med(k, slot, "palettes")
            print(f"{path:>8} {n:>9} {k:>8} {slot:>5} {f:9.1f} {g:8.1f} {geo:8.0f} {pal:8.0f} "
                  f"{(pal / geo if geo and k == 'tracks' else 0):6.3f} {pg:11.2f} "
                  f"{med(k, slot, 'palette_cpu_ms'):11.2f} {f / base:16.3f}")
PY
