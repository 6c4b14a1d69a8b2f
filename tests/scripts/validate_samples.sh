#!/usr/bin/env bash
# Every sample glTF must pass the Khronos glTF validator with zero errors.
# Skips (exit 77) where node or the validator (installed by ./run test into .tools) is absent.
set -euo pipefail
. "$(dirname "$(realpath "$0")")/skip.sh"
bin=$1 root=$2 work=$3
need_node_tools "$root" gltf-validator
rm -rf "$work" && mkdir -p "$work"
"$bin/crowdbake" samples --no-cloth --out "$work" >/dev/null
node "$root/tests/scripts/validate.js" "$tools/gltf-validator" "$work"/*.glb
