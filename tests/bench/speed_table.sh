#!/usr/bin/env bash
# Bake speed per character and per job of the demo library: this crowdbake
# against a baseline crowdbake (the previous release) in the same run, each building the library
# cold (its own empty cache), one after the other on the same machine. Per job: seconds for both,
# the ratio, the input size and this build's throughput. Writes OUT/speed_table.csv.
# Usage: tests/bench/speed_table.sh BASELINE_CROWDBAKE [OUT] [JOBS]   (after ./run demo, which
#   writes out/library.json). A baseline from an earlier commit:
#   git worktree add /tmp/base REV && cmake -S /tmp/base -B /tmp/base/build -G Ninja \
#     -DCROWD_TESTS=OFF && cmake --build /tmp/base/build --target crowdbake
set -euo pipefail
cd "$(dirname "$0")/../.."
base=$(realpath "$1")
out=${2:-out/bench}/speed
jobs=${3:-0}
[ -f out/library.json ] || { echo "run ./run demo first (it writes out/library.json)" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out"
# As ./run demo: the library names the models of ../shared, so the asset root holds both.
root=$(realpath .)
while [[ "$(realpath ../shared)/" != "${root%/}/"* ]]; do root=$(dirname "$root"); done
for who in baseline this; do
  bin=build/bin/crowdbake; [ $who = baseline ] && bin=$base
  # The manifest names its inputs relative to out/: the build reads them there.
  "$bin" build out/library.json -o "$out/$who" --cache "$out/$who.cache" -j "$jobs" \
    --asset-root "$root" -q
  echo "$who: $("$bin" --version 2>/dev/null | head -1), $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['time_s'])" "$out/$who/build.report.json") s" >&2
done
python3 - "$out" <<'PY'
import csv, json, sys
out = sys.argv[1]
def jobs(who):
    r = json.load(open(f"{out}/{who}/build.report.json"))
    return {j["label"]: j for c in r["characters"] for j in c["jobs"]}, r["time_s"]
base, base_total = jobs("baseline")
this, this_total = jobs("this")
def size(j):  # the job's input, in the unit its throughput is given in
    f = j["figures"]
    if j["kind"] == "mesh":
        return f.get("input_triangles", 0), "triangles"
    if j["kind"] == "impostor":
        a, e = f["views"].split("x")
        return int(a) * int(e) * f["frames"], "views"
    if j["kind"] == "cloth":
        return f["vertices"], "garment vertices"
    return f.get("pack_bytes", 0), "bytes"
rows = []
for label, j in this.items():
    b = base.get(label)
    n, unit = size(j)
    s = j["seconds"]
    rows.append({"job": label, "kind": j["kind"], "input": n, "unit": unit,
                 "baseline_s": round(b["seconds"], 3) if b else "", "this_s": round(s, 3),
                 "speedup": round(b["seconds"] / s, 2) if b and s > 0 else "",
                 "throughput_per_s": round(n / s) if s > 0 else ""})
with open(f"{out}/speed_table.csv", "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
print("| job | kind | input | baseline s | this s | speed-up | throughput /s |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    print(f"| {r['job']} | {r['kind']} | {r['input']} {r['unit']} | {r['baseline_s']} | {r['this_s']} | "
          f"{r['speedup']} | {r['throughput_per_s']} |")
print(f"| whole build (wall) | | | {base_total:.1f} | {this_total:.1f} | {base_total / this_total:.2f} | |")
PY
