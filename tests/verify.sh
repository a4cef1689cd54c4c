#!/bin/sh
# make verify: the long acceptance runs. For every generator, seed and size, bake with every method
# and check the result against ray sampling with pvscheck. One line per scene and method:
#   SCENE SEED SIZE METHOD cells=N misses=N tightness=T
# Exits non-zero on any miss of a conservative method. The `sample` method is an estimate from below
# (not conservative): its misses are printed for information and never fail the run. `auto` (the
# intersection of the conservative methods that apply) must also be at least as tight as the best of
# the other conservative methods on each scene (its mean PVS no larger).
set -u
B=${B:-build}
T=$B/verify
mkdir -p "$T"
CONSERVATIVE_METHODS=${CONSERVATIVE_METHODS:-"shrink otree extproj vocc auto"}   # filled in as conservative methods land
CELLS=${CELLS:-500}
J=${J:-0}
fail=0
for kind in city forest indoor walls soup; do
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
      if [ -n "$auto_pvs" ] && [ -n "$best" ] && awk "BEGIN { exit !($auto_pvs > $best) }"; then
        echo "$kind $seed $size auto: mean PVS $auto_pvs is larger than the best single method's $best FAIL"; fail=1
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
    line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.otree.pvs")
    rc=$?
    note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
    echo "city $seed 1 otree $line$note"
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
      line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.vocc-only.pvs")
      rc=$?
      note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
      echo "city $seed 1 vocc-only $line$note"
    fi
    line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.vocc.pvs")
    rc=$?
    note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
    echo "city $seed 1 vocc $line$note"
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
        line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.$variant.pvs")
        rc=$?
        note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
        echo "$kind $seed 0.6 extproj-$variant $line$note"
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
      line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.$variant.pvs")
      rc=$?
      note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
      echo "forest-dense $seed 0.6 extproj-$variant $line$note"
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
    line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.pvs")
    rc=$?
    note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
    echo "forest-1000 $seed 0.4 extproj-sweep64-1024 $line$note"
    "$B/pvsbake" -q --no-state "$base.obj" --cells "$base.cells" --method extproj --sweep-planes 64 --resolution 1024 --subcells -j "$J" -o "$base.sub.pvs" ||
      { echo "forest 1000 $seed extproj --subcells: bake failed"; fail=1; continue; }
    line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.sub.pvs")
    rc=$?
    note=""; [ "$rc" -ne 0 ] && { fail=1; note=" FAIL"; }
    echo "forest-1000 $seed 0.4 extproj-sweep64-1024-subcells $line$note"
  done;;
esac
[ $fail -eq 0 ] && echo "verify: ok" || echo "verify: FAILED"
exit $fail
