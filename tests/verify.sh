#!/bin/sh
# make verify: the long acceptance runs. For every generator, seed and size, bake with every method
# and check the result against ray sampling with pvscheck. One line per scene and method:
#   SCENE SEED SIZE METHOD cells=N misses=N tightness=T
# Exits non-zero on any miss of a conservative method. The `sample` method is an estimate from below
# (not conservative): its misses are printed for information and never fail the run. `auto` (the
# intersection of the conservative methods that cull on its sample) must also be within 5% of the best
# of the other conservative methods on each scene (its mean PVS at most 1.05 times theirs).
set -u
B=${B:-build}
T=$B/verify
mkdir -p "$T"
CONSERVATIVE_METHODS=${CONSERVATIVE_METHODS:-"shrink otree extproj vocc portal auto"}   # filled in as conservative methods land
CELLS=${CELLS:-500}
J=${J:-0}
fail=0
# check LABEL SCENE.obj FILE.pvs: pvscheck's line after LABEL, and " FAIL" (failing the run) unless it ends 0
check() {
  line=$("$B/pvscheck" -q -j "$J" --seed 99 "$2" "$3")
  rc=$?
  note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
  echo "$1 $line$note"
}
for kind in city forest indoor walls soup building; do
  for seed in 1 2 3; do
    for size in 0.3 0.6; do
      base="$T/$kind-$seed-$size"
      "$B/pvsgen" "$kind" --seed "$seed" --size "$size" --max-cells "$CELLS" -o "$base.obj" --cells "$base.cells" 2>/dev/null || { echo "$kind $seed $size: pvsgen failed"; fail=1; continue; }
      best=""; auto_pvs=""
      for method in sample $CONSERVATIVE_METHODS; do
        # vocc needs vertical walls standing on the ground (2.5D); it refuses forest and soup
        case "$method:$kind" in vocc:forest|vocc:soup) continue;; esac
        if ! "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method "$method" -j "$J" -o "$base.$method.pvs"; then
          echo "$kind $seed $size $method: bake failed"; fail=1; continue
        fi
        line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.$method.pvs")
        rc=$?
        misses=$(echo "$line" | sed -n 's/.*misses \([0-9]*\).*/\1/p' | head -1)
        cells=$(echo "$line" | sed -n 's/^cells \([0-9]*\).*/\1/p' | head -1)
        tight=$(echo "$line" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p' | head -1)
        mean=$(echo "$line" | sed -n 's/.*mean pvs \([0-9.]*\).*/\1/p' | head -1)
        if [ "$method" = auto ]; then auto_pvs=$mean;
        elif [ "$method" != sample ] && [ -n "$mean" ]; then
          if [ -z "$best" ] || awk "BEGIN { exit !($mean < $best) }"; then best=$mean; fi
        fi
        note=""
        if [ "$method" = sample ]; then note=" (approximate: not counted)";
        elif [ "$rc" -ne 0 ]; then fail=1; note=" FAIL"; fi
        echo "$kind $seed $size $method cells=$cells misses=$misses tightness=$tight$note"
      done
      # auto keeps the best single method on its 8 sample cells, then those that cull enough more
      # (PVS_AUTO_MIN_GAIN, by cost class): never over 1.05 times the best single method here
      if [ -n "$auto_pvs" ] && [ -n "$best" ] && awk "BEGIN { exit !($auto_pvs > 1.05 * $best) }"; then
        echo "$kind $seed $size auto: mean PVS $auto_pvs is over 1.05 times the best single method's $best FAIL"; fail=1
      fi
    done
  done
done
# otree on the full-size city: three seeds, 500 cells each (CITY_CELLS), files identical for -j1 and -j2
case " $CONSERVATIVE_METHODS " in *" otree "*)
  for seed in 1 2 3; do
    base="$T/city-full-$seed"
    "$B/pvsgen" city --seed "$seed" --max-cells "${CITY_CELLS:-500}" -o "$base.obj" --cells "$base.cells" 2>/dev/null || { echo "city full $seed: pvsgen failed"; fail=1; continue; }
    "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method otree -j 1 -o "$base.otree.pvs" || { echo "city full $seed otree: bake failed"; fail=1; continue; }
    if [ "$seed" = 1 ]; then
      "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method otree -j 2 -o "$base.otree-j2.pvs" &&
        cmp -s "$base.otree.pvs" "$base.otree-j2.pvs" || { echo "city full $seed otree: -j1 and -j2 files differ"; fail=1; }
    fi
    check "city $seed 1 otree" "$base.obj" "$base.otree.pvs"
  done;;
