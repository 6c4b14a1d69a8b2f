#!/usr/bin/env bash
# Golden files: each sample is baked, and `crowdbake inspect` of the pack plus its SHA-256 must
# match the checked-in goldens. After a deliberate change, run with CROWD_UPDATE_GOLDEN=1 and
# say why in the commit.
set -euo pipefail
bin=$1 golden=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
"$bin/crowdbake" samples --no-cloth --out "$work" >/dev/null
status=0
for glb in "$work"/*.glb; do
  name=$(basename "$glb" .glb)
  (cd "$work" && "$bin/crowdbake" anim "$name.glb" -o "$name.crowdpack" --quiet)
  "$bin/crowdbake" inspect "$work/$name.crowdpack" > "$work/$name.inspect.txt"
  (cd "$work" && sha256sum "$name.crowdpack") > "$work/$name.sha256"
  for kind in inspect.txt sha256; do
    if [ "${CROWD_UPDATE_GOLDEN:-0}" = 1 ]; then
      cp "$work/$name.$kind" "$golden/$name.$kind"
    elif ! diff -u "$golden/$name.$kind" "$work/$name.$kind"; then
      echo "golden mismatch: $name.$kind" >&2
      status=1
    fi
  done
done
[ $status = 0 ] && echo "goldens match"
exit $status
