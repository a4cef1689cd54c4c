#!/bin/sh
# make verify: the long acceptance runs. For every generator, seed and size, bake with every method
# and check the result against ray sampling with pvscheck. One line per scene and method:
#   SCENE SEED SIZE METHOD cells=N misses=N tightness=T
# Exits non-zero on any miss of a conservative method. The `sample` method is an estimate from below
# (not conservative): its misses are printed for information and never fail the run.
set -u
B=${B:-build}
T=$B/verify
mkdir -p "$T"
CONSERVATIVE_METHODS=${CONSERVATIVE_METHODS:-"shrink otree extproj"}   # filled in as conservative methods land
CELLS=${CELLS:-500}
J=${J:-0}
fail=0
for kind in city forest indoor walls soup; do
  for seed in 1 2 3; do
    for size in 0.3 0.6; do
      base="$T/$kind-$seed-$size"
      "$B/pvsgen" "$kind" --seed "$seed" --size "$size" --max-cells "$CELLS" -o "$base.obj" --cells "$base.cells" 2>/dev/null || { echo "$kind $seed $size: pvsgen failed"; fail=1; continue; }
      for method in sample $CONSERVATIVE_METHODS; do
        if ! "$B/pvsbake" -q "$base.obj" --cells "$base.cells" --method "$method" -j "$J" -o "$base.$method.pvs"; then
          echo "$kind $seed $size $method: bake failed"; fail=1; continue
        fi
        line=$("$B/pvscheck" -q -j "$J" --seed 99 "$base.obj" "$base.$method.pvs")
        rc=$?
        misses=$(echo "$line" | sed -n 's/.*misses \([0-9]*\).*/\1/p' | head -1)
        cells=$(echo "$line" | sed -n 's/^cells \([0-9]*\).*/\1/p' | head -1)
        tight=$(echo "$line" | sed -n 's/.*tightness \([0-9.]*\).*/\1/p' | head -1)
        note=""
        if [ "$method" = sample ]; then note=" (approximate: not counted)";
        elif [ "$rc" -ne 0 ]; then fail=1; note=" FAIL"; fi
        echo "$kind $seed $size $method cells=$cells misses=$misses tightness=$tight$note"
      done
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
# extproj with the occlusion sweep (§5) and with adaptive cells (§6.1): every generator, three seeds,
# EXTPROJ_CELLS cells each; files identical for -j1 and -j2
case " $CONSERVATIVE_METHODS " in *" extproj "*)
  for kind in city forest indoor walls soup; do
    for seed in 1 2 3; do
      base="$T/$kind-$seed-ep"
      "$B/pvsgen" "$kind" --seed "$seed" --size 0.6 --max-cells "${EXTPROJ_CELLS:-500}" -o "$base.obj" --cells "$base.cells" 2>/dev/null || { echo "$kind $seed extproj: pvsgen failed"; fail=1; continue; }
      # adaptive cells split each cell into many: fewer cells (ADAPTIVE_CELLS)
      "$B/pvsgen" "$kind" --seed "$seed" --size 0.6 --max-cells "${ADAPTIVE_CELLS:-100}" -o "$base-a.obj" --cells "$base-a.cells" 2>/dev/null || { echo "$kind $seed extproj: pvsgen failed"; fail=1; continue; }
      for variant in sweep adaptive; do
        if [ "$variant" = sweep ]; then opts="--sweep"; cf="$base.cells"; else opts="--adaptive ${ADAPTIVE_BUDGET:-20000}"; cf="$base-a.cells"; fi
        "$B/pvsbake" -q "$base.obj" --cells "$cf" --method extproj $opts -j "$J" -o "$base.$variant.pvs" || { echo "$kind $seed extproj $variant: bake failed"; fail=1; continue; }
        if [ "$seed" = 1 ]; then
          "$B/pvsbake" -q "$base.obj" --cells "$cf" --method extproj $opts -j 1 -o "$base.$variant-j1.pvs" &&
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
[ $fail -eq 0 ] && echo "verify: ok" || echo "verify: FAILED"
exit $fail
