#!/usr/bin/env bash
# Animation bake figures per asset: joints, clips, frames, bytes per joint per frame and the
# measured error of each precision (frame and mid-frame times), and bake time.
# Usage: tests/bench/anim_table.sh [OUTDIR]   (after ./run build; writes OUTDIR/anim_table.csv)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-out/bench}
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
  $bin anim "$f" -o "$out/$name.crowdpack" --report "$out/$name.json" --threads 1 --quiet
done
python3 - "$out" "${inputs[@]}" <<'PY'
import json, os, sys
out, inputs = sys.argv[1], sys.argv[2:]
rows = []
print(f"{'asset':<20}{'joints':>7}{'clips':>6}{'frames':>7}{'diag':>8}  {'precision':<9}{'B/j/f':>6}"
      f"{'max@frame':>11}{'mean@frame':>11}{'max@mid':>10}{'mean@mid':>10}{'max@frame mm':>13}{'bake s':>8}")
for f in inputs:
    name = os.path.splitext(os.path.basename(f))[0]
    r = json.load(open(os.path.join(out, name + ".json")))
    frames = sum(c["frames"] for c in r["clips"])
    for p in r["precisions"]:
        cl = p["clips"]
        mx = max(c["max_error_at_frames"] for c in cl)
        mean = sum(c["mean_error_at_frames"] * c["frames"] for c in cl) / frames
        mxm = max(c["max_error_at_midframes"] for c in cl)
        meanm = sum(c["mean_error_at_midframes"] * c["frames"] for c in cl) / frames
        mm = max(c["max_error_at_frames_model_units"] for c in cl) * 1000
        row = [name, r["joints"], len(r["clips"]), frames, r["diagonal"], p["precision"],
               p["bytes_per_joint_per_frame"], mx, mean, mxm, meanm, mm, r["time_s"]["total"]]
        rows.append(row)
        print(f"{name:<20}{r['joints']:>7}{len(r['clips']):>6}{frames:>7}{r['diagonal']:>8.3f}  {p['precision']:<9}"
              f"{p['bytes_per_joint_per_frame']:>6.0f}{mx:>11.2e}{mean:>11.2e}{mxm:>10.2e}{meanm:>10.2e}{mm:>13.4f}"
              f"{r['time_s']['total']:>8.3f}")
with open(os.path.join(out, "anim_table.csv"), "w") as fh:
    fh.write("asset,joints,clips,frames,diagonal,precision,bytes_per_joint_per_frame,max_error_at_frames,"
             "mean_error_at_frames,max_error_at_midframes,mean_error_at_midframes,max_error_at_frames_model_units_x1000,bake_time_s\n")
    for row in rows: fh.write(",".join(str(x) for x in row) + "\n")
print("errors are fractions of the rest-pose bounding-box diagonal; 'mm' assumes model units are metres")
PY
