#!/usr/bin/env bash
# Makes the README's gallery: small PNGs of physframes' own frames and figures.
# Run from the repository root:  docs/gallery/make.sh
# Every image is made by a physframes command from a scene in scenes/; to add one, add
# a line below and a row to the gallery table in README.md.
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet
pf=target/release/physframes
out=docs/gallery
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The article's Figure 3: the drag equation's slope field with Euler's steps.
$pf figure drag-field --size 480x360 --out "$out/figure-3.png" --quiet
# Two gear-shaped polygons spun up by torques against angular drag (frame 150 of 300).
$pf figure scenes/gears.toml --size 480x307 --frame 150 --out "$out/gears.png" --quiet
# A box hanging by a spring at its corner, with its trail (frame 200).
$pf figure scenes/pendulum.toml --size 400x320 --frame 200 --out "$out/pendulum.png" --quiet
# Error against run time for every integrator on the hanging box.
$pf study work-precision --problem hanging-box --levels 6 --samples 3 --out "$tmp/wp" --quiet
cp "$tmp/wp/work-precision.png" "$out/work-precision.png"
# An animated preview: the spin-up of a box and a disc, at 10 frames per second.
$pf render scenes/spin.toml --set render.width=256 --set render.height=144 \
    --set render.fps=10 --out "$tmp/spin" --apng "$out/spin.png" --quiet
# A break shot: balls and cushions colliding, seen from above (frame 12 of 100).
$pf figure scenes/billiards.toml --size 480x270 --frame 12 --out "$out/billiards.png" --quiet
ls -l "$out"
