#!/usr/bin/env bash
# The mutation check (not in CI): each mutation of tests/mutation/mutations.txt changes
# one line that carries a central decision, rebuilds BUILD (default build/, configured), runs the
# tests that should catch it and restores the line; a table of caught and surviving mutations
# goes to stdout and to OUT (default docs/mutation.md). A mutation whose line is no longer in its
# file is listed as stale, not skipped silently. ONLY=N runs mutation N alone.
#   tests/mutation/run.sh [BUILD] [OUT]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build} out=${2:-docs/mutation.md}
[ -f "$build/CTestTestfile.cmake" ] || { echo "mutation: configure and build $build first" >&2; exit 2; }
exec python3 - "$build" "$out" "${ONLY:-}" <<'PY'
import os, re, signal, subprocess, sys, time
build, out, only = sys.argv[1], sys.argv[2], sys.argv[3]
# Stopped (Ctrl-C, kill): the mutated line is put back by the `finally` below either way.
signal.signal(signal.SIGTERM, lambda *_: sys.exit('mutation: stopped; the mutated file restored'))

def blocks(path):
    block = {}
    for line in open(path):
        line = line.rstrip('\n')
        if line.startswith('#'):
            continue
        if not line.strip():
            if block:
                yield block
            block = {}
            continue
        key, _, value = line.partition(': ')
        block[key] = value
    if block:
        yield block

mutations = list(blocks('tests/mutation/mutations.txt'))
rows = []
for n, m in enumerate(mutations, 1):
    if only and str(n) not in only.split(','):
        continue
    path = m['file']
    original = open(path).read()
    lines = original.split('\n')
    hits = [i for i, l in enumerate(lines) if l == m['from']]
    if len(hits) != 1:
        rows.append((n, m, 'stale', f'the line occurs {len(hits)} times', 0))
        print(f'{n:2}: stale: {m["what"]}', flush=True)
        continue
    lines[hits[0]] = m['to']
    start = time.time()
    try:
        open(path, 'w').write('\n'.join(lines))
        built = subprocess.run(['cmake', '--build', build], capture_output=True, text=True)
        if built.returncode != 0:
            verdict, detail = 'caught', 'the build fails'
        else:
            run = subprocess.run(['ctest', '--test-dir', build, '-R', m['tests'], '-j2',
                                  '--timeout', '600'], capture_output=True, text=True)
            failed = re.findall(r'^\s*\d+ - (\S+) \((?!Skipped)', run.stdout, re.M)
            ran = re.findall(r'^\s*\d+/\d+ Test +#', run.stdout, re.M)
            if not ran:
                verdict, detail = 'stale', 'no test matches ' + m['tests']
            elif run.returncode != 0:
                verdict, detail = 'caught', ', '.join(failed[:4]) or 'ctest failed'
            else:
                verdict, detail = 'SURVIVED', f'{len(ran)} tests passed'
    finally:
        open(path, 'w').write(original)
    rows.append((n, m, verdict, detail, time.time() - start))
    print(f'{n:2}: {verdict}: {m["what"]} ({detail}; {time.time() - start:.0f} s)', flush=True)
subprocess.run(['cmake', '--build', build], capture_output=True)  # back to the sources as they are

caught = sum(r[2] == 'caught' for r in rows)
table = ['# Mutation check', '',
         f'`tests/mutation/run.sh`: {caught} of {len(rows)} mutations caught. Each changes one line',
         'that carries a central decision (tests/mutation/mutations.txt), rebuilds and runs the',
         'tests that should catch it.', '',
         '| # | decision broken | file | tests run | verdict | caught by |',
         '|---|---|---|---|---|---|']
for n, m, verdict, detail, _ in rows:
    why = f' {m["note"]}' if 'note' in m else ''
    tests = m['tests'].replace('|', '\\|')  # a table cell: | escaped, even in code
    table.append(f'| {n} | {m["what"]} | `{m["file"]}` | `{tests}` | {verdict} | {detail}.{why} |')
text = '\n'.join(table) + '\n'
print(text)
if not only:
    os.makedirs(os.path.dirname(out) or '.', exist_ok=True)
    open(out, 'w').write(text)
sys.exit(0 if caught == len(rows) else 1)
PY
