#!/bin/sh
# Every OpenArena map (make verify with ALL_MAPS=1; about 20 minutes on 2 cores): the maps of the packages
# openarena-081-maps and its 0.8.5 patch beyond the six of tests/maps.sh, each on about 30 evenly spaced BSP-leaf
# cells, baked with auto and portal on 2 threads and checked by pvscheck (seed 99): one line a map, then a summary.
#   sh tests/maps_all.sh OUTDIR
# Another Quake 3 game's maps (IBSP 46), levels made by other hands: PVS_MAPS_PK3S names its pk3 files, e.g.
#   PVS_MAPS_PK3S=/usr/share/games/nexuiz/data/data.pk3 sh tests/maps_all.sh OUTDIR   (package nexuiz-data)
# A map is imported twice by tests/maps.sh: every leaf (to count them), then every N-th (its q3map2 PVS on the same
# cells). Exits 1 when any bake fails or misses an object, 0 otherwise; 0 with a message when the package is absent.
set -u
B=${B:-build}
. tests/map_check.sh
out=${1:?usage: sh tests/maps_all.sh OUTDIR}
DIR=${PVS_MAPS_DIR:-/usr/share/games/openarena/baseoa}
PK3S=${PVS_MAPS_PK3S:-"$DIR/pak1-maps.pk3 $DIR/pak6-patch085.pk3"}
SIX=" oa_dm7 ps37ctf oa_dm1 q3dm6ish oa_bases3 kaos2 "
CELLS=${MAP_CELLS:-30}
mkdir -p "$out"
list() { # PK3: its maps' names
  if command -v unzip > /dev/null 2>&1; then unzip -Z1 "$1" 2> /dev/null
  else python3 -c "import sys, zipfile; print('\n'.join(zipfile.ZipFile(sys.argv[1]).namelist()))" "$1" 2> /dev/null; fi |
    sed -n 's,^maps/\([^/]*\)\.bsp$,\1,p'
}
set -- $PK3S
[ -r "$1" ] || { echo "maps_all: $1 not found (apt install openarena-081-maps, or nexuiz-data): skipped"; exit 0; }
fail=0; maps=0; misses=0; seen=" "
for pk in $PK3S; do
  [ -r "$pk" ] || continue
  for m in $(list "$pk"); do
    case "$SIX$seen" in *" $m "*) continue ;; esac
    seen="$seen$m "
    PVS_MAPS=$m PVS_MAPS_PK3=$pk sh tests/maps.sh "$out/all" 1 > /dev/null 2> "$out/$m.err" || { echo "map $m: import failed FAIL"; fail=1; continue; }
    [ -s "$out/all/$m.cells" ] || { echo "map $m: no cells ($(tail -1 "$out/$m.err"))"; continue; }
    n=$(grep -vc '^#' "$out/all/$m.cells")
    PVS_MAPS=$m PVS_MAPS_PK3=$pk sh tests/maps.sh "$out" $(( (n + CELLS - 1) / CELLS )) > /dev/null 2>&1 ||
      { echo "map $m: import failed FAIL"; fail=1; continue; }
    q=$("$B/pvsinfo" "$out/$m.q3.pvs" 2> /dev/null | awk '/^pvs size/ { print $4 }'); q=${q:-0}
    line="map $m ($n leaves, $(grep -vc '^#' "$out/$m.cells") cells):"
    for method in auto portal; do
      if ! "$B/pvsbake" -q "$out/$m.obj" --cells "$out/$m.cells" -o "$out/$m.$method.pvs" -j 2 --no-state \
           --method "$method" > /dev/null 2>&1; then
        line="$line $method bake failed FAIL"; fail=1; continue
      fi
      map_check "$out/$m.obj" "$out/$m.$method.pvs"
      k=$misses_found p=$mean_pvs t=$tightness
      line="$line $method $p ($(awk "BEGIN { if ($q > 0) printf \"%.2f\", ${p:-0} / $q; else printf \"-\" }") of q3map2's $q, tightness $t), misses $k;"
      misses=$((misses + k))
      [ "$k" -eq 0 ] || fail=1
    done
    maps=$((maps + 1))
    echo "$line"
  done
done
echo "maps_all: $maps maps, $misses misses$([ $fail -eq 0 ] || echo ' FAIL')"
exit $fail
