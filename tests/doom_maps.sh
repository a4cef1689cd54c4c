#!/bin/sh
# Doom maps (make verify with DOOM_MAPS=1; skipped with a message without the package freedoom): every map of
# Freedoom's two campaigns and of FreeDM, imported by pvsimport (one cell per subsector of an open sector; every
# N-th for about MAP_CELLS cells, default 30, 0: all), baked with auto and portal on 2 threads and checked by
# pvscheck (seed 99): one line a map, then a summary. With NO_SOLIDS=1 the maps are imported without their solid
# space (pvsimport --no-solids: the drawn surfaces and the sky alone, as a converter to OBJ would give them).
#   sh tests/doom_maps.sh OUTDIR
# Exits 1 when any import or bake fails or a bake misses an object, 0 otherwise.
set -u
B=${B:-build}
. tests/map_check.sh
out=${1:?usage: sh tests/doom_maps.sh OUTDIR}
DIR=${PVS_DOOM_DIR:-/usr/share/games/doom}
CELLS=${MAP_CELLS:-30}
extra=""; [ "${NO_SOLIDS:-0}" = 1 ] && extra="--no-solids"
[ -r "$DIR/freedoom2.wad" ] || { echo "doom_maps: $DIR/freedoom2.wad not found (apt install freedoom): skipped"; exit 0; }
mkdir -p "$out"
fail=0; maps=0; misses=0
for wad in freedoom1 freedoom2 freedm; do
  [ -r "$DIR/$wad.wad" ] || continue
  for m in $("$B/pvsimport" "$DIR/$wad.wad" --list); do
    name=$wad.$m
    "$B/pvsimport" -q "$DIR/$wad.wad" --map "$m" -o "$out/$name.obj" --cells "$out/$name.cells" $extra 2> "$out/$name.err" ||
      { echo "map $name: import failed FAIL ($(tail -1 "$out/$name.err"))"; fail=1; continue; }
    n=$(grep -vc '^#' "$out/$name.cells")
    step=1; [ "$CELLS" -gt 0 ] && step=$(( (n + CELLS - 1) / CELLS ))
    [ "$step" -gt 1 ] && "$B/pvsimport" -q "$DIR/$wad.wad" --map "$m" -o "$out/$name.obj" --cells "$out/$name.cells" \
      --cell-step "$step" $extra 2> "$out/$name.err"
    line="map $name ($n subsectors, $(grep -vc '^#' "$out/$name.cells") cells):"
    for method in auto portal; do
      if ! "$B/pvsbake" -q "$out/$name.obj" --cells "$out/$name.cells" -o "$out/$name.$method.pvs" -j 2 --no-state \
           --method "$method" > "$out/$name.$method.log" 2>&1; then
        if grep -q "no closed convex meshes" "$out/$name.$method.log"; then line="$line $method does not apply;"; continue; fi
        line="$line $method bake failed FAIL"; fail=1; continue
      fi
      if [ "$method" = portal ] && "$B/pvsinfo" --raw "$out/$name.auto.pvs" "$out/a.raw" > /dev/null 2>&1 &&
         "$B/pvsinfo" --raw "$out/$name.portal.pvs" "$out/p.raw" > /dev/null 2>&1 && cmp -s "$out/a.raw" "$out/p.raw"; then
        line="$line portal the same;"; continue # auto ran portal alone: checked above
      fi
      map_check "$out/$name.obj" "$out/$name.$method.pvs"
      k=$misses_found p=$mean_pvs t=$tightness
      line="$line $method $p (tightness $t), misses $k;"
      misses=$((misses + k))
      [ "$k" -eq 0 ] || fail=1
    done
    maps=$((maps + 1))
    echo "$line"
  done
done
echo "doom_maps: $maps maps, $misses misses$([ $fail -eq 0 ] || echo ' FAIL')"
exit $fail