esac
# vocc on the full-size city: three seeds, 500 cells each; the PVS checked is the one rebuilt from the
# stored virtual occluders (pvs_vocc_cull); files identical for -j1 and -j2 and for 3 merged shards; a
# --vocc-only bake stores the same occluders
case " $CONSERVATIVE_METHODS " in *" vocc "*)
  for seed in 1 2 3; do
    base="$T/city-full-$seed"
    [ -f "$base.obj" ] || "$B/pvsgen" city --seed "$seed" --max-cells "${CITY_CELLS:-500}" -o "$base.obj" --cells "$base.cells" 2>/dev/null || { echo "city full $seed: pvsgen failed"; fail=1; continue; }
    "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method vocc -j 1 -o "$base.vocc.pvs" || { echo "city full $seed vocc: bake failed"; fail=1; continue; }
    if [ "$seed" = 1 ]; then
      "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method vocc -j 2 -o "$base.vocc-j2.pvs" &&
        cmp -s "$base.vocc.pvs" "$base.vocc-j2.pvs" || { echo "city full $seed vocc: -j1 and -j2 files differ"; fail=1; }
      for k in 1 2 3; do "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method vocc --shard $k/3 -j "$J" -o "$base.vocc-p$k.pvs"; done
      "$B/pvsbake" merge -o "$base.vocc-merged.pvs" "$base.vocc-p3.pvs" "$base.vocc-p1.pvs" "$base.vocc-p2.pvs" 2>/dev/null &&
        cmp -s "$base.vocc.pvs" "$base.vocc-merged.pvs" || { echo "city full $seed vocc: 3 shards merged differ from the whole bake"; fail=1; }
      "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method vocc --vocc-only -j "$J" -o "$base.vocc-only.pvs" &&
        "$B/pvsinfo" --vocc "$base.vocc.pvs" > "$base.vocc.txt" && "$B/pvsinfo" --vocc "$base.vocc-only.pvs" > "$base.vocc-only.txt" &&
        cmp -s "$base.vocc.txt" "$base.vocc-only.txt" || { echo "city full $seed vocc: --vocc-only stores other occluders"; fail=1; }
      check "city $seed 1 vocc-only" "$base.obj" "$base.vocc-only.pvs"
    fi
    check "city $seed 1 vocc" "$base.obj" "$base.vocc.pvs"
  done;;
esac
# extproj with the occlusion sweep (§5), with its sub-cells and with adaptive cells (§6.1): every
# generator, three seeds, EXTPROJ_CELLS cells each (ADAPTIVE_CELLS for adaptive cells, each split
# into many); files identical for -j1 and -j2
case " $CONSERVATIVE_METHODS " in *" extproj "*)
  for kind in city forest indoor walls soup; do
    for seed in 1 2 3; do
      base="$T/$kind-$seed-ep"
      "$B/pvsgen" "$kind" --seed "$seed" --size 0.6 --max-cells "${EXTPROJ_CELLS:-500}" -o "$base.obj" --cells "$base.cells" 2>/dev/null || { echo "$kind $seed extproj: pvsgen failed"; fail=1; continue; }
      "$B/pvsgen" "$kind" --seed "$seed" --size 0.6 --max-cells "${ADAPTIVE_CELLS:-100}" -o "$base-a.obj" --cells "$base-a.cells" 2>/dev/null || { echo "$kind $seed extproj: pvsgen failed"; fail=1; continue; }
      for variant in sweep subcells adaptive; do
        case $variant in
          sweep) opts="--sweep"; cf="$base.cells";;
          subcells) opts="--sweep --subcells"; cf="$base.cells";;
          *) opts="--adaptive ${ADAPTIVE_BUDGET:-20000}"; cf="$base-a.cells";;
        esac
        "$B/pvsbake" -q --no-state "$base.obj" --cells "$cf" --method extproj $opts -j "$J" -o "$base.$variant.pvs" || { echo "$kind $seed extproj $variant: bake failed"; fail=1; continue; }
        if [ "$seed" = 1 ]; then
          "$B/pvsbake" -q --no-state "$base.obj" --cells "$cf" --method extproj $opts -j 1 -o "$base.$variant-j1.pvs" &&
            cmp -s "$base.$variant.pvs" "$base.$variant-j1.pvs" || { echo "$kind $seed extproj $variant: files differ with the thread count"; fail=1; }
        fi
        check "$kind $seed 0.6 extproj-$variant" "$base.obj" "$base.$variant.pvs"
      done
    done
  done;;
