#!/bin/sh
# Bakes a fixed set of small generator scenes with every method and prints one line per bake:
#   SCENE SEED METHOD-AND-OPTIONS sha256-of-the-file (or "refused N" with pvsbake's exit status)
# `sh tests/bake_hashes.sh --check` compares against tests/bake_hashes.txt (the files baked before a
# refactoring; make verify runs the check): a line that differs is a change of behaviour. After a change
# that is meant to change results, `sh tests/bake_hashes.sh > tests/bake_hashes.txt` records the new files.
set -u
mode=${1:-}
B=${B:-build}
T=$B/bake_hashes
mkdir -p "$T"
out=$T/now.txt
: > "$out"
for kind in city forest indoor walls soup; do
  for seed in 1 2 3; do
    base="$T/$kind-$seed"
    "$B/pvsgen" "$kind" --seed "$seed" --size 0.3 --max-cells 12 -o "$base.obj" --cells "$base.cells" 2>/dev/null ||
      { echo "$kind $seed: pvsgen failed" >&2; exit 1; }
    more='"auto --adaptive 20000"'
    case $kind in forest|soup) more="";; esac   # adaptive cells: slow where little is culled
    eval "set -- auto sample shrink otree extproj vocc portal \"auto --preview\" \"extproj --sweep --subcells\" \
      otree,extproj \"vocc --vocc-only\" \"auto --max-distance 40\" $more"
    for m in "$@"; do
      name=$(echo "$m" | tr ' ' '_')
      # shellcheck disable=SC2086
      "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --no-state -j 2 --method $m -o "$base.pvs" 2>/dev/null
      rc=$?
      if [ "$rc" -eq 0 ]; then
        h=$(sha256sum < "$base.pvs" | cut -c1-64)
      else
        h="refused $rc"
      fi
      echo "$kind $seed $name $h" >> "$out"
    done
  done
done
if [ "$mode" = --check ]; then
  if diff tests/bake_hashes.txt "$out" > "$T/diff.txt"; then
    echo "bake hashes: $(wc -l < "$out") bakes byte-identical to tests/bake_hashes.txt"
  else
    echo "bake hashes: these bakes differ from tests/bake_hashes.txt (< before, > now):"
    cat "$T/diff.txt"
    exit 1
  fi
else
  cat "$out"
fi
