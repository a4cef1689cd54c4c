#!/bin/sh
# make bench (issue 30): the .pvs file against general-purpose compressors applied to its own raw bit
# table (pvsinfo --raw: cells x ceil(objects / 8) bytes), on generator scenes baked with auto and on
# the OpenArena maps' whole-level bakes that tests/bench_maps.sh leaves in $B/maps (run it first) and on
# three Doom maps (packages freedoom, freedm: Freedoom's E1M1 and MAP01, FreeDM's MAP01), every subsector a cell, and
# on oa_dm7's walkable cells (pvsbake --cells walkable):
#   BENCH file_ratio_raw_SCENE    the file over the raw table
#   BENCH file_ratio_gzip_SCENE   the file over gzip -9 of the raw table
#   BENCH file_ratio_xz_SCENE     the file over xz -9 of the raw table
#   BENCH file_ratio_zrl_SCENE    the file over the raw table's rows compressed as Quake's vis does (each byte
#                                 as is, but a run of up to 255 zero bytes as a 0 and its length; rows apart)
#   BENCH file_ratio_gzip_nolookup_MAP  the maps' files without cell boxes and look-up (pvsbake merge
#                                 --no-lookup: engines that find their cells themselves) over gzip -9 of the table
#   BENCH file_ratio_gzip_cells_SCENE  the file over gzip -9 of the table followed by the cells file: what the file
#                                 carries (every cell's box beside its PVS), where the other yardstick has no boxes
# then the means over the scenes measured, and file_ratio_gzip_levels_mean over the real levels alone. The
# scenes are baked without object names (--no-names: identity, not visibility; the raw table holds none either).
# A compressor or a package not installed is skipped with a message.
set -u
B=${B:-build}
T=$B/file-ratio
mkdir -p "$T"
have_gzip=1; command -v gzip > /dev/null || { have_gzip=0; echo "bench_file_ratio: gzip not found: file_ratio_gzip skipped"; }
have_xz=1; command -v xz > /dev/null || { have_xz=0; echo "bench_file_ratio: xz not found: file_ratio_xz skipped"; }
sums=$T/sums.txt
: > "$sums"; rm -f "$T/nolookup.txt" "$T/levels.txt" "$T/cells.txt"
ratio() { # FILE.pvs LABEL [CELLS]
  "$B/pvsinfo" --raw "$1" "$T/raw.bin" || return
  f=$(wc -c < "$1"); r=$(wc -c < "$T/raw.bin")
  echo "BENCH file_ratio_raw_$2 $(awk "BEGIN { printf \"%.3f\", $f / $r }") ratio"
  row=$("$B/pvsinfo" "$1" | awk '/^objects/ { printf "%d", ($2 + 7) / 8 }')
  z=$(od -An -v -tu1 -w"$row" "$T/raw.bin" | awk '{ for (i = 1; i <= NF; ) if ($i != 0) { n++; i++ }
        else { for (c = 0; i <= NF && $i == 0 && c < 255; c++) i++; n += 2 } } END { print n + 0 }')
  [ "$z" -gt 0 ] && echo "BENCH file_ratio_zrl_$2 $(awk "BEGIN { printf \"%.2f\", $f / $z }") ratio"
  g=0; x=0
  if [ $have_gzip -eq 1 ]; then
    g=$(gzip -9 -c "$T/raw.bin" | wc -c)
    echo "BENCH file_ratio_gzip_$2 $(awk "BEGIN { printf \"%.2f\", $f / $g }") ratio"
    if [ -f "${3:-}" ]; then
      c=$(cat "$T/raw.bin" "$3" | gzip -9 | wc -c)
      echo "BENCH file_ratio_gzip_cells_$2 $(awk "BEGIN { printf \"%.2f\", $f / $c }") ratio"
    fi
  fi
  if [ $have_xz -eq 1 ]; then
    x=$(xz -9 -c "$T/raw.bin" | wc -c)
    echo "BENCH file_ratio_xz_$2 $(awk "BEGIN { printf \"%.2f\", $f / $x }") ratio"
  fi
  echo "$f $r $g $x $z" >> "$sums"
}
for s in "city 0.5" "indoor 1" "building 0.5" "walls 1" "forest 0.5" "soup 1"; do
  set -- $s
  "$B/pvsgen" "$1" --size "$2" -o "$T/$1.obj" --cells "$T/$1.cells" > /dev/null 2>&1 || { echo "pvsgen $1 failed"; exit 1; }
  "$B/pvsbake" -q "$T/$1.obj" --cells "$T/$1.cells" -o "$T/$1.pvs" -j 2 --no-state --no-names ||
    { echo "pvsbake $1 failed"; exit 1; }
  ratio "$T/$1.pvs" "$1" "$T/$1.cells"
