#!/bin/sh
# Writes the benchmark scenes of bodies written one `[[body]]` table each, as a user
# writes them (issue #16): the same moving discs as circles-1000.toml, but in the
# default colour cycle, and variants with 10,000 bodies, velocity arrows, trails, mixed
# shapes, turning boxes, shapes of their own sizes with trails, and springs shown as
# coils, scattered and in a cloth; and two contact scenes, mixed shapes on a ramp and
# a pour of turning polygons into a bucket. Run from the repository's root:
#   sh scenes/bench/make-scenes.sh
# The numbers come from a Park-Miller generator (x <- 16807·x mod 2^31 - 1, exact in
# awk's doubles) and are printed with 4 decimals, so every run writes the same files.
set -eu
cd "$(dirname "$0")"

# header NAME TITLE DURATION [EXTRA-RENDER-LINE]
header() {
    cat <<HEAD
# Benchmark (issue #16): $2
# Written by scenes/bench/make-scenes.sh; \`physframes bench\` prints its frame rate and
# its ratio to circles-1000.toml measured in the same run.
name = "$1"

[simulation]
duration = $3
# dt defaults to 1/(10·fps)

[render]
width = 1280
height = 720
fps = 30
view = { min = [0.0, 0.0], max = [16.0, 9.0] }
HEAD
    if [ $# -ge 4 ]; then printf '%s\n' "$4"; fi
    printf '\n'
}

footer() {
    cat <<FOOT
[[force]]
kind = "drag"            # F = -k·v: the bodies slow down a little
k = 0.05
FOOT
}

# bodies COUNT SEED KIND [RADIUS]: COUNT [[body]] tables; KIND is circles, arrows, mixed,
# sizes, crates, dumbbells, spinning-dumbbells, turning, turning-sizes or trails-sizes; circles and arrows have RADIUS (0.06 unless given).
bodies() {
    awk -v n="$1" -v seed="$2" -v kind="$3" -v radius="${4:-0.06}" '
    function rnd() { x = (x * 16807) % 2147483647; return x / 2147483647 }
    function uniform(a, b) { return a + (b - a) * rnd() }
    BEGIN {
        x = seed
        for (i = 0; i < n; i++) {
            px = uniform(0.5, 15.5); py = uniform(0.5, 8.5)
            vx = uniform(-0.3, 0.3); vy = uniform(-0.3, 0.3)
            printf "[[body]]\n"
            if (kind != "dumbbells" && kind != "spinning-dumbbells") printf "mass = 1.0\n"
            printf "position = [%.4f, %.4f]\nvelocity = [%.4f, %.4f]\n", px, py, vx, vy
            if (kind == "circles" || kind == "arrows") {
                printf "shape = { circle = { radius = %s } }\n", radius
                if (kind == "arrows") print "show_velocity = true"
            } else if (kind == "mixed") {
                # Circles, boxes, triangles and pentagons of two sizes each, in an order
                # that does not repeat with the colour cycle.
                k = int(8 * rnd())
                s = (k % 2 == 0) ? 1.0 : 1.5
                if (k < 2) printf "shape = { circle = { radius = %.4f } }\n", 0.05 * s
                else if (k < 4) printf "shape = { box = { width = %.4f, height = %.4f } }\n", 0.12 * s, 0.08 * s
                else if (k < 6) printf "shape = { polygon = { points = [[%.4f, %.4f], [%.4f, %.4f], [0.0, %.4f]] } }\n", -0.07 * s, -0.05 * s, 0.07 * s, -0.05 * s, 0.07 * s
                else {
                    printf "shape = { polygon = { points = ["
                    for (j = 0; j < 5; j++) {
                        a = 6.283185307179586 * j / 5 + 1.5707963267948966
                        printf "%s[%.4f, %.4f]", (j ? ", " : ""), 0.06 * s * cos(a), 0.06 * s * sin(a)
                    }
                    printf "] } }\n"
                }
            } else if (kind == "sizes") {
                # Every body a size of its own, as when a user scatters balls and
                # crates of many sizes: discs of radii 0.03 to 0.1, and boxes of their
                # own widths and heights, each at a fixed angle of its own.
                if (rnd() < 0.5) printf "shape = { circle = { radius = %.4f } }\n", uniform(0.03, 0.1)
                else {
                    printf "angle = %.4f\n", uniform(-3.1416, 3.1416)
                    printf "shape = { box = { width = %.4f, height = %.4f } }\n", uniform(0.08, 0.2), uniform(0.05, 0.15)
                }
            } else if (kind == "crates") {
                # Boxes of one size and L shapes of one size, none turning, each at a
                # fixed angle of its own.
                printf "angle = %.4f\n", uniform(-3.1416, 3.1416)
                if (rnd() < 0.5) print "shape = { box = { width = 0.16, height = 0.08 } }"
                else print "shape = { polygon = { points = [[-0.08, -0.08], [0.08, -0.08], [0.08, -0.03], [-0.03, -0.03], [-0.03, 0.08], [-0.08, 0.08]] } }"
            } else if (kind == "dumbbells") {
                # A body of two point masses (Equations 7-11 of the article) instead of
                # mass and shape; the mass printed above is replaced by its points.
                print "points = [{ offset = [-0.05, 0.0], mass = 1.0 }, { offset = [0.05, 0.0], mass = 2.0 }]"
            } else if (kind == "spinning-dumbbells") {
                # The same bodies, each turning at its own rate from its own angle.
                printf "angle = %.4f\nangular_velocity = %.4f\n", uniform(-3.1416, 3.1416), uniform(-2.0, 2.0)
                print "points = [{ offset = [-0.05, 0.0], mass = 1.0 }, { offset = [0.05, 0.0], mass = 2.0 }]"
            } else if (kind == "turning") {
                printf "angle = %.4f\nangular_velocity = %.4f\n", uniform(-3.1416, 3.1416), uniform(-2.0, 2.0)
                print "shape = { box = { width = 0.16, height = 0.08 } }"
            } else if (kind == "trails-sizes") {
                # Discs, boxes and triangles, each of its own size, half of them
                # turning from an angle of their own, as a user scatters shapes, to
                # be drawn with trails (none is stamped but the discs, from sprites
                # of snapped radii).
                k = rnd()
                if (rnd() < 0.5) printf "angle = %.4f\nangular_velocity = %.4f\n", uniform(-3.1416, 3.1416), uniform(-2.0, 2.0)
                if (k < 0.4) printf "shape = { circle = { radius = %.4f } }\n", uniform(0.04, 0.09)
                else if (k < 0.7) printf "shape = { box = { width = %.4f, height = %.4f } }\n", uniform(0.08, 0.2), uniform(0.06, 0.15)
                else printf "shape = { polygon = { points = [[-0.06, -0.04], [0.07, -0.05], [0.0, %.4f]] } }\n", uniform(0.05, 0.1)
            } else if (kind == "turning-sizes") {
                # The turning boxes of turning-boxes-1000, each of its own width and
                # height (as when a user scatters crates of many sizes): none shares a
                # geometry, so none is stamped.
                printf "angle = %.4f\nangular_velocity = %.4f\n", uniform(-3.1416, 3.1416), uniform(-2.0, 2.0)
                printf "shape = { box = { width = %.4f, height = %.4f } }\n", uniform(0.1, 0.22), uniform(0.06, 0.12)
            }
        }
    }'
    printf '\n'
}

{
    header bodies-1000 "1000 moving discs, one [[body]] table each, in the default colour cycle." 10.0
    bodies 1000 7 circles
    footer
} >bodies-1000.toml

{
    header bodies-10000 "the 10,000 moving discs of circles-10000.toml (radius 0.03), one [[body]] table each, in the default colour cycle." 10.0
    bodies 10000 11 circles 0.03
    footer
} >bodies-10000.toml

{
    header arrows-1000 "1000 moving discs in the default colours, each showing its velocity arrow." 10.0
    bodies 1000 13 arrows
    footer
} >arrows-1000.toml

{
    header trails-1000 "1000 moving discs in the default colours with trails, 1201 frames." 40.0 "trails = true"
    bodies 1000 17 circles
    footer
} >trails-1000.toml

{
    header mixed-1000 "1000 circles, boxes, triangles and pentagons of two sizes each, in the default colours." 10.0
    bodies 1000 19 mixed
    footer
} >mixed-1000.toml

{
    header sizes-1000 "1000 discs and boxes in the default colours, no two of one size, each box at a fixed angle of its own." 10.0
    bodies 1000 31 sizes
    footer
} >sizes-1000.toml

{
    header crates-1000 "1000 boxes and L shapes of one size each in the default colours, none turning, each at a fixed angle of its own." 10.0
    bodies 1000 37 crates
    footer
} >crates-1000.toml

{
    header dumbbells-1000 "1000 bodies of two point masses each, alike, in the default colours." 10.0
    bodies 1000 41 dumbbells
    footer
} >dumbbells-1000.toml

{
    header spinning-dumbbells-1000 "1000 bodies of two point masses each, alike, in the default colours, each turning at its own rate from its own angle." 10.0
    bodies 1000 43 spinning-dumbbells
    footer
} >spinning-dumbbells-1000.toml

{
    header turning-boxes-1000 "1000 boxes in the default colours, each turning at its own rate from its own angle." 10.0
    bodies 1000 23 turning
    footer
} >turning-boxes-1000.toml

{
    header turning-sizes-1000 "1000 boxes in the default colours, each of its own width and height, turning at its own rate from its own angle." 10.0
    bodies 1000 53 turning-sizes
    footer
} >turning-sizes-1000.toml

{
    header trails-sizes-1000 "1000 discs, boxes and triangles in the default colours with trails, each of its own size, half of them turning, 601 frames." 20.0 "trails = true"
    bodies 1000 59 trails-sizes
    footer
} >trails-sizes-1000.toml

# springs COUNT: COUNT springs shown as coils, each joining unnamed body 2k to body 2k + 1
# (named body0, body1, ... by their order): scattered at random, so the coils start
# long, most of them across a good part of the view, and shorten as the springs pull.
springs() {
    awk -v n="$1" 'BEGIN {
        for (k = 0; k < n; k++)
            printf "[[force]]\nkind = \"spring\"\na = \"body%d\"\nb = \"body%d\"\nstiffness = 0.5\nrest_length = 0.3\n\n", 2 * k, 2 * k + 1
    }'
}

