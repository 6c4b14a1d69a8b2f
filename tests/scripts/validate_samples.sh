#!/usr/bin/env bash
# Every sample glTF must pass the Khronos glTF validator with zero errors.
# Skips (exit 77) where node or the validator (installed by ./run test into .tools) is absent.
set -euo pipefail
bin=$1 root=$2 work=$3
validator=$root/.tools/node_modules/gltf-validator
if ! command -v node >/dev/null; then echo "SKIP: node is not installed"; exit 77; fi
if [ ! -d "$validator" ]; then echo "SKIP: gltf-validator not installed at $validator (./run test installs it)"; exit 77; fi
rm -rf "$work" && mkdir -p "$work"
"$bin/crowdbake" samples --no-cloth --out "$work" >/dev/null
node "$root/tests/scripts/validate.js" "$validator" "$work"/*.glb
