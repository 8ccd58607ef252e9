#!/usr/bin/env bash
# Writes the golden frames listed in assets/golden/frames.txt (make update-goldens), by rendering the
# replays in assets/replays/ with rattle-replay render. Run it on purpose only, when a change of the
# picture is intended, and look at the new PNGs before committing them: the golden-frame tests compare
# against these files.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
REPLAY=${REPLAY:-build/bin/rattle-replay}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
while read -r replay tick size fog; do
  [[ -z "$replay" || "$replay" == \#* ]] && continue
  "$REPLAY" render --quiet "assets/replays/$replay" --frames "$TMP" --from "$tick" --to "$tick" --size "$size" --fog "$fog" > /dev/null
  out="assets/golden/${replay%.replay}_$(printf '%06d' "$tick").png"
  mv "$TMP/frame_$(printf '%06d' "$tick").png" "$out"
  echo "$out"
done < assets/golden/frames.txt