{
    header springs-300 "1000 moving discs in the default colours, 300 pairs of them joined by springs shown as coils, long at the start." 10.0 "show_springs = true"
    bodies 1000 47 circles
    springs 300
    footer
} >springs-300.toml

# cloth COLUMNS ROWS SEED: a grid of COLUMNS x ROWS discs in the default colours, 0.38
# apart across and 0.33 up, each with a small velocity of its own, every one joined to
# its neighbours to the left and below by springs at their rest lengths, shown as
# coils: a cloth, the way a user builds a soft body, with short coils everywhere.
cloth() {
    awk -v cols="$1" -v rows="$2" -v seed="$3" '
    function rnd() { x = (x * 16807) % 2147483647; return x / 2147483647 }
    function uniform(a, b) { return a + (b - a) * rnd() }
    BEGIN {
        x = seed
        for (i = 0; i < cols; i++)
            for (j = 0; j < rows; j++) {
                printf "[[body]]\nname = \"n%d_%d\"\nmass = 1.0\n", i, j
                printf "position = [%.4f, %.4f]\n", 0.5 + 0.38 * i, 0.5 + 0.33 * j
                printf "velocity = [%.4f, %.4f]\n", uniform(-0.3, 0.3), uniform(-0.3, 0.3)
                print "shape = { circle = { radius = 0.04 } }"
            }
        printf "\n"
        for (i = 0; i < cols; i++)
            for (j = 0; j < rows; j++) {
                if (i > 0) printf "[[force]]\nkind = \"spring\"\na = \"n%d_%d\"\nb = \"n%d_%d\"\nstiffness = 5.0\nrest_length = 0.38\n\n", i, j, i - 1, j
                if (j > 0) printf "[[force]]\nkind = \"spring\"\na = \"n%d_%d\"\nb = \"n%d_%d\"\nstiffness = 5.0\nrest_length = 0.33\n\n", i, j, i, j - 1
            }
    }'
}

