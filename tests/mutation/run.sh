#!/usr/bin/env bash
# The mutation check (not in CI): each mutation of tests/mutation/mutations.txt changes
# one line that carries a central decision, rebuilds BUILD (default build/, configured), runs the
# tests that should catch it and restores the line; a table of caught and surviving mutations
# goes to stdout and to OUT (default docs/mutation.md). First every selected test runs on the
# unmodified tree: where one fails there, nothing is mutated (exit 2). A mutation is caught only
# where a test fails on an assertion (ctest's "Failed", or a crash or a non-zero exit): one that
# fails to build is invalid, one whose tests only time out is a timeout, a line no longer in its
# file (or no test matching) is stale; none of those counts as caught, and any of them fails the
# run (exit 1) naming it, as a survivor does. ONLY=N[,M...] runs those mutations alone.
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

def ctest(regex):
    """(the tests that failed other than by a timeout, each with ctest's word for how: Failed,
    SEGFAULT, ...; those timed out; how many ran)"""
    run = subprocess.run(['ctest', '--test-dir', build, '-R', regex, '-j2', '--timeout', '600'],
                         capture_output=True, text=True)
    ended = re.findall(r'^\s*\d+ - (\S+) \((\w[^)]*)\)', run.stdout, re.M)
    failed = [f'{t} ({why})' for t, why in ended if why not in ('Skipped', 'Timeout', 'Not Run')]
    timeouts = [t for t, why in ended if why == 'Timeout']
    ran = re.findall(r'^\s*\d+/\d+ Test +#', run.stdout, re.M)
    if run.returncode != 0 and not failed and not timeouts:
        failed = ['ctest exited ' + str(run.returncode)]
    return failed, timeouts, len(ran)

mutations = list(blocks('tests/mutation/mutations.txt'))
chosen = [(n, m) for n, m in enumerate(mutations, 1) if not only or str(n) in only.split(',')]
# The baseline: the unmodified tree builds and every selected test passes.
if subprocess.run(['cmake', '--build', build], capture_output=True).returncode != 0:
    sys.exit('mutation: the unmodified tree does not build')
failed, timeouts, _ = ctest('|'.join(m['tests'] for _, m in chosen))
if failed or timeouts:
    sys.exit('mutation: on the unmodified tree these fail: ' + ', '.join(failed + timeouts) +
             '; nothing was mutated')
print('baseline: every selected test passes on the unmodified tree', flush=True)
rows = []
for n, m in chosen:
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
            verdict, detail = 'invalid', 'the mutated tree does not build'
        else:
            failed, timeouts, ran = ctest(m['tests'])
            if not ran:
                verdict, detail = 'stale', 'no test matches ' + m['tests']
            elif failed:
                verdict, detail = 'caught', ', '.join(failed[:4])
            elif timeouts:
                verdict, detail = 'timeout', 'only timed out: ' + ', '.join(timeouts[:4])
            else:
                verdict, detail = 'SURVIVED', f'{ran} tests passed'
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
