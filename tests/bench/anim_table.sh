#!/usr/bin/env bash
# Animation bake figures per clip of each asset: first what the error budget chose (rate,
# precision, bytes per joint per frame, the largest error at any time in millimetres at a 1.8 m
# character), then every precision at those rates (frame times, mid-frames and 64 seeded random
# times), then every option the budget tried, charted as error against bytes per clip (SVG).
# Usage: tests/bench/anim_table.sh [OUTDIR] [FPS|source|auto] [BUDGET_MM]
#   (after ./run build; writes OUTDIR/anim_choice.csv, anim_table.csv, anim_options.csv and
#   anim_options_ASSET_CLIP.svg; FPS and BUDGET default to the bake's defaults)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
fps=(${2:+--fps "$2"} ${3:+--error-budget "$3"})
mkdir -p "$out"
bin=build/bin/crowdbake
$bin samples --no-cloth --out "$out/samples" >/dev/null
inputs=("$out/samples/humanoid.glb")
for m in CesiumMan Fox RiggedFigure RecursiveSkeletons RiggedSimple SimpleSkin AnimatedMorphCube; do
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
def table(cols, rows, path):
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for row in rows:
        print("| " + " | ".join(f"{x:.3f}" if isinstance(x, float) else str(x) for x in row) + " |")
    with open(os.path.join(out, path), "w") as fh:
        fh.write(",".join(cols) + "\n")
        for row in rows: fh.write(",".join(str(x) for x in row) + "\n")

choice, options = [], []
for f in inputs:
    name = os.path.splitext(os.path.basename(f))[0]
    r = json.load(open(os.path.join(out, name + ".json")))
    for c in r["clips"]:
        choice.append([name, c["name"], c["frames"], round(c.get("source_fps", 0), 3),
                       round(c["fps"], 3), r["precision"], r["bytes_per_joint_per_frame"],
                       c["max_error_any_time_mm"], r["budget_met"], r["time_s"]])
        for o in c.get("options_tried", []):
            options.append([name, c["name"], o["precision"], round(o["fps"], 3), o["frames"],
                            o["bytes"], o["max_error_any_time_mm"], o["meets_budget"],
                            o["precision"] == r["precision"] and abs(o["fps"] - c["fps"]) < 1e-3])
print("The budget's choice (error budget %s mm)" % r["error_budget_mm"])
table(["asset", "clip", "frames", "source_fps", "fps", "precision", "bytes_per_joint_per_frame",
       "max_error_any_time_mm", "budget_met", "bake_time_s"], choice, "anim_choice.csv")
mean = sum(row[6] * row[2] for row in choice) / sum(row[2] for row in choice)
print("mean bytes per joint per frame over every clip's frames: %.1f; worst error at any time: "
      "%.3f mm" % (mean, max(row[7] for row in choice)))
ocols = ["asset", "clip", "precision", "fps", "frames", "bytes", "max_error_any_time_mm",
         "meets_budget", "chosen"]
with open(os.path.join(out, "anim_options.csv"), "w") as fh:
    fh.write(",".join(ocols) + "\n")
    for row in options: fh.write(",".join(str(x) for x in row) + "\n")
print("\nEvery precision at the chosen rates")
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
table(cols, rows, "anim_table.csv")
print("mm: the character scaled to 1.8 m tall (its rest height; flat assets: its diagonal)")
PY
# Error against bytes of every option tried, one chart per clip, a line per precision.
command -v node >/dev/null || { echo "node not found: no charts"; exit 0; }
tail -n +2 "$out/anim_options.csv" | cut -d, -f1,2 | sort -u | while IFS=, read -r asset clip; do
  svg="$out/anim_options_${asset}_${clip//[^A-Za-z0-9_-]/_}.svg"
  node tests/bench/chart.js "$svg" "$asset $clip: error against bytes, every option tried" \
    "texture bytes (log)" "max error at any time (mm at 1.8 m)" \
    <(awk -F, -v a="$asset" -v c="$clip" 'NR == 1 || ($1 == a && $2 == c)' "$out/anim_options.csv") \
    bytes max_error_any_time_mm precision log
  echo "chart: $svg"
done
