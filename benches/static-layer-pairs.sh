#!/bin/sh
# The static-layer target of issue #6, measured in alternating pairs: renders
# scenes/bench/circles-1000.toml and circles-1000-field.toml (the same circles over
# axes and 500 arrows) one after the other, N times, and prints the median and the
# quartiles of the ratio of their frames per second (1.03 means the layer adds 3% to
# the frame time). Pairs cancel most of the drift of a shared machine.
#
#   cargo build --release && sh benches/static-layer-pairs.sh [N] [OUT_DIR]
#
# N defaults to 21; OUT_DIR (default /dev/shm, memory, so that no disk is in the way)
# receives the frames of the last pair. Run from the repository's top folder.
set -eu
n=${1:-21}
out=${2:-/dev/shm}
bin=${PHYSFRAMES:-target/release/physframes}
i=0
while [ "$i" -lt "$n" ]; do
    "$bin" bench scenes/bench/circles-1000.toml scenes/bench/circles-1000-field.toml \
        --repeat 1 --out "$out" | tail -n 2 | awk '{ print $4 }' | paste -sd' ' -
    i=$((i + 1))
done | awk '{ print $1 / $2 }' | sort -g | awk '
    { r[NR] = $1 }
    END {
        if (NR == 0) exit 1
        m = (NR % 2) ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2
        printf "pairs %d: frame time with the layer / without: median %.3f, quartiles %.3f and %.3f, range %.3f to %.3f\n",
            NR, m, r[int((NR + 3) / 4)], r[int((3 * NR + 3) / 4)], r[1], r[NR]
    }'
