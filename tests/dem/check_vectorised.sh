#!/usr/bin/env bash
# check_vectorised.sh REPORT SOURCE: every loop of SOURCE (the bond pass) that GCC did not
# vectorise, as its vectorisation report REPORT says (-fopt-info-vec-all, written by the
# object library strata_dem_vectorised_probe), is one the source marks "left scalar" on the
# line the report names. The `#pragma omp simd` loops are not marked: one of them left scalar,
# in any instantiation, fails this check. Such a loop computes the same bits, only slower, so
# no other test sees it.
set -euo pipefail
report=$1
src=$2
name=$(basename "$src")
[[ -s "$report" ]] || { echo "check_vectorised: no vectorisation report at $report" >&2; exit 1; }
vectorised=$(grep -c "/$name:[0-9]*:[0-9]*: optimized: loop vectorized" "$report" || true)
((vectorised > 0)) || { echo "check_vectorised: $report names no vectorised loop of $name" >&2; exit 1; }
bad=0
while read -r n line; do
  if sed -n "${line}p" "$src" | grep -q "left scalar"; then
    echo "$name:$line: left scalar by design ($n loop versions)"
  else
    echo "$src:$line: a loop left scalar ($n compiled versions) that the source does not mark" \
      "'left scalar' (an omp simd loop of the bond pass must vectorise); GCC's reasons are in $report" >&2
    sed -n "${line}p" "$src" >&2
    bad=1
  fi
done < <(grep -oE "/$name:[0-9]+:[0-9]+: missed: couldn't vectorize loop" "$report" | cut -d: -f2 | sort -n | uniq -c)
((bad == 0)) && echo "$name: $vectorised loop versions vectorised; no omp simd loop left scalar"
exit $bad
