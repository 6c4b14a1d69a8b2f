#!/usr/bin/env bash
# Test inputs from another real exporter: Debian's gltfpack (meshoptimizer 0.18) run with its
# defaults over two of the Blender exports. Its output quantizes positions, normals and UVs
# (KHR_mesh_quantization), undoes the UV quantization with KHR_texture_transform on each textured
# material, and reorders and welds vertices. The committed files are the tests' inputs; rerun
# this (apt-get install gltfpack) only to remake them.
set -euo pipefail
cd "$(dirname "$0")"
for name in trooper_cm morph_biped; do
  src=../blender/$name.glb
  [ -f "$src" ] || src=../blender/$name.gltf
  gltfpack -i "$src" -o "${name}_packed.glb"
done
