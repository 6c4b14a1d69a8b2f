// An impostor's planes on the GPU, compactly (formats/impostor_spans.h), a layer per frame.
#pragma once
#include <array>
#include <cstdint>

#include "crowd/formats/impostor.h"

namespace crowd::runtime {

inline constexpr uint32_t kImpostorMaxLevels = 6; // impostorMipLevels' limit

struct ImpostorGpu {
  uint32_t levels = 0;     // mip levels (impostorMipLevels)
  uint32_t regionBits = 8; // 4: two texels a byte, the lower nibble the even column
  // Each level's region plane in its frame's layer: level 0 at the corner, the others in a row
  // below it (columns in bytes, rows), so one gather reads a texel's 2x2 at any level.
  std::array<std::array<int32_t, 2>, kImpostorMaxLevels> regionOrigin{};
  uint32_t poolShift = 0; // a pool row holds 1 << poolShift blocks
  uint64_t bytes = 0;     // everything uploaded, every frame and level
};

// Uploads into `textures` (2D arrays: normal pool, UV pool, region planes) and `buffers` (views:
// 3 vec4 each as impostor.vert reads them; spans: uvec2 each, first one per (level, view) at
// level * views + view giving the index of the view's first row, then the rows (pool block of
// the row's first stored block within the frame's layer, its block column at that level)). Each
// level's blocks follow the level before's in a frame's layer. Throws a clear error when a pool
// would exceed this GL's texture size.
ImpostorGpu uploadImpostor(const pack::Impostor &m, const unsigned textures[3],
                           const unsigned buffers[2]);

} // namespace crowd::runtime
