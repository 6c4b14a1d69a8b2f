// An impostor's planes on the GPU, compactly (formats/impostor_spans.h), a layer per frame.
#pragma once
#include <array>
#include <cstdint>

#include "crowd/formats/impostor.h"
#include "crowd/runtime/impostor_runtime.h"

namespace crowd::runtime {

struct ImpostorGpu {
  uint32_t levels = 0;     // mip levels (impostorMipLevels)
  uint32_t regionBits = 8; // 4 or 8 (Impostor::regionBits)
  // The region ids in 32-bit words, the lower bits the left texel: frame f's level l starts at
  // word f * regionFrameWords + regionLevelWord[l], rows of regionRowWords[l] words.
  uint32_t regionFrameWords = 0;
  std::array<int32_t, kImpostorMaxMipLevels> regionLevelWord{}, regionRowWords{};
  uint32_t poolShift = 0; // a pool row holds 1 << poolShift blocks
  uint64_t bytes = 0;     // everything uploaded, every frame and level
};

// Uploads into `textures` (2D arrays, a layer per frame: the normal pool and the UV pool, every
// level's span blocks, level 0's first) and `buffers`: the views (3 vec4 each as impostor.vert
// reads them); the spans (uvec2 each: first one per (level, view) at level * views + view giving
// the index of the view's first row, then the rows: the pool block of the row's first stored
// block within the frame's layer, and its block column at that level); the region ids
// (ImpostorGpu's layout; a storage buffer, so the mip levels need no texture layout). Throws a
// clear error when a plane exceeds this GL's texture or storage-block size.
ImpostorGpu uploadImpostor(const pack::Impostor &m, const unsigned textures[2],
                           const unsigned buffers[3]);

} // namespace crowd::runtime
