#!/bin/sh
# Two builds of physframes compared on whole renders of one scene, in alternating
# pairs: renders SCENE with build A, then with build B, N times, each into a fresh
# folder in OUT_DIR, and prints for each build the median and the lowest wall time and
# CPU time (user + system, all threads) of a render. Pairs cancel most of the drift of
# a shared machine; on this one, two copies of the same build came out within 1 to 2%
# of each other in the medians of 6 to 10 pairs, where the ratios of `physframes bench`
# move by a fifth from one round to the next. A render's CPU time is the figure a
# change to its work moves: with every core busy, the frame rate follows it.
#
#   sh benches/builds-pairs.sh BUILD_A BUILD_B SCENE [N] [OUT_DIR]
#
# For example, with the build before a change copied aside:
#
#   cp target/release/physframes /tmp/before && (make the change) && cargo build --release
#   sh benches/builds-pairs.sh /tmp/before target/release/physframes scenes/bench/trails-1000.toml 8
#
# N defaults to 8; OUT_DIR (default /dev/shm, memory, so that no disk is in the way)
# receives the renders, each removed after it is measured. Needs GNU time
# (/usr/bin/time, Debian's package `time`).
set -eu
if [ "$#" -lt 3 ]; then
    echo "usage: sh benches/builds-pairs.sh BUILD_A BUILD_B SCENE [N] [OUT_DIR]" >&2
    exit 2
fi
a=$1
b=$2
scene=$3
n=${4:-8}
out=${5:-/dev/shm}
if ! /usr/bin/time -f '' true 2>/dev/null; then
    echo "builds-pairs.sh needs GNU time as /usr/bin/time" >&2
    exit 2
fi
dir="$out/builds-pairs.$$"
times=$(mktemp)
trap 'rm -rf "$dir" "$times"' EXIT
i=0
while [ "$i" -lt "$n" ]; do
    for which in A B; do
        if [ "$which" = A ]; then bin=$a; else bin=$b; fi
        rm -rf "$dir"
        /usr/bin/time -a -o "$times" -f "$which %e %U %S" "$bin" render "$scene" --out "$dir" -q
    done
    i=$((i + 1))
done
for which in A B; do
    if [ "$which" = A ]; then bin=$a; else bin=$b; fi
    grep "^$which " "$times" | awk '{ print $2, $3 + $4 }' | sort -g | awk -v name="$which ($bin)" '
        { wall[NR] = $1; cpu[NR] = $2 }
        END {
            if (NR == 0) exit 1
            m = (NR % 2) ? wall[(NR + 1) / 2] : (wall[NR / 2] + wall[NR / 2 + 1]) / 2
            # The CPU times in order of their own.
            for (i = 1; i <= NR; i++) c[i] = cpu[i]
            for (i = 2; i <= NR; i++) { v = c[i]; j = i - 1; while (j > 0 && c[j] > v) { c[j + 1] = c[j]; j-- } c[j + 1] = v }
            mc = (NR % 2) ? c[(NR + 1) / 2] : (c[NR / 2] + c[NR / 2 + 1]) / 2
            printf "%s: %d renders, wall median %.3f s (lowest %.3f), CPU median %.3f s (lowest %.3f)\n",
                name, NR, m, wall[1], mc, c[1]
        }'
done