done
level() { # FILE.pvs LABEL CELLS: a real level, also without its look-up (ratio's f, g, c: file, gzip -9 of its
  # table, of the table and cells)
  c=0
  ratio "$1" "$2" "$3" || return
  [ "$g" -gt 0 ] || return 0
  echo "$f $g" >> "$T/levels.txt"
  [ "$c" -gt 0 ] && echo "$f $c" >> "$T/cells.txt"
  "$B/pvsbake" merge --no-lookup -o "$T/$2.nolookup.pvs" "$1" 2> /dev/null || return 0
  n=$(wc -c < "$T/$2.nolookup.pvs")
  echo "BENCH file_ratio_gzip_nolookup_$2 $(awk "BEGIN { printf \"%.2f\", $n / $g }") ratio"
  echo "$n $g" >> "$T/nolookup.txt"
}
for p in "$B"/maps/*.whole.pvs; do
  [ -f "$p" ] || { echo "bench_file_ratio: no whole-level map bakes in $B/maps (tests/bench_maps.sh): Quake 3 levels skipped"; break; }
  level "$p" "$(basename "$p" .whole.pvs)" "$B/maps/all/$(basename "$p" .whole.pvs).cells"
done
# oa_dm7 on the cells a camera can walk to (pvsbake --cells walkable in Quake 3's units), not one per BSP leaf
if [ -f "$B/maps/oa_dm7.obj" ] && "$B/pvsbake" -q "$B/maps/oa_dm7.obj" --cells walkable --eye-height 50 \
     --step-height 18 -o "$T/oa_dm7_walkable.pvs" -j 2 --no-state --no-names 2> /dev/null; then
  level "$T/oa_dm7_walkable.pvs" oa_dm7_walkable "$T/oa_dm7_walkable.walkable.cells"
fi
DOOM=${PVS_DOOM_DIR:-/usr/share/games/doom}
for s in "freedoom1 E1M1 freedoom" "freedoom2 MAP01 freedoom" "freedm MAP01 freedm"; do
  set -- $s
  [ -r "$DOOM/$1.wad" ] || { echo "bench_file_ratio: $DOOM/$1.wad not found (apt install $3): skipped"; continue; }
  m=$(echo "$1_$2" | tr 'A-Z' 'a-z')
  "$B/pvsimport" "$DOOM/$1.wad" --map "$2" -o "$T/$m.obj" --cells "$T/$m.cells" -q > /dev/null 2>&1 &&
    "$B/pvsbake" -q "$T/$m.obj" --cells "$T/$m.cells" -o "$T/$m.pvs" -j 2 --no-state --no-names 2> /dev/null ||
    { echo "bench_file_ratio: $1 $2: import or bake failed"; continue; }
  level "$T/$m.pvs" "$m" "$T/$m.cells"
done
mean() { # FILE NAME: BENCH NAME, the mean of FILE's lines' file / gzip; FILE removed
  [ -s "$1" ] && awk -v name="$2" '{ r += $1 / $2; n++ } END { printf "BENCH %s %.2f ratio\n", name, r / n }' "$1"
  rm -f "$1"
}
mean "$T/levels.txt" file_ratio_gzip_levels_mean
mean "$T/nolookup.txt" file_ratio_gzip_nolookup_mean
mean "$T/cells.txt" file_ratio_gzip_cells_levels_mean
awk '{ n++; if ($3 > 0) { g += $1 / $3; ng++ } if ($4 > 0) { x += $1 / $4; nx++ } if ($5 > 0) { z += $1 / $5; nz++ }
       r += $1 / $2 }
     END { if (n) printf "BENCH file_ratio_raw_mean %.3f ratio\n", r / n;
           if (ng) printf "BENCH file_ratio_gzip_mean %.2f ratio\n", g / ng;
           if (nx) printf "BENCH file_ratio_xz_mean %.2f ratio\n", x / nx;
           if (nz) printf "BENCH file_ratio_zrl_mean %.2f ratio\n", z / nz }' "$sums"
