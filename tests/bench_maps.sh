#!/bin/sh
# make bench: the building generator and real Quake 3 levels (issue 28), the OpenArena maps of the package openarena-081-maps
# (tests/maps.sh; skipped with a message when it is absent). Per map, on an evenly spaced sample of
# about MAP_CELLS (40: enough for AUTO's sample) of its BSP-leaf cells (every N-th leaf), one thread:
#   BENCH auto_ms_per_cell_MAP        auto's time per cell (pvsbake's figure: the cells alone)
#   BENCH auto_prepare_s_MAP          auto's set-up before the cells (occluder synthesis, trees)
#   BENCH auto_pvs_vs_q3map2_MAP      auto's mean PVS over the map's own PVS (q3map2's vis) on the same cells
#   BENCH auto_tightness_MAP          auto's mean PVS over the ray-sampled visible set (pvscheck)
#   BENCH q3map2_tightness_MAP        the same for the map's own PVS
#   BENCH auto_misses_MAP             pvscheck's misses for auto (a conservative PVS has 0)
#   BENCH portal_ms_per_cell_MAP, portal_pvs_vs_q3map2_MAP, portal_tightness_MAP, portal_misses_MAP: the same for
#                                     the portal method alone (the building: all but the q3map2 figure)
#   BENCH auto_whole_bake_s_MAP       the whole level (every leaf, auto_whole_cells_MAP cells) on 2 threads, wall
#                                     seconds from loading the OBJ to the written file (q3map2's vis: 0.3 to 8 s)
#   BENCH auto_whole_max_ms_per_cell_MAP  the whole level's slowest cell (each cell runs on one thread; issue 28's
#                                     target: none above 30 ms)
set -u
B=${B:-build}
T=$B/maps
MAP_CELLS=${MAP_CELLS:-40}
mkdir -p "$T"
# the indoor generator's building (pvsgen building, 6 storeys, ~15,000 objects), MAP_CELLS cells
"$B/pvsgen" building --max-cells "$MAP_CELLS" -o "$T/building.obj" --cells "$T/building.cells" 2>/dev/null
out=$("$B/pvsbake" "$T/building.obj" --cells "$T/building.cells" -o "$T/building.auto.pvs" -j 1 --no-state 2>&1 | tr '\r' '\n')
echo "BENCH auto_ms_per_cell_building $(echo "$out" | sed -n 's/.*time per cell \([0-9.]*\) ms.*/\1/p' | tail -1) ms"
cb=$("$B/pvscheck" -q "$T/building.obj" "$T/building.auto.pvs")
echo "BENCH auto_tightness_building $(echo "$cb" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p') x"
echo "BENCH auto_misses_building $(echo "$cb" | sed -n 's/.*misses \([0-9]*\).*/\1/p') pairs"
out=$("$B/pvsbake" "$T/building.obj" --cells "$T/building.cells" -o "$T/building.portal.pvs" -j 1 --no-state --method portal 2>&1 |
      tr '\r' '\n')
echo "BENCH portal_ms_per_cell_building $(echo "$out" | sed -n 's/.*time per cell \([0-9.]*\) ms.*/\1/p' | tail -1) ms"
cb=$("$B/pvscheck" -q "$T/building.obj" "$T/building.portal.pvs")
echo "BENCH portal_tightness_building $(echo "$cb" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p') x"
echo "BENCH portal_misses_building $(echo "$cb" | sed -n 's/.*misses \([0-9]*\).*/\1/p') pairs"
maps=$(sh tests/maps.sh "$T/all" 1) || { echo "bench_maps: skipped (no OpenArena maps)"; exit 0; }
for m in $maps; do
  n=$(grep -vc '^#' "$T/all/$m.cells")
  step=$(( (n + MAP_CELLS - 1) / MAP_CELLS ))
  PVS_MAPS=$m sh tests/maps.sh "$T" "$step" >/dev/null || continue
  out=$("$B/pvsbake" "$T/$m.obj" --cells "$T/$m.cells" -o "$T/$m.auto.pvs" -j 1 --no-state 2>&1 | tr '\r' '\n')
  per=$(echo "$out" | sed -n 's/.*time per cell \([0-9.]*\) ms.*/\1/p' | tail -1)
  prep=$(echo "$out" | sed -n 's/.*bake \([0-9.]*\) s wall on 1 thread, \([0-9.]*\) s total.*/\1 \2/p' | tail -1 |
         awk '{ printf "%.2f", $2 - $1 }')
  a=$("$B/pvsinfo" "$T/$m.auto.pvs" | awk '/^pvs size/ { print $4 }')
  q=$("$B/pvsinfo" "$T/$m.q3.pvs" | awk '/^pvs size/ { print $4 }')
  ca=$("$B/pvscheck" -q "$T/$m.obj" "$T/$m.auto.pvs")
  cq=$("$B/pvscheck" -q "$T/$m.obj" "$T/$m.q3.pvs")
  echo "BENCH auto_ms_per_cell_$m $per ms"
  echo "BENCH auto_prepare_s_$m $prep s"
  echo "BENCH auto_pvs_vs_q3map2_$m $(awk "BEGIN { printf \"%.2f\", $a / $q }") x"
  echo "BENCH auto_tightness_$m $(echo "$ca" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p') x"
  echo "BENCH q3map2_tightness_$m $(echo "$cq" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p') x"
  echo "BENCH auto_misses_$m $(echo "$ca" | sed -n 's/.*misses \([0-9]*\).*/\1/p') pairs"
  out=$("$B/pvsbake" "$T/$m.obj" --cells "$T/$m.cells" -o "$T/$m.portal.pvs" -j 1 --no-state --method portal 2>&1 |
        tr '\r' '\n')
  p=$("$B/pvsinfo" "$T/$m.portal.pvs" | awk '/^pvs size/ { print $4 }')
  cp=$("$B/pvscheck" -q "$T/$m.obj" "$T/$m.portal.pvs")
  echo "BENCH portal_ms_per_cell_$m $(echo "$out" | sed -n 's/.*time per cell \([0-9.]*\) ms.*/\1/p' | tail -1) ms"
  echo "BENCH portal_pvs_vs_q3map2_$m $(awk "BEGIN { printf \"%.2f\", $p / $q }") x"
  echo "BENCH portal_tightness_$m $(echo "$cp" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p') x"
  echo "BENCH portal_misses_$m $(echo "$cp" | sed -n 's/.*misses \([0-9]*\).*/\1/p') pairs"
  # the whole level, every leaf a cell, as a user bakes it: AUTO, its sample included, 2 threads, wall time (without
  # object names: bench_file_ratio.sh compares the file with compressors of its bit table, which holds none)
  out=$("$B/pvsbake" "$T/all/$m.obj" --cells "$T/all/$m.cells" -o "$T/$m.whole.pvs" -j 2 --no-state --no-names 2>&1 |
        tr '\r' '\n')
  echo "BENCH auto_whole_bake_s_$m $(echo "$out" | sed -n 's/.*bake \([0-9.]*\) s wall.* \([0-9.]*\) s total.*/\2/p' | tail -1) s"
  echo "BENCH auto_whole_max_ms_per_cell_$m $(echo "$out" | sed -n 's/.*slowest cells: [0-9]* (\([0-9.]*\) ms).*/\1/p' | tail -1) ms"
  echo "BENCH auto_whole_cells_$m $n cells"
done
