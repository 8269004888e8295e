#!/usr/bin/env bash
# Builds dqkit and runs the main demo: the seeds' worked examples, then the character pipeline on
# real motion capture (CMU 01_01.bvh from Debian's assimp-testmodels): inspect it, forward
# kinematics of a few frames, and a conversion to another rotation order, checked by reading it
# back. Installs its Debian packages when missing.
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