esac
# the dense forest (pvsgen forest --dense, Durand 2000 §7.2's kind of scene): extproj with and without
# the occlusion sweep, three seeds, DENSE_CELLS cells each; 0 misses (pvscheck's default --aim 32)
case " $CONSERVATIVE_METHODS " in *" extproj "*)
  for seed in 1 2 3; do
    base="$T/forest-dense-$seed"
    "$B/pvsgen" forest --dense --seed "$seed" --size 0.6 --max-cells "${DENSE_CELLS:-200}" -o "$base.obj" --cells "$base.cells" 2>/dev/null || { echo "forest --dense $seed: pvsgen failed"; fail=1; continue; }
    for variant in sweep plain; do
      if [ "$variant" = sweep ]; then opts="--sweep"; else opts=""; fi
      "$B/pvsbake" -q --no-state "$base.obj" --cells "$base.cells" --method extproj $opts -j "$J" -o "$base.$variant.pvs" || { echo "forest --dense $seed extproj $variant: bake failed"; fail=1; continue; }
      check "forest-dense $seed 0.6 extproj-$variant" "$base.obj" "$base.$variant.pvs"
    done
  done
  # the paper's density (1,000 leaves per tree, 1 m cells) with the sweep at 1024 pixels and 64
  # planes (bench_extproj's forest1000 settings), with and without sub-cells, two seeds, PAPER_CELLS
  # cells each
  for seed in 1 2; do
    base="$T/forest-1000-$seed"
    "$B/pvsgen" forest --dense --leaves-per-tree 1000 --cell-size 1 --seed "$seed" --size 0.4 --max-cells "${PAPER_CELLS:-30}" -o "$base.obj" --cells "$base.cells" 2>/dev/null ||
      { echo "forest --dense --leaves-per-tree 1000 $seed: pvsgen failed"; fail=1; continue; }
    "$B/pvsbake" -q --no-state "$base.obj" --cells "$base.cells" --method extproj --sweep-planes 64 --resolution 1024 -j "$J" -o "$base.pvs" ||
      { echo "forest 1000 $seed extproj: bake failed"; fail=1; continue; }
    if [ "$seed" = 1 ]; then
      "$B/pvsbake" -q --no-state "$base.obj" --cells "$base.cells" --method extproj --sweep-planes 64 --resolution 1024 -j 1 -o "$base-j1.pvs" &&
        cmp -s "$base.pvs" "$base-j1.pvs" || { echo "forest 1000 $seed extproj: files differ with the thread count"; fail=1; }
    fi
    check "forest-1000 $seed 0.4 extproj-sweep64-1024" "$base.obj" "$base.pvs"
    "$B/pvsbake" -q --no-state "$base.obj" --cells "$base.cells" --method extproj --sweep-planes 64 --resolution 1024 --subcells -j "$J" -o "$base.sub.pvs" ||
      { echo "forest 1000 $seed extproj --subcells: bake failed"; fail=1; continue; }
    check "forest-1000 $seed 0.4 extproj-sweep64-1024-subcells" "$base.obj" "$base.sub.pvs"
  done;;
