#!/usr/bin/env bash
# Records the replays in assets/replays/ (make replays). They are inputs of the tests: after recording
# them again, run `make update-goldens` too, and look at the new golden frames before committing them.
#
#   arena.replay             the default arena, the scripted opponent playing both teams from seed 2
#   doorway-rush.replay      doorways.json: both armies through three doorways (doorway-rush.commands)
#   projectile-storm.replay  storm.json: two armies firing through a picket fence (projectile-storm.commands)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
REPLAY=${REPLAY:-build/bin/rattle-replay}
OUT=assets/replays

"$REPLAY" record --quiet --map assets/maps/arena.json --seed 2 --ticks 450 --units 40 "$OUT/arena.replay"
"$REPLAY" record --quiet --map assets/maps/doorways.json --seed 1 --ticks 360 --units 60 --no-weapons --opponent none \
  --script "$OUT/doorway-rush.commands" "$OUT/doorway-rush.replay"
"$REPLAY" record --quiet --map assets/maps/storm.json --seed 1 --ticks 300 --units 50 --opponent none \
  --script "$OUT/projectile-storm.commands" "$OUT/projectile-storm.replay"
for f in "$OUT"/*.replay; do "$REPLAY" verify --quiet "$f"; done
