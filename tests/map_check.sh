# Sourced by tests/maps_all.sh and tests/doom_maps.sh: map_check OBJ PVS runs pvscheck (2 threads, seed 99) and sets
# misses_found (1 when pvscheck gives no summary), mean_pvs and tightness from its summary line (not its last line:
# with a miss that names the first one).
map_check() {
  c=$("$B/pvscheck" -q -j 2 --seed 99 "$1" "$2" 2> /dev/null | grep "^cells" | tail -1)
  misses_found=$(echo "$c" | sed -n 's/.*misses \([0-9]*\).*/\1/p'); misses_found=${misses_found:-1}
  mean_pvs=$(echo "$c" | sed -n 's/.*mean pvs \([0-9.]*\).*/\1/p')
  tightness=$(echo "$c" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p')
}
