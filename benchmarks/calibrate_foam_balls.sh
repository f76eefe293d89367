#!/usr/bin/env bash
# Coarse-mesh calibrations of the foam laws MAT_057 and MAT_083 to the seed's ball types 1 and 2
# (experiment columns of Tables 5-8), starting from the example foams (specs/data/foam057.toml,
# foam083.toml) with the seed ball's size and mass; free: curve_scale, hu, shape, damp (issue 5).
# Coarse only (8-division ball, 3,584 hexes; no full-mesh stage) to fit the shared 2-core machine:
# one worker; type1-mat057 with 8 Latin-hypercube points and at most 12 least-squares
# evaluations, the others (run beside it, on a machine loaded ~5x) with 6 and 8. HU is searched in
# [0.02, 1]: MAT_057 excludes 0, and MAT_083 reads HU = 0 as "no damage" (= HU 1), a jump.
# Writes benchmarks/calibration/<name>.json and the fitted balls <name>.toml.
# Usage: benchmarks/calibrate_foam_balls.sh [name ...]   (default: all four)
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=benchmarks/calibration
STUDIES=${STUDIES:-runs}
PY=${PY:-python}
declare -A ARGS=(
  [type1-mat057]="--ball type1 --model mat057 --global-points 8 --max-evaluations 12"
  [type2-mat057]="--ball type2 --model mat057 --global-points 6 --max-evaluations 8"
  [type1-mat083]="--ball type1 --model mat083 --global-points 6 --max-evaluations 8"
  [type2-mat083]="--ball type2 --model mat083 --global-points 6 --max-evaluations 8"
)
names=("$@")
[ ${#names[@]} -eq 0 ] && names=(type1-mat057 type2-mat057 type1-mat083 type2-mat083)
for name in "${names[@]}"; do
  # shellcheck disable=SC2086
  $PY -m batball.cli calibrate ${ARGS[$name]} --quick --coarse-divisions 8 \
    --workers 1 --bound "hu=0.02:1" --study "$STUDIES/calibrate-$name.db" \
    --save "$OUT/$name.toml" --json --no-progress > "$OUT/$name.json"
  echo "$name: $(grep -m1 wall_seconds "$OUT/$name.json")"
done
