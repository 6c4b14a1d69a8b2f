#!/usr/bin/env bash
# farm_scale.sh BIN WORK N...: cold and warm library builds of N distinct characters
# (farm_library.py) on this machine's cores: jobs a second, peak memory of the build process and
# of its largest job, cache and report bytes, the warm no-op build's time, and the report page's
# time to write and to load in chromium headless. One table row per N; the rates are compared
# with the first N's.
set -euo pipefail
bin=$(realpath "$1") work=$2; shift 2
here=$(dirname "$(realpath "$0")")
mkdir -p "$work" && cd "$work"
[ -d samples ] || "$bin/crowdbake" samples --no-cloth --out samples >/dev/null
browser=$(command -v chromium || command -v chromium-browser || true)
now() { date +%s.%N; }
chrome() { timeout 300 "$browser" --headless --no-sandbox --disable-gpu \
  --user-data-dir="$work/profile" --dump-dom "file://$1" >/dev/null 2>&1 || true; }
if [ -n "$browser" ]; then # chromium's own start, to read the page loads against
  echo '<!doctype html><title>blank</title>' > blank.html
  chrome "$work/blank.html"; t=$(now); chrome "$work/blank.html"
  echo "chromium headless, a blank page: $(python3 -c "print(f'{$(now) - $t:.2f}')") s"
fi
printf '%6s %6s %8s %8s %9s %9s %10s %10s %8s %8s %8s\n' N jobs cold_s jobs/s build_MiB job_MiB \
  cache_MiB report_MB warm_s page_s load_s
for n in "$@"; do
  rm -rf "lib$n" && python3 "$here/farm_library.py" "$n" "lib$n" samples
  t0=$(now); "$bin/crowdbake" build "lib$n/library.json" -o "lib$n/out" -q || true; t1=$(now)
  cp "lib$n/out/build.report.json" "lib$n/cold.report.json"
  "$bin/crowdbake" build "lib$n/library.json" -o "lib$n/out" -q || true; t2=$(now)
  "$bin/crowdbake" report "lib$n/out" -o "lib$n/report.html"; t3=$(now)
  load=-
  if [ -n "$browser" ]; then
    chrome "$work/lib$n/report.html"
    load=$(python3 -c "print(f'{$(now) - $t3:.2f}')")
  fi
  python3 - "lib$n/cold.report.json" "$n" "$t0" "$t1" "$t2" "$t3" "$load" <<'PY'
import json, os, subprocess, sys
path, n, t0, t1, t2, t3, load = sys.argv[1], int(sys.argv[2]), *map(float, sys.argv[3:7]), sys.argv[7]
r = json.load(open(path))
jobs = r['jobs']['run']
cache = int(subprocess.check_output(['du', '-sb', os.path.join(os.path.dirname(path), 'out', '.cache')]).split()[0])
m = r.get('peak_memory_mib', {})
print('%6d %6d %8.1f %8.2f %9s %9s %10.1f %10.2f %8.2f %8.2f %8s' % (
    n, jobs, t1 - t0, jobs / (t1 - t0), m.get('build', '-'), m.get('largest_job', '-'),
    cache / 2**20, os.path.getsize(path) / 1e6, t2 - t1, t3 - t2, load))
PY
done