esac
# bounded time and memory on any input (BOUNDED=0 skips): a 100,000-vertex single face (one OBJ `f`
# line: a fan of 99,998 slivers) bakes with every method within 2 GB (--memory 2G and a 2.5 GB
# address-space ulimit) and 60 s; the adversarial scenes at full size (a standing fan, slivers in every
# direction, a huge triangle with 100,000 tiny ones, 100,000 copies of one triangle) bake with auto
# and check with 0 misses; the resume journal costs at most 1.5 times --no-state at 10k, 40k and
# 200,000 cells; the preview of 200,000 objects and 2,025 cells ends within 60 s on 2 threads; and the
# sanitizer build of pvsbake ends 0 with the attached -j1 form
if [ "${BOUNDED:-1}" != 0 ]; then
  now() { date +%s.%N; }
  four="$T/bounded-cells.txt"
  printf '%s\n' "-10 1 -10 -5 3 -5" "20 1 20 25 3 25" "-40 10 30 -35 12 35" "0 30 -2 2 32 2" > "$four"
  awk 'BEGIN { n = 100000; print "o fan"; for (i = 0; i < n; i++) { a = 6.283185307179586 * i / n; printf "v %.6f 5 %.6f\n", 50 * cos(a), 50 * sin(a) }
               printf "f"; for (i = 1; i <= n; i++) printf " %d", i; print "" }' > "$T/fan100k.obj"
  awk 'BEGIN { n = 100000; print "o fan"; for (i = 0; i < n; i++) { a = 6.283185307179586 * i / n; printf "v %.6f %.6f 0\n", 50 * cos(a), 50 + 50 * sin(a) }
               printf "f"; for (i = 1; i <= n; i++) printf " %d", i; print "" }' > "$T/wallfan100k.obj"
  awk 'BEGIN { srand(1); print "o slivers"; for (i = 0; i < 100000; i++) { a = 3.141592653589793 * rand(); y = 20 * rand(); c = 50 * cos(a); s = 50 * sin(a)
               printf "v %.6f %.6f %.6f\nv %.6f %.6f %.6f\nv %.6f %.6f %.6f\nf %d %d %d\n", -c, y, -s, c, y, s, c, y + 0.001, s, 3*i+1, 3*i+2, 3*i+3 } }' > "$T/slivers100k.obj"
  awk 'BEGIN { srand(2); print "o huge\nv -1e6 0 -1e6\nv 1e6 0 -1e6\nv 0 0 1e6\nf 1 2 3\no tiny"; for (i = 0; i < 100000; i++) { x = 100 * rand() - 50; y = 20 * rand(); z = 100 * rand() - 50
               printf "v %.6f %.6f %.6f\nv %.6f %.6f %.6f\nv %.6f %.6f %.6f\nf %d %d %d\n", x, y, z, x + 0.001, y, z, x, y + 0.001, z, 3*i+4, 3*i+5, 3*i+6 } }' > "$T/hugetiny100k.obj"
  awk 'BEGIN { print "v -10 0 -10\nv 10 0 -10\nv 0 10 10\no same"; for (i = 0; i < 100000; i++) print "f 1 2 3" }' > "$T/coincident100k.obj"
  # and 24 small boxes around them (above, below and beside the fans), objects of their own that the
  # adversarial occluders may hide: the checks then test what the methods cull
  for scene in fan100k wallfan100k slivers100k hugetiny100k coincident100k; do
    awk 'BEGIN { srand(5); for (b = 0; b < 24; b++) { x = 80 * rand() - 40; y = b % 3 == 0 ? 20 + 20 * rand() : b % 3 == 1 ? 6 + 4 * rand() : 0.5 * rand(); z = 80 * rand() - 40
                 printf "o box%d\n", b; for (k = 0; k < 8; k++) printf "v %g %g %g\n", x + (k % 2), y + int(k / 2) % 2, z + (k >= 4)
                 split("0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5", f, " ")
                 for (t = 0; t < 12; t++) printf "f %d %d %d\n", f[3*t+1] - 8, f[3*t+2] - 8, f[3*t+3] - 8 } }' >> "$T/$scene.obj"
  done
  for method in sample shrink otree extproj vocc auto; do
    t0=$(now)
    ( ulimit -v 2621440; timeout 60 "$B/pvsbake" -q --no-state --memory 2G "$T/fan100k.obj" --cells "$four" --method "$method" -o "$T/fan.$method.pvs" ) > "$T/fan.$method.txt" 2>&1
    rc=$?
    dt=$(awk "BEGIN { printf \"%.1f\", $(now) - $t0 }")
    note=""
    if [ "$rc" -eq 124 ] || [ "$rc" -gt 1 ]; then fail=1; note=" FAIL"; fi  # 0: baked, 1: refused with a message (vocc: no walls)
    echo "fan100k $method exit=$rc seconds=$dt$note $(head -c 160 "$T/fan.$method.txt" | tr '\n' ' ')"
  done
  for scene in fan100k wallfan100k slivers100k hugetiny100k coincident100k; do
    t0=$(now)
    ( ulimit -v 2621440; timeout 120 "$B/pvsbake" -q --no-state --memory 2G "$T/$scene.obj" --cells "$four" -o "$T/$scene.pvs" ) || { echo "$scene auto: bake failed FAIL"; fail=1; continue; }
    dt=$(awk "BEGIN { printf \"%.1f\", $(now) - $t0 }")
    check "$scene auto seconds=$dt" "$T/$scene.obj" "$T/$scene.pvs"
  done
  awk 'BEGIN { srand(3); v = 1; for (i = 0; i < 17; i++) { x = 90 * rand(); z = 90 * rand(); w = 2 + 6 * rand(); h = 3 + 12 * rand(); printf "o box%d\n", i
               for (k = 0; k < 8; k++) printf "v %g %g %g\n", x + (k % 2 ? w : 0), (int(k / 2) % 2 ? h : 0), z + (k >= 4 ? w : 0)
               split("0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5", f, " ")
               for (t = 0; t < 12; t++) printf "f %d %d %d\n", v + f[3*t+1], v + f[3*t+2], v + f[3*t+3]; v += 8 } }' > "$T/small17.obj"
  for cells in 10000 40000 200000; do
    awk -v n="$cells" 'BEGIN { s = int(sqrt(n) + 0.999); c = 0; for (i = 0; i < s && c < n; i++) for (j = 0; j < s && c < n; j++) {
               d = 100 / s; printf "%g 1 %g %g 2 %g\n", i * d, j * d, i * d + d, j * d + d; c++ } }' > "$T/small$cells.txt"
    best_with=""; best_without=""
    for run in 1 2; do
      t0=$(now); "$B/pvsbake" -q --no-state "$T/small17.obj" --cells "$T/small$cells.txt" --method otree -j 2 -o "$T/small-a.pvs"; t1=$(now)
      "$B/pvsbake" -q "$T/small17.obj" --cells "$T/small$cells.txt" --method otree -j 2 -o "$T/small-b.pvs"; t2=$(now)
      a=$(awk "BEGIN { print $t1 - $t0 }"); b=$(awk "BEGIN { print $t2 - $t1 }")
      if [ -z "$best_without" ] || awk "BEGIN { exit !($a < $best_without) }"; then best_without=$a; fi
      if [ -z "$best_with" ] || awk "BEGIN { exit !($b < $best_with) }"; then best_with=$b; fi
    done
    cmp -s "$T/small-a.pvs" "$T/small-b.pvs" || { echo "state $cells: files differ"; fail=1; }
    ratio=$(awk "BEGIN { printf \"%.2f\", $best_with / $best_without }")
    note=""; awk "BEGIN { exit !($ratio > 1.5) }" && { fail=1; note=" FAIL"; }
    echo "state $cells cells: ${best_with}s with the journal, ${best_without}s without, ratio $ratio$note"
  done
  awk 'BEGIN { srand(7); v = 1; side = 448; for (c = 0; c < 200000; c++) { x = (c % side) * 2 + 0.5 * rand(); z = int(c / side) * 2 + 0.5 * rand(); s = 0.3 + 0.9 * rand()
               h = rand() < 0.3 ? 0.5 + 5.5 * rand() : 0.2 + 1.3 * rand(); printf "o b%d\n", c
               for (k = 0; k < 8; k++) printf "v %.3f %.3f %.3f\n", x + (k % 2 ? s : 0), (int(k / 2) % 2 ? h : 0), z + (k >= 4 ? s : 0)
               split("0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5", f, " ")
               for (t = 0; t < 12; t++) printf "f %d %d %d\n", v + f[3*t+1], v + f[3*t+2], v + f[3*t+3]; v += 8 } }' > "$T/s200k.obj"
  awk 'BEGIN { for (i = 0; i < 45; i++) for (j = 0; j < 45; j++) { x = (i + 0.5) * 896 / 45; z = (j + 0.5) * 896 / 45; printf "%.3f 0.1 %.3f %.3f 2 %.3f\n", x, z, x + 1.5, z + 1.5 } }' > "$T/s200k.txt"
  t0=$(now)
  "$B/pvsbake" -q "$T/s200k.obj" --cells "$T/s200k.txt" --preview -j 2 -o "$T/s200k.pvs" || { echo "preview 200k: bake failed"; fail=1; }
  dt=$(awk "BEGIN { printf \"%.1f\", $(now) - $t0 }")
  note=""; awk "BEGIN { exit !($dt > 60) }" && { fail=1; note=" FAIL"; }
  echo "preview 200,000 objects 2,025 cells: ${dt}s$note"
  make -s CONFIG=sanitize B="$B/san" "$B/san/pvsbake" >/dev/null 2>&1 || { echo "sanitize build failed"; fail=1; }
  "$B/san/pvsbake" -q "$T/small17.obj" --cells "$T/small10000.txt" --method otree -j1 -o "$T/san.pvs" && echo "sanitizer pvsbake -j1: exit 0" ||
    { echo "sanitizer pvsbake -j1: non-zero exit FAIL"; fail=1; }
