#!/usr/bin/env bash
# Drape against Blender's cloth, side by side in one run: the same
# tablecloth dropped onto the round table, each tool in turn, twice, at
# 33 × 33 and 64 × 64. Drape: `drape check` (the key's whole rest shape,
# loading included). Blender: a 100-frame simulation at quality 5
# (tablecloth_drop.py; the time printed excludes Blender's start and the
# scene's building, and the wall time beside it includes them).
#
#     cargo build --release && bash benches/against_blender/run.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
drape="$here/../../target/release/drape"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
command -v blender >/dev/null || { echo "needs Blender (apt-get install blender)" >&2; exit 1; }
test -x "$drape" || { echo "needs $drape (cargo build --release)" >&2; exit 1; }

now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { print b - a }'; }
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores; $(blender --version | head -n 1)"
printf '%-5s %-6s %-9s %-12s %-10s %s\n' grid round drape_s drape blender_s "blender: wall s, last frame's move, highest, lowest, points inside the top"
for round in 1 2; do
    for grid in 33 64; do
        scene="$work/round_table_$grid.ron"
        sed -e "s/grid: (64, 64)/grid: ($grid, $grid)/" "$here/round_table_64.ron" > "$scene"
        began=$(now)
        "$drape" check "$scene" > "$work/check.txt" 2>/dev/null
        drape_s=$(since "$began")
        verdict=settled
        grep -q "NOT settled" "$work/check.txt" && verdict="NOT settled"
        began=$(now)
        line=$(blender -b --factory-startup -P "$here/tablecloth_drop.py" -- --grid "$grid" --frames 100 2>/dev/null | grep '^blender')
        wall_s=$(since "$began")
        read -r -a f <<< "$line"
        printf '%-5s %-6s %-9.2f %-12s %-10.2f %.2f s, %s mm, %s m, %s m, %s\n' \
            "$grid" "$round" "$drape_s" "$verdict" "${f[6]}" "$wall_s" "${f[8]}" "${f[10]}" "${f[12]}" "${f[14]}"
    done
done
