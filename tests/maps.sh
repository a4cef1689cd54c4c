#!/bin/sh
# Real levels for make verify and make bench (issue 28): the OpenArena maps of the system package
# openarena-081-maps, imported with build/pvsimport. Nothing from the maps is committed.
#   sh tests/maps.sh OUTDIR [CELL_STEP]
# writes OUTDIR/NAME.obj, NAME.cells and NAME.q3.pvs (the map's own PVS, q3map2's vis expanded to
# objects) for each map below, every CELL_STEP-th cell (default 1: every BSP leaf with a cluster).
# With the game's shader scripts (openarena-data's pk3s beside it), surfaces drawn front only are one-sided.
# Prints the names of the maps made, one per line, on stdout. Exits 77 with a message on stderr when
# the package, or a way to read its zip archive (unzip or python3), is missing.
# The maps: arenas (oa_dm1, oa_dm7, q3dm6ish), CTF (ps37ctf, oa_bases3) and a large one (kaos2, 1,050 cells).
set -u
MAPS=${PVS_MAPS:-"oa_dm7 ps37ctf oa_dm1 q3dm6ish oa_bases3 kaos2"}
PK3=${PVS_MAPS_PK3:-/usr/share/games/openarena/baseoa/pak1-maps.pk3}
out=${1:?usage: sh tests/maps.sh OUTDIR [CELL_STEP]}
step=${2:-1}
if [ ! -r "$PK3" ]; then
  echo "maps: $PK3 not found (apt install openarena-081-maps), real levels skipped" >&2
  exit 77
fi
mkdir -p "$out"
# the game's shader scripts (package openarena-data): which surfaces are drawn front only (pvsimport --shaders)
shaders="$out/shaders.txt"
if [ ! -s "$shaders" ]; then
  for p in "$(dirname "$PK3")"/*.pk3; do
    if command -v unzip >/dev/null 2>&1; then
      for f in $(unzip -Z1 "$p" 2>/dev/null | grep '^scripts/.*\.shader$'); do unzip -p "$p" "$f"; echo; done
    elif command -v python3 >/dev/null 2>&1; then
      python3 -c "import sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
for n in z.namelist():
    if n.startswith('scripts/') and n.endswith('.shader'): sys.stdout.buffer.write(z.read(n) + b'\\n')" "$p"
    fi
  done > "$shaders.tmp" 2>/dev/null
  mv "$shaders.tmp" "$shaders"
fi
if [ -s "$shaders" ]; then set -- --shaders "$shaders"; else
  echo "maps: no shader scripts next to $PK3 (apt install openarena-data): every surface two-sided" >&2; set --; fi
for m in $MAPS; do
  bsp="$out/$m.bsp"
  if [ ! -s "$bsp" ]; then
    if command -v unzip >/dev/null 2>&1; then
      unzip -p "$PK3" "maps/$m.bsp" > "$bsp.tmp" 2>/dev/null
    elif command -v python3 >/dev/null 2>&1; then
      python3 -c "import sys, zipfile; sys.stdout.buffer.write(zipfile.ZipFile(sys.argv[1]).read(sys.argv[2]))" \
        "$PK3" "maps/$m.bsp" > "$bsp.tmp" 2>/dev/null
    else
      echo "maps: neither unzip nor python3 to read $PK3, real levels skipped" >&2
      exit 77
    fi
    if [ ! -s "$bsp.tmp" ]; then rm -f "$bsp.tmp"; echo "maps: $m not in $PK3, skipped" >&2; continue; fi
    mv "$bsp.tmp" "$bsp"
  fi
  if "${B:-build}/pvsimport" -q "$bsp" -o "$out/$m.obj" --cells "$out/$m.cells" --pvs "$out/$m.q3.pvs" --cell-step "$step" "$@"; then
    echo "$m"
  else
    echo "maps: $m: import failed" >&2
    exit 1
  fi
done
