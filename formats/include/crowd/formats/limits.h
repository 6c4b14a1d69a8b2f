// Every size limit of crowdbake and crowdplay, in one place: the decoders, the importer, the
// option checks and the scene loader read them from here. A limit is checked before anything is
// allocated or looped over for the count it bounds; raising one is a one-line change here (or,
// for the per-file byte bound, an option: --max-file-size).
#pragma once
#include <cstdint>

namespace crowd::limits {

// Input files (glTF, external buffers and images, manifests, scenes): the default byte bound,
// checked before a file is read. `--max-file-size` raises it.
inline constexpr uint64_t kInputFileBytes = uint64_t(1) << 30; // 1 GiB
// JSON nesting (glTF, manifests, scenes), checked before parsing. A glTF needs about 8 levels.
inline constexpr int kJsonDepth = 64;

// glTF contents.
inline constexpr uint64_t kAccessorElements = uint64_t(1) << 24; // per accessor
inline constexpr uint64_t kTriangles = uint64_t(1) << 22;        // per character, all primitives
inline constexpr uint64_t kVertices = uint64_t(1) << 22;         // per character
inline constexpr uint32_t kJoints = 65535;                       // joint ids are 16-bit
inline constexpr int kImageSide = 8192;                          // decoded diffuse texture
// Morph targets per character, and targets x vertices (dense offsets in the bake and the pack).
inline constexpr uint32_t kMorphTargets = 1024;
inline constexpr uint64_t kMorphOffsets = uint64_t(1) << 25;

// Animation bakes: frames per clip.
inline constexpr uint64_t kClipFrames = 65536; // 36 minutes at 30 fps
// Compressed joint tracks: samples per clip (the source's keys, kept as they are).
inline constexpr uint64_t kTrackSamples = uint64_t(1) << 22;

// Cloth caches (PC2, MDD): frames per cache; vertices per frame is kVertices. A cache is
// streamed, so its byte size is bounded only by the input byte bound.
inline constexpr uint32_t kCacheFrames = uint32_t(1) << 20;

// Impostor views sized from a switch distance (--texels auto): a nearer switch would need more
// texels than this per view; they are clamped here, with a warning (a texel then covers more
// than a pixel at the switch).
inline constexpr uint32_t kAutoImpostorTexels = 512;

// Terrain bakes: cells of an environment's grid (4096 x 4096: a 1 km square at 0.25 m), checked
// from the environment's extent and the cell size before any map is allocated.
inline constexpr uint64_t kTerrainCells = uint64_t(1) << 24;

// Packs: texture sides and element counts a chunk may declare, chunks per container.
inline constexpr uint32_t kTextureSide = 65536;
inline constexpr uint64_t kChunkElements = uint64_t(1) << 32;
inline constexpr uint32_t kChunks = 1024;

// The player: instances in a scene, window and screenshot sides.
inline constexpr uint64_t kInstances = 1000000;
inline constexpr int kScreenSide = 16384;

} // namespace crowd::limits