{
    header cloth-1000 "a cloth of 40 x 25 discs in the default colours joined to their neighbours by 1935 springs shown as coils." 10.0 "show_springs = true"
    cloth 40 25 61
    footer
} >cloth-1000.toml

# mixed_contacts COUNT SEED: COUNT circles, boxes and triangles in a grid above a tilted
# static ramp and a static floor, each at its own angle with a small velocity, arrows on
# every fifth body; the colliding bodies' [[body]] tables only (issue #16's style).
mixed_contacts() {
    awk -v n="$1" -v seed="$2" '
    function rnd() { x = (x * 16807) % 2147483647; return x / 2147483647 }
    function uniform(a, b) { return a + (b - a) * rnd() }
    BEGIN {
        x = seed
        cols = 25
        for (i = 0; i < n; i++) {
            # A grid 25 wide, 0.56 apart, from 2.9 up: no two bodies (at most 0.3
            # across) touch at the start, and the lowest row is above the ramp.
            px = 1.2 + 0.56 * (i % cols) + uniform(-0.05, 0.05)
            py = 2.9 + 0.5 * int(i / cols) + uniform(-0.05, 0.05)
            vx = uniform(-0.5, 0.5); vy = uniform(-0.5, 0.5)
            printf "[[body]]\n"
            if (kind != "dumbbells") printf "mass = 1.0\n"
            printf "position = [%.4f, %.4f]\nvelocity = [%.4f, %.4f]\n", px, py, vx, vy
            k = int(3 * rnd())
            if (k == 0) print "shape = { circle = { radius = 0.1 } }"
            else {
                printf "angle = %.4f\n", uniform(-3.1416, 3.1416)
                if (k == 1) print "shape = { box = { width = 0.24, height = 0.16 } }"
                else print "shape = { polygon = { points = [[-0.12, -0.08], [0.12, -0.08], [0.0, 0.13]] } }"
            }
            if (i % 5 == 0) print "show_velocity = true"
        }
    }'
    printf '\n'
}