fi
# real Quake 3 levels (issue 28; MAPS=0 skips): the OpenArena maps of the package openarena-081-maps
# (tests/maps.sh, skipped with a message when absent), every BSP leaf with a cluster a cell: portal and auto
# with 0 misses; the map's own PVS (q3map2's vis, expanded to objects) checked the same way, for information
if [ "${MAPS:-1}" != 0 ]; then
  if maps=$(sh tests/maps.sh "$T/maps" 1); then
    for m in $maps; do
      for method in portal auto; do
        if "$B/pvsbake" -q "$T/maps/$m.obj" --cells "$T/maps/$m.cells" -j "$J" --no-state --method "$method" \
             -o "$T/maps/$m.$method.pvs"; then
          check "map $m $method" "$T/maps/$m.obj" "$T/maps/$m.$method.pvs"
        else
          echo "map $m $method: bake failed FAIL"; fail=1
        fi
      done
      echo "map $m q3map2 (not counted) $("$B/pvscheck" -q -j "$J" --seed 99 "$T/maps/$m.obj" "$T/maps/$m.q3.pvs")"
    done
  fi
fi
# every other OpenArena map, about 30 cells each (ALL_MAPS=1; about 20 minutes): tests/maps_all.sh
if [ "${ALL_MAPS:-0}" = 1 ]; then sh tests/maps_all.sh "$T/all_maps" || fail=1; fi
# Nexuiz's 39 maps (NEXUIZ_MAPS=1; package nexuiz-data; Quake 3 BSPs made by other hands), the same way
if [ "${NEXUIZ_MAPS:-0}" = 1 ]; then
  PVS_MAPS_PK3S=${PVS_NEXUIZ_PK3:-/usr/share/games/nexuiz/data/data.pk3} sh tests/maps_all.sh "$T/nexuiz_maps" || fail=1
fi
# Freedoom's and FreeDM's 100 Doom maps, about 30 cells each (DOOM_MAPS=1; package freedoom; about 100 minutes)
if [ "${DOOM_MAPS:-0}" = 1 ]; then sh tests/doom_maps.sh "$T/doom_maps" || fail=1; fi
[ $fail -eq 0 ] && echo "verify: ok" || echo "verify: FAILED"
exit $fail
