#!/bin/sh
# The spread of fragment areas of window.json's pane (1.2 x 0.9 m, 6 mm annealed glass) broken
# by the uncleared 6.99 ms triangle at P kPa, through `brisance fracture` (the function a job
# uses): per seed the fragment count, the largest fragment in % of the pane, and p10, p50, p90
# of the fragment areas (nearest rank, as the result's frontal_area_m2 distribution) with
# p90 / p10 (issue 11: at least 20). Default: twice the breaking pressure (14.42 kPa), seeds 1-8.
# Run from the repository root:
#   sh bench/sim/fracture_area_spread.sh > bench/results/fracture_area_spread.txt
#   P="7.3 23 46.5 80.9 157" SEEDS="1 2 3" sh bench/sim/fracture_area_spread.sh
B=${B:-build/release/cli/brisance}
P=${P:-14.42}
SEEDS=${SEEDS:-"1 2 3 4 5 6 7 8"}
OUT=${TMPDIR:-/tmp}/fracture_area_spread.json
echo "# fragment areas of a 1.2 x 0.9 m, 6 mm annealed pane, 6.99 ms triangle: per seed"
printf "%8s %5s %9s %10s %10s %10s %10s %8s\n" P_kPa seed fragments largest_% p10_cm2 p50_cm2 \
  p90_cm2 p90/p10
for p in $P; do
  for s in $SEEDS; do
    $B fracture --width 1.2 --height 0.9 --pressure-kpa "$p" --duration-ms 6.99 --seed "$s" \
      -o "$OUT" > /dev/null || exit 1
    python3 - "$OUT" "$p" "$s" <<'PY'
import json, math, sys
areas = sorted(f["area"] for f in json.load(open(sys.argv[1]))["fragments"])
def rank(q):  # nearest rank: the smallest value with at least q of the values at or below it
    return areas[max(math.ceil(q * len(areas)), 1) - 1]
p10, p50, p90 = rank(0.1), rank(0.5), rank(0.9)
print("%8s %5s %9d %10.2f %10.3f %10.2f %10.2f %8.1f" % (sys.argv[2], sys.argv[3], len(areas),
      100 * areas[-1] / sum(areas), p10 * 1e4, p50 * 1e4, p90 * 1e4, p90 / p10))
PY
  done
done
