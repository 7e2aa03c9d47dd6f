#!/usr/bin/env bash
# check_bench_peak.sh STRATA: `scripts/bench peak` finds the bond pass's vector loop in the
# executable STRATA as built, in lattice slots and in the general form, 2D and 3D: one square
# root and one division a bond, and the flops the law needs (2D 36, 3D 69) whatever the
# vector width. The instruction mix in docs/performance.md comes from this tool; it reads symbols
# by their template signature, so a kernel whose signature changes would otherwise leave it
# failing unnoticed. The machine's peak itself (bench_peak) is not run here.
set -euo pipefail
out=$(STRATA=$1 BENCH_PEAK=true bash "$(dirname "${BASH_SOURCE[0]}")/../../scripts/bench" peak)
echo "$out"
bad=0
for dim in 2 3; do
  flops=$([[ $dim == 2 ]] && echo 36.0 || echo 69.0)
  for form in slots general; do
    line=$(grep -F "\"dim\": $dim, \"form\": \"$form\"" <<<"$out" || true)
    if [[ -z $line ]]; then
      echo "check_bench_peak: no $form loop of dimension $dim" >&2
      bad=1
    elif ! grep -qF "\"flops_per_bond\": $flops," <<<"$line" || ! grep -qF "\"sqrt_div_pairs_per_bond\": 1.00}" <<<"$line"; then
      echo "check_bench_peak: the $form loop of dimension $dim is not the intact law's ($flops flops," \
        "one square root and division a bond): $line" >&2
      bad=1
    fi
  done
done
exit $bad