{
    cat <<'HEAD'
# Benchmark: 300 circles, boxes and triangles, one [[body]] table each in the default
# colours, dropped onto a tilted static ramp and a static floor under gravity, with
# friction 0.5 and restitution 0.3, trails, and velocity arrows on every fifth body, at
# dt = 1/240 s: a scene written as a user writes it whose time goes to the contacts
# (the times of impact of resting bodies that turn). Written by
# scenes/bench/make-scenes.sh. Bench it with
#   physframes bench scenes/bench/mixed-contacts-300.toml --simulate-only --repeat 3
#   physframes bench scenes/bench/mixed-contacts-300.toml --repeat 3
name = "mixed-contacts-300"

[simulation]
dt = 0.004166666666666667   # 1/240 s
duration = 5.0

[render]
width = 1280
height = 720
fps = 30
view = { min = [0.0, -0.5], max = [16.0, 8.5] }
trails = true

[contacts]
friction = 0.5
restitution = 0.3

[[force]]
kind = "gravity"

[[body]]
name = "floor"
static = true
position = [8.0, -0.2]
shape = { box = { width = 20.0, height = 0.4 } }

[[body]]
name = "ramp"
static = true
position = [4.0, 1.5]
angle = -0.3
shape = { box = { width = 6.0, height = 0.2 } }

HEAD
    mixed_contacts 300 29
} >mixed-contacts-300.toml

