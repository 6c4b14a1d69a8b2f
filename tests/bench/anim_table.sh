#!/usr/bin/env bash
# Animation bake figures per clip of each asset and precision: bytes per joint per frame and the
# error the player shows, led by the largest at any time (frame times, mid-frames and 64 seeded
# random times) in millimetres at a 1.8 m character, and bake time.
# Usage: tests/bench/anim_table.sh [OUTDIR] [FPS|source]
#   (after ./run build; writes OUTDIR/anim_table.csv; FPS defaults to the bake's default)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
fps=(${2:+--fps "$2"})
mkdir -p "$out"
bin=build/bin/crowdbake
$bin samples --out "$out/samples" >/dev/null
inputs=("$out/samples/humanoid.glb")
for m in CesiumMan Fox RiggedFigure RecursiveSkeletons RiggedSimple SimpleSkin; do
  f=$(ls ../shared/assets/gltf/$m/*.gl* 2>/dev/null | head -1 || true)
  [ -n "$f" ] && inputs+=("$f")
done
for f in "${inputs[@]}"; do
  name=$(basename "${f%.*}")
  $bin anim "$f" -o "$out/$name.crowdpack" --report "$out/$name.json" --threads 1 --quiet "${fps[@]}"
done
python3 - "$out" "${inputs[@]}" <<'PY'
import json, os, sys
out, inputs = sys.argv[1], sys.argv[2:]
cols = ["asset", "clip", "frames", "fps", "precision", "bytes_per_joint_per_frame",
        "max_error_any_time_mm", "max_at_frames_mm", "max_at_midframes_mm", "max_at_random_mm",
        "mean_at_random_mm", "bake_time_s"]
rows = []
for f in inputs:
    name = os.path.splitext(os.path.basename(f))[0]
    r = json.load(open(os.path.join(out, name + ".json")))
    mm = r["mm_per_model_unit"]
    fps = {c["name"]: c["fps"] for c in r["clips"]}
    for p in r["precisions"]:
        for c in p["clips"]:
            rows.append([name, c["clip"], c["frames"], round(fps[c["clip"]], 3), p["precision"],
                         p["bytes_per_joint_per_frame"], c["max_error_any_time_mm"],
                         c["max_error_at_frames_model_units"] * mm,
                         c["max_error_at_midframes_model_units"] * mm,
                         c["max_error_at_random_times_model_units"] * mm,
                         c["mean_error_at_random_times_model_units"] * mm, r["time_s"]])
print("| " + " | ".join(cols) + " |")
print("|" + "---|" * len(cols))
for row in rows:
    print("| " + " | ".join(f"{x:.3f}" if isinstance(x, float) else str(x) for x in row) + " |")
with open(os.path.join(out, "anim_table.csv"), "w") as fh:
    fh.write(",".join(cols) + "\n")
    for row in rows: fh.write(",".join(str(x) for x in row) + "\n")
print("mm: the character scaled to 1.8 m tall (its rest height; flat assets: its diagonal)")
PY
