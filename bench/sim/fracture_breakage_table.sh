#!/bin/sh
# Breakage: dynamic against static (docs/fracture.md, "Coupling to the blast") for window.json's
# pane (1.2 x 0.9 m, 6 mm annealed glass), TNT air bursts head-on, through `brisance blast` and
# `brisance fracture` (the functions a job uses). The pulse flags give the uncleared reflected
# pulse; the last column is the dynamic plate under the front face cleared from the pane's edges
# (--charge-kg/--distance-m: what a job with clearing on, the default, takes). Run from the
# repository root:
#   sh bench/sim/fracture_breakage_table.sh > bench/results/fracture_breakage.txt
B=${B:-build/release/cli/brisance}
printf "| charge | P_r kPa | t_o ms | i_r kPa·ms | stress static MPa | stress dynamic MPa | a_c×5000 static mm | dynamic mm | breaking P_r static kPa | dynamic kPa | stress dynamic cleared MPa |\n|---|---|---|---|---|---|---|---|---|---|---|\n"
for cd in "1 40" "10 40" "10 20" "10 10" "100 10"; do
  set -- $cd
  eval $($B blast --charge-kg $1 --distance-m $2 --json | python3 -c "import json,sys; d=json.load(sys.stdin); print('P=%.17g D=%.17g I=%.17g' % (d['reflected_overpressure_kpa'], d['positive_duration_ms'], d['reflected_impulse_kpa_ms']))")
  for m in static dynamic; do
    $B fracture --width 1.2 --height 0.9 --grid 256 --pressure-kpa $P --duration-ms $D --impulse-kpa-ms $I --breakage $m -o /tmp/sdof_cmp_$m.json > /dev/null
    $B fracture --width 1.2 --height 0.9 --grid 256 --duration-ms $D --breakage $m -o /tmp/sdof_brk_$m.json > /dev/null
  done
  $B fracture --width 1.2 --height 0.9 --grid 256 --charge-kg $1 --distance-m $2 -o /tmp/sdof_cmp_cleared.json > /dev/null
  python3 - "$1" "$2" "$P" "$D" "$I" <<'PY'
import json,sys
kg,r,P,D,I=sys.argv[1:]
c=json.load(open('/tmp/sdof_cmp_cleared.json'))
s=json.load(open('/tmp/sdof_cmp_static.json')); d=json.load(open('/tmp/sdof_cmp_dynamic.json'))
bs=json.load(open('/tmp/sdof_brk_static.json')); bd=json.load(open('/tmp/sdof_brk_dynamic.json'))
def ac(x):
    # eq. 5.5 x pattern_scale 5000 (annealed glass, K_c 0.75 MPa m^0.5, strength 45 MPa), mm
    return "%.3g" % ((1 / 3.141592653589793) * (0.75 / x) ** 2 * 5000 * 1e3) if x > 45 else "unbroken"
print("| %s kg at %s m | %.1f | %.2f | %.0f | %.0f | %.0f | %s | %s | %.2f | %.2f | %.0f |" % (kg, r, float(P), float(D), float(I), s['stress_mpa'], d['stress_mpa'], ac(s['stress_mpa']), ac(d['stress_mpa']), bs['pressure_kpa'], bd['pressure_kpa'], c['stress_mpa']))
PY
done
