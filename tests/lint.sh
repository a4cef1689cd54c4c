#!/bin/sh
# make test: the house rules a compiler does not check (STYLE.md; issue 27).
#   - pvs.h: under 1 MiB (source tools skip larger files), tabs (stops every 4 columns, .editorconfig) for
#     indentation and for aligning trailing comments,
#     no line wider than 120 columns, no function longer than 150 lines;
#   - tools/: no function longer than 150 lines.
# A function runs from its first line at column 0 (return type and name) to the closing brace at
# column 0, the house layout. Prints each offence as FILE:LINE and exits 1 when there is one.
set -u
fail=0
size=$(wc -c < pvs.h)
if [ "$size" -ge 1048576 ]; then echo "pvs.h: $size bytes (at most 1 MiB, 1048575)"; fail=1; fi
long=$(awk '{ n = 0; for (i = 1; i <= length($0); ++i) n = substr($0, i, 1) == "\t" ? n - n % 4 + 4 : n + 1 }
  n > 120 { printf "%s:%d: line of %d columns (at most 120)\n", FILENAME, FNR, n }' pvs.h)
if [ -n "$long" ]; then echo "$long"; fail=1; fi
spaces=$(grep -n '^    ' pvs.h | head -3 | sed 's/:.*/: indented with spaces (tabs, 4 columns wide)/; s/^/pvs.h:/')
if [ -n "$spaces" ]; then echo "$spaces"; fail=1; fi
for f in pvs.h tools/*.c tools/*.h; do
  out=$(awk -v max=150 '
    /^[A-Za-z_][A-Za-z0-9_ *]*[ *]pvs_?_?[A-Za-z0-9_]*\(|^(static |PVS__STATIC |PVS_API )?[A-Za-z_][A-Za-z0-9_ *]*[ *][A-Za-z_][A-Za-z0-9_]*\(/ {
      if (!infn && $0 !~ /;[ \t]*$/ && $0 !~ /^(typedef|return|else|if|for|while|switch|#)/) { start = FNR; name = $0; infn = 1 }
    }
    infn && /;[ \t]*$/ && FNR == start { infn = 0 }
    infn && /^}/ {
      if (FNR - start + 1 > max) printf "%s:%d: function of %d lines (at most %d): %s\n", FILENAME, start, FNR - start + 1, max, substr(name, 1, 80)
      infn = 0
    }' "$f")
  if [ -n "$out" ]; then echo "$out"; fail=1; fi
done
if [ "$fail" -eq 0 ]; then echo "lint: pvs.h $size bytes, tab-indented, lines within 120 columns; functions in pvs.h and tools/ within 150 lines"; fi
exit $fail
