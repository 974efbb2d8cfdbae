#!/bin/sh
# Fragment count against growth length and against pressure for a 1.2 x 0.8 m, 6 mm annealed
# pane (docs/fracture.md, "How the count scales"), through `brisance fracture` (the function a
# job uses: scene defaults, grid 2048 refined to 4 cells per growth length up to 4096), 8 seeds.
# Run from the repository root:
#   sh bench/sim/fracture_count_sweep.sh > bench/results/fracture_count_sweep.txt
B=${B:-build/release/cli/brisance}
SEEDS="1 2 3 4 5 6 7 8"
count() {  # the fragment count of one run: "<n> fragments written to ..."
  $B fracture --width 1.2 --height 0.8 "$@" -o /tmp/count_sweep.json | sed -n 's/^\([0-9]*\) fragments.*/\1/p'
}
summary() {  # mean, min, max of the counts on stdin
  awk '{s+=$1; if(NR==1||$1<lo)lo=$1; if($1>hi)hi=$1} END {printf "%8.0f %6d %6d", s/NR, lo, hi}'
}
echo "# fragments of a 1.2 x 0.8 m pane over seeds $SEEDS: mean min max"
echo "# by growth length (--growth-length)"
printf "%10s %6s %8s %6s %6s\n" a_c_mm cells mean min max
for a in 0.05 0.02 0.01 0.005 0.003 0.002 0.0015 0.00117 0.000586; do
  out=$(for s in $SEEDS; do count --growth-length $a --seed $s; done | summary)
  cells=$(python3 -c "import math; a=$a; print(max(2048, min(4096, math.ceil(4*1.2/a))))")
  printf "%10s %6s %s\n" "$(python3 -c "print('%g' % ($a*1e3))")" "$cells" "$out"
done
echo "# by peak reflected pressure (dynamic plate, 8 ms triangle)"
printf "%10s %8s %6s %6s\n" P_r_kPa mean min max
for p in 10 25 50 100 200 300 500 700 1000 3000; do
  out=$(for s in $SEEDS; do count --pressure-kpa $p --duration-ms 8 --seed $s; done | summary)
  printf "%10s %s\n" $p "$out"
done
