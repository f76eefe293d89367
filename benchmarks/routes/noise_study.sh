#!/usr/bin/env bash
# The routes under measurement noise (docs/notes/calibration-routes.md, "Measurement noise"): seeded
# noisy copies of a synthetic data set (batball synthetic-noise, the assumed lab repeatability
# of calibrate/noise.py) and compare-calibrations on each, one JSON per seed.
# Usage: benchmarks/routes/noise_study.sh [seed ...]   (default 1 2 3 4)
# Env: SOURCE (exact data, default benchmarks/routes/synthetic), TAG (result name, "synthetic"),
# EXTRA (more compare-calibrations options, e.g. the DMA's --bulk-modulus), PY, RUNS.
# A seed whose JSON exists is skipped; the calibration studies live in $RUNS/noise-$TAG-seed-N,
# so an interrupted run resumes where it stopped. Results are written atomically (tmp + mv).
set -euo pipefail
cd "$(dirname "$0")/../.."
SOURCE=${SOURCE:-benchmarks/routes/synthetic}
TAG=${TAG:-synthetic}
EXTRA=${EXTRA:---bulk-modulus=243500psi}
PY=${PY:-python}
RUNS=${RUNS:-runs}
DATA=benchmarks/routes/noise-$TAG
OUT=benchmarks/routes/results
seeds=("$@")
[ ${#seeds[@]} -eq 0 ] && seeds=(1 2 3 4)
$PY -m batball.cli synthetic-noise --source "$SOURCE" --out "$DATA" --seeds "${seeds[@]}" > /dev/null
for seed in "${seeds[@]}"; do
  result=$OUT/noise-$TAG-seed-$seed.json
  [ -s "$result" ] && { echo "seed $seed: done ($result)"; continue; }
  d=$DATA/seed-$seed
  start=$(date +%s)
  eval "$PY -m batball.cli compare-calibrations --ball type1 --bat default \
    --cor-targets $d/cor-targets.toml --ccor-targets $d/ccor-targets.toml --dma $d/dma.csv \
    --measured-bbs $d/bbs.toml --circumferential 16 --axial-size '0.4 in' --workers 1 \
    --runs-dir $RUNS/noise-$TAG-seed-$seed --json $EXTRA" > "$result.tmp"
  mv "$result.tmp" "$result"
  echo "seed $seed: $(( $(date +%s) - start )) s"
done
