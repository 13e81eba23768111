#!/usr/bin/env bash
# rigid_block.sh -- cases/rigid_block.json (Molinos et al. 2021, section
# 3.2; issue 17) on cells of 4 m instead of 2 m (a quarter of the points,
# half the steps): explicit npc with LME, gamma 3 and 0.8, gravity ramped in
# by eq 45 over T = 20 s. The block settles by a third of its height, so its
# points cross cells. Each run must reach 20 s with finite stresses; from
# t = 10 s (the ramp done) the top must oscillate about the settlement at
# rest of the rate-form elastic block, 33.2 m, within 2 % (measured 1.6 and
# 0.9 %), and the bottom row's sigma_yy, averaged over that window, must be
# rho0 g (H0 - Y) within 3 % (measured 0.2 and 1.4 %: the window holds
# about 1.2 periods of the block's oscillation, of +-40 %).
# With Cundall's local damping (time.local_damping 0.2), LME gamma 3 comes
# to rest: over the last 5 s (15-20 s) the bottom row's ratio must stay
# within a band of 0.1 (undamped: 0.6-1.45) and average 1 within 3 %
# (measured 0.979, band 0.950-0.997; settlement 33.55 m, 1.1 %).
# With kinetic damping (time.kinetic_damping: the points stopped at each
# peak of their kinetic energy), both gammas come to rest by 15 s: over the
# last 5 s the bottom row's ratio must average 1 within 2 % (the issue's
# item) and stay within a band of 0.02, the settlement within 2 % of 33.2 m
# (measured: gamma 0.8 1.0026, band 0.0008, 33.21 m; gamma 3 0.985, band
# 0.004, 33.64 m), and the run must count its resets.
# usage: rigid_block.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"

check='
import json, sys
s = json.load(open(sys.argv[1]))
m = s["metrics"]
end = s["scene"]["time"]["end"]
print("t = %g s reached, settlement %.3f m (at rest %.3f), bottom ratio %.4f (from %.3f to %.3f)"
      % (end, m["top_settlement_mid"], m["settlement_ref"], m["bottom_stress_ratio"],
         m["bottom_stress_ratio_min"], m["bottom_stress_ratio_max"]))
ok = s["status"] == "completed" and "stress_not_finite" not in m and m["settlement_error"] < 0.02 \
    and m["bottom_stress_error"] < 0.03 and m["bottom_points"] == 44
sys.exit(0 if ok else 1)
'
for g in 3 0.8; do
  d="$work/lme_$g"
  "$exe" run "$src/cases/rigid_block.json" --quiet --set output.vtk=none --set mesh.h=4 \
    --set probes.top=[44,87] --set shape.gamma=$g --out "$d" > /dev/null 2> "$d.err"
  rc=$?
  if [ $rc -ne 0 ]; then
    ko "LME gamma $g: exit $rc: $(head -c 300 "$d.err")"
    continue
  fi
  if out=$(python3 -c "$check" "$d/summary.json" 2>&1); then
    ok "LME gamma $g: $out"
  else
    ko "LME gamma $g: $out"
  fi
done

d="$work/lme_3_damped"
"$exe" run "$src/cases/rigid_block.json" --quiet --set output.vtk=none --set mesh.h=4 \
  --set probes.top=[44,87] --set time.local_damping=0.2 --set reference.from=15 --out "$d" \
  > /dev/null 2> "$d.err"
rc=$?
if [ $rc -ne 0 ]; then
  ko "LME gamma 3, damped: exit $rc: $(head -c 300 "$d.err")"
elif out=$(python3 -c "$check" "$d/summary.json" 2>&1) && python3 -c '
import json, sys
m = json.load(open(sys.argv[1]))["metrics"]
sys.exit(0 if m["bottom_stress_ratio_max"] - m["bottom_stress_ratio_min"] < 0.1 else 1)' "$d/summary.json"; then
  ok "LME gamma 3, local damping 0.2, from 15 s: $out"
else
  ko "LME gamma 3, local damping 0.2, from 15 s: $out"
fi

for g in 0.8 3; do
  d="$work/lme_${g}_kinetic"
  "$exe" run "$src/cases/rigid_block.json" --quiet --set output.vtk=none --set mesh.h=4 \
    --set probes.top=[44,87] --set shape.gamma=$g --set time.kinetic_damping=true \
    --set reference.from=15 --out "$d" > /dev/null 2> "$d.err"
  rc=$?
  if [ $rc -ne 0 ]; then
    ko "LME gamma $g, kinetic damping: exit $rc: $(head -c 300 "$d.err")"
  elif out=$(python3 -c "$check" "$d/summary.json" 2>&1) && python3 -c '
import json, sys
s = json.load(open(sys.argv[1]))
m = s["metrics"]
sys.exit(0 if m["bottom_stress_error"] < 0.02 and m["bottom_stress_ratio_max"] - m["bottom_stress_ratio_min"] < 0.02
         and s["counts"]["kinetic_resets"] > 0 else 1)' "$d/summary.json"; then
    ok "LME gamma $g, kinetic damping, from 15 s: $out"
  else
    ko "LME gamma $g, kinetic damping, from 15 s: $out"
  fi
done

echo "rigid_block: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
