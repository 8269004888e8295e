#!/usr/bin/env bash
# Builds dqkit and runs the main demo: the seeds' worked examples, then the character pipeline on
# real motion capture (CMU 01_01.bvh from Debian's assimp-testmodels): inspect it, forward
# kinematics of a few frames, and a conversion to another rotation order, checked by reading it
# back. Then the seeds' demos (a few frames of each to PNG), a real character skinned three ways
# in one picture, and the slider puzzle to play in a window when there is a display. Installs its
# Debian packages when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j "$(nproc)" --target seed_walkthrough dqkit_cli
build/release/examples/seed_walkthrough

motion=/usr/share/assimp/models/BVH/01_01.bvh
tool=build/release/tools/dqkit
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo
echo "== The character pipeline on real motion capture: $motion"
"$tool" info "$motion" | head -12
echo "  ..."
echo
echo "== World transforms of frames 0 and 1000 (first joints)"
"$tool" fk "$motion" --frames 0,1000 | head -8
echo
echo "== Convert to ZXY rotation channels and read it back"
"$tool" convert "$motion" "$out/01_01_zxy.bvh" --rotation-order ZXY
"$tool" info "$out/01_01_zxy.bvh" | sed -n '7p'
"$tool" fk "$out/01_01_zxy.bvh" --frames 1000 | sed -n '2,3p'
echo
echo "== A skinned glTF model and an animated DirectX model, through the importer"
"$tool" info /usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf | head -6
"$tool" info /usr/share/assimp/models/X/BCN_Epileptic.X | head -6

echo
echo "== The seeds' demos, headless (docs/demos.md): the slider puzzle scrambled and solved, the"
echo "   thesis' four viewports, the biped following a target by IK"
cmake --build build/release -j "$(nproc)" --target dqkit_puzzle dqkit_viewports dqkit_biped
demos=build/demo-frames
rm -rf "$demos"
mkdir -p "$demos"
build/release/apps/dqkit-puzzle --headless --frames 12 --out "$demos/puzzle" --seed 3 --scramble 10 --solve \
  --export-x3d "$demos/puzzle_solved.x3d"
build/release/apps/dqkit-viewports --headless --frames 8 --out "$demos/viewports"
build/release/apps/dqkit-biped --headless --frames 8 --out "$demos/biped"
echo "The frames are PNG files in $(pwd)/$demos/{puzzle,viewports,biped}/frame_0000.png ..."

echo
echo "== Skinning a real animated character (DirectX BCN_Epileptic.X) at t = 1 s: linear blend (red),"
echo "   dual quaternions (blue) and centres of rotation (green), side by side (docs/skinning.md)"
"$tool" render /usr/share/assimp/models/X/BCN_Epileptic.X --time 1 --method all --width 1200 --height 400 \
  --out "$demos/skinning_lbs_dqs_cor.png" --force
echo "The picture is $(pwd)/$demos/skinning_lbs_dqs_cor.png"

echo
if [[ -z ${DISPLAY:-} ]]; then
  echo "No display (\$DISPLAY is not set): the slider puzzle is not started in a window."
  echo "On a desktop: build/release/apps/dqkit-puzzle (docs/demos.md)"
elif ! xdotool getdisplaygeometry >/dev/null 2>&1; then
  echo "The display $DISPLAY cannot be opened: the slider puzzle is not started in a window."
else
  echo "== The slider puzzle in a window on $DISPLAY: click a piece next to the hole to move it, drag to"
  echo "   turn the cube, S scramble, U undo, R redo, Space solve, Esc quit (docs/demos.md)"
  build/release/apps/dqkit-puzzle --seed 3 --scramble 6
fi
