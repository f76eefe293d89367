#!/usr/bin/env bash
# The fine (12-division, the seed's 12,096-hex ball) stage of the MAT_057 foam fits of
# calibrate_foam_balls.sh: bounded least squares started from each coarse (8-division) fit, no
# global stage, at most 8 least-squares evaluations, 2 workers. The coarse fits did not survive
# refinement (docs/foams.md, "On one mesh"); these are the fits on the mesh Table 9 runs on.
# Writes benchmarks/calibration/<name>-12div.json and the fitted balls <name>-12div.toml.
# Usage: benchmarks/calibrate_foam_fine.sh [name ...]   (default: type1-mat057 type2-mat057)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=benchmarks/calibration
STUDIES=${STUDIES:-runs}
PY=${PY:-python}
names=("$@")
[ ${#names[@]} -eq 0 ] && names=(type1-mat057 type2-mat057)
for name in "${names[@]}"; do
  $PY -m batball.cli calibrate --ball "$OUT/$name.toml" --model mat057 --quick \
    --global-points 0 --coarse-divisions 12 --max-evaluations 8 --workers 2 \
    --bound "hu=0.02:1" --study "$STUDIES/calibrate-$name-12div.db" \
    --save "$OUT/$name-12div.toml" --json --no-progress > "$OUT/$name-12div.json"
  echo "$name-12div: $(grep -m1 wall_seconds "$OUT/$name-12div.json")"
done
