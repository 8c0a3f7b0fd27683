#!/bin/sh
# Takes docs/images/meshlab_subdivide.png (the filter's parameter dialog) and
# docs/images/meshlab_subdivide_result.png (after Apply), then docs/images/meshlab_cut.png
# and meshlab_cut_result.png (katachi: Cut by polyline on fandisk.off, the view taken from
# the 3D view, the cut's vertices selected) in MeshLab 2020.09 under Xvfb.
#
# Not part of `cargo xtask test`: it drives the GUI by screen coordinates (xdotool), which
# depend on MeshLab's layout at 1280x900. Needs the private prefix that
# `cargo xtask meshlab-plugin --test` makes, and the Debian packages xdotool and imagemagick
# (`cargo xtask deps` installs them).
#
#   tests/meshlab/screenshot.sh [TARGET_DIR]     (default: $CARGO_TARGET_DIR or ./target)
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
target=${1:-${CARGO_TARGET_DIR:-$root/target}}
prefix=$target/meshlab/prefix
model=$root/tests/data/models/fandisk_quads.off
for tool in xvfb-run xdotool import; do
    command -v $tool >/dev/null || { echo "screenshot.sh: $tool is missing (apt-get install xvfb xdotool imagemagick)" >&2; exit 1; }
done
[ -x "$prefix/bin/meshlabserver" ] || { echo "screenshot.sh: run cargo xtask meshlab-plugin --test first ($prefix)" >&2; exit 1; }
# The GUI, copied beside meshlabserver so it loads the prefix's plugins.
cp "$(command -v meshlab)" "$prefix/bin/meshlab"
mkdir -p "$root/docs/images"

# Opens the model $1 in MeshLab under Xvfb, then Filters > Remeshing, Simplification and
# Reconstruction, runs the xdotool/import steps $2 (a shell script; "$out" is docs/images)
# and closes MeshLab.
in_meshlab() {
    xvfb-run -a -s "-screen 0 1280x900x24" sh -c '
        "$1/bin/meshlab" "$2" >/dev/null 2>&1 &
        gui=$!
        sleep 10
        win=$(xdotool search --name MeshLab | tail -1)
        xdotool windowsize "$win" 1280 860 windowmove "$win" 0 0
        sleep 2
        xdotool mousemove 120 10 click 1      # Filters
        sleep 2
        xdotool mousemove 275 161 click 1     # Remeshing, Simplification and Reconstruction
        sleep 2
        out=$3
        eval "$4"
        kill $gui
    ' sh "$prefix" "$1" "$root/docs/images" "$2"
}

in_meshlab "$model" '
    xdotool mousemove 935 137 click 1     # katachi: Solid-aware subdivision
    sleep 3
    import -window root -crop 1280x860+0+0 "$out/meshlab_subdivide.png"
    xdotool mousemove 280 475 click 1     # Apply
    sleep 5
    import -window root -crop 1280x860+0+0 "$out/meshlab_subdivide_result.png"
'
echo "wrote $root/docs/images/meshlab_subdivide.png and meshlab_subdivide_result.png"

in_meshlab "$root/tests/data/models/fandisk.off" '
    xdotool mousemove 905 112 click 1     # katachi: Cut by polyline
    sleep 3
    xdotool mousemove 280 360 click 1     # Stroke
    xdotool type --delay 30 "150 400; 450 420; 750 400"
    sleep 1
    xdotool mousemove 340 520 click 1     # Apply (the view: the 3D view, by default)
    sleep 5
    import -window root -crop 1280x860+0+0 "$out/meshlab_cut.png"
    xdotool mousemove 118 520 click 1     # Close
    sleep 2
    import -window root -crop 860x760+0+70 "$out/meshlab_cut_result.png"
'
echo "wrote $root/docs/images/meshlab_cut.png and meshlab_cut_result.png"