# polygon_pour N SEED: N bodies of six shapes (discs, boxes, triangles, pentagons,
# hexagons and octagons), each of its own size, angle and spin, on a grid 16 wide and
# 0.36 apart (no two touch at the start: the largest reaches 0.171 from its centre).
polygon_pour() {
    awk -v n="$1" -v seed="$2" '
    function rnd() { x = (x * 16807) % 2147483647; return x / 2147483647 }
    function uniform(a, b) { return a + (b - a) * rnd() }
    BEGIN {
        x = seed
        pi = 3.141592653589793
        for (i = 0; i < n; i++) {
            px = -2.7 + 0.36 * (i % 16) + uniform(-0.01, 0.01)
            py = 0.4 + 0.36 * int(i / 16) + uniform(-0.01, 0.01)
            printf "[[body]]\nmass = %.1f\n", 1 + int(2 * rnd())
            printf "position = [%.4f, %.4f]\nvelocity = [%.4f, %.4f]\n", px, py, uniform(-0.5, 0.5), uniform(-1, 0)
            printf "angle = %.4f\nangular_velocity = %.4f\n", uniform(0, 6.2832), uniform(-2, 2)
            k = int(6 * rnd()); s = uniform(0.08, 0.14)
            if (k == 0) printf "shape = { circle = { radius = %.4f } }\n", s
            else if (k == 1) printf "shape = { box = { width = %.4f, height = %.4f } }\n", 2 * s, 1.4 * s
            else if (k == 2) printf "shape = { polygon = { points = [[%.4f, %.4f], [%.4f, %.4f], [0.0, %.4f]] } }\n", -s, -0.6 * s, s, -0.6 * s, s
            else {
                m = (k == 3) ? 5 : (k == 4) ? 6 : 8
                printf "shape = { polygon = { points = ["
                for (j = 0; j < m; j++) {
                    if (j > 0) printf ", "
                    printf "[%.4f, %.4f]", s * cos(2 * pi * j / m), s * sin(2 * pi * j / m)
                }
                printf "] } }\n"
            }
        }
    }'
    printf '\n'
}

{
    cat <<'HEAD'
# Benchmark: 400 discs, boxes, triangles and regular polygons of five to eight sides,
# one [[body]] table each in the default colours, each of its own size, angle and
# spin, poured into a bucket of three static walls under gravity (friction 0.4,
# restitution 0.2, dt = 1/240 s): a pile of turning polygons, whose time goes to the
# times of impact of polygons in contact (parry's GJK and EPA), which the bench's
# other scenes (discs, and boxes' closed forms) barely meet. Written by
# scenes/bench/make-scenes.sh. Bench it with
#   physframes bench scenes/bench/polygon-pour-400.toml --simulate-only --repeat 3
name = "polygon-pour-400"

[simulation]
dt = 0.004166666666666667   # 1/240 s
duration = 3.0

[render]
width = 800
height = 800
fps = 30
view = { min = [-3.6, -0.6], max = [3.6, 12.6] }

[contacts]
friction = 0.4
restitution = 0.2

[[force]]
kind = "gravity"

[[body]]
name = "bottom"
static = true
position = [0.0, -0.25]
shape = { box = { width = 7.0, height = 0.5 } }
color = "#555555"

[[body]]
name = "left"
static = true
position = [-3.25, 6.0]
shape = { box = { width = 0.5, height = 12.0 } }
color = "#555555"

[[body]]
name = "right"
static = true
position = [3.25, 6.0]
shape = { box = { width = 0.5, height = 12.0 } }
color = "#555555"

HEAD
    polygon_pour 400 41
} >polygon-pour-400.toml
