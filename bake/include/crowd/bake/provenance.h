// Provenance of a bake: baker version, settings and a content hash of every input file.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd {

// In every cache key and pack: raise it (with the project's VERSION) whenever a bake's output
// changes for the same inputs and settings, or a build would take the older baker's parts from
// its cache. 0.1.1: outfit copies of partly covered body parts survive LOD. 0.2.0: impostor
// atlases in BC5 blocks and region bytes (IMPO version 3). 0.2.1: the rasterizer gives a pixel on
// an edge two triangles share to exactly one of them (it could fall between both). 0.3.0: the
// LOD collapses on flat arrays, non-manifold vertices split per fan, its cost the worst pose's
// (another collapse order), flat-shaded copies welded (normals stored as zero). 0.4.0: impostor
// planes fitted to the silhouette and tilted (IMPO version 4). 0.5.0: unclothed packs keep each
// sub-mesh's material colour and texture flag (LOOK); every skin a mesh uses is baked, not the
// largest alone. 0.6.0: the LOD costs its rest pose as drawn (an armature's scale and rigid parts'
// nodes applied), not in the mesh's own units. 0.7.0: the LOD weights border and seam planes as
// faces and counts costs below rounding's as 0 (another collapse order). 0.8.0: the LOD queues
// each candidate at its rest-pose bound and costs it over the poses when that comes up (ties
// within a bucket of the queue pop in another order). 0.8.1: the LOD's free collapses queue by
// the octave of their edge's length, shortest first (they all went last pushed first). 0.8.2:
// triangles under a mirroring node are turned round to face out as drawn (they faced in).
inline constexpr const char *kBakerVersion = "crowdbake 0.8.2";

// The compiler and C library this crowdbake was built with and runs on: floats may round
// differently under another, so byte-identical goldens hold only on the same toolchain
// (tests/golden/toolchain.txt; elsewhere they are checked with crowdbake diff's tolerances).
std::string toolchain();

} // namespace crowd
