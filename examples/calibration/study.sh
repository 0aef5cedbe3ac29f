#!/bin/sh
# Reproduce the numbers of docs/validation.md (about 25 minutes on 2 cores).
#   sh examples/calibration/study.sh [SERVES_CSV] [OUT_DIR]
# The real data are not part of the repository (../shared/realdata/README.md).
set -e
S=${1:-../shared/realdata/courtvision_serves.csv}
O=${2:-out/validation}
mkdir -p "$O"
T="python -m tennislab calibrate"
# 1. every registered model as published, under four spin-axis assumptions
for AX in none topspin 90 fitted; do
  $T validate --serves "$S" --spin-axis "$AX" --json --quiet > "$O/validate_$AX.json"
done
# 2. calibrations: held out by match parity and by tournament (fitted on Roland Garros)
for SPLIT in parity tournament:roland_garros; do
  N=$(echo "$SPLIT" | tr ':' '_')
  $T serves --serves "$S" --split "$SPLIT" --out-table "$O/aero_$N.csv" --json --quiet > "$O/serves_cd_$N.json"
  $T serves --serves "$S" --split "$SPLIT" --fit cd,cd_s --json --quiet > "$O/serves_cd_cds_$N.json"
  $T serves --serves "$S" --split "$SPLIT" --fit cd,cl --spin-axis topspin --json --quiet > "$O/serves_cdcl_topspin_$N.json"
  $T serves --serves "$S" --split "$SPLIT" --fit speed_scale --cd 0.6 --json --quiet > "$O/serves_speed_$N.json"
done
# 3. the calibrated table validated like any model
$T validate --serves "$S" --models stepanek1988 --aero-table "$O/aero_parity.csv" --spin-axis fitted --json --quiet \
  > "$O/validate_table.json"
# 4. sensitivity of the misses to C_D, C_L, the spin axis and the tracker's speed
$T sensitivity --serves "$S" --cd 0.5,0.6,0.7,0.8,0.9 --cl 0,0.3,0.6,0.9 --spin-axes topspin,fitted --json --quiet \
  > "$O/sensitivity.json"
$T sensitivity --serves "$S" --cd 0.6 --cl 0.6 --spin-axes fitted --speed-scale 0.88,0.92,0.96,1.0 --json --quiet \
  > "$O/sensitivity_speed.json"
# 5. effective drag per event (conditions and balls differ)
for EV in australian_open_2020 australian_open_2021 roland_garros_2019 roland_garros_2020 roland_garros_2021; do
  $T serves --serves "$S" --split "event:$EV" --json --quiet > "$O/serves_cd_event_$EV.json"
done
