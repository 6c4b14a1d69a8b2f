#include "crowd/formats/impostor_spans.h"

#include <algorithm>

namespace crowd::pack {

ImpostorSpans impostorSpans(std::span<const ImpostorView> views, std::span<const uint8_t> regions,
                            uint32_t width, uint32_t height, uint32_t level) {
  ImpostorSpans s;
  const uint32_t blocksWide = (width + 3) / 4;
  for (const ImpostorView &v : views) {
    s.viewRows.push_back(uint32_t(s.rows.size()));
    if (v.width == 0 || v.height == 0)
      continue;
    const uint32_t x0 = v.x >> level, x1 = std::min((v.x + v.width - 1u) >> level, width - 1);
    const uint32_t y0 = v.y >> level, y1 = std::min((v.y + v.height - 1u) >> level, height - 1);
    for (uint32_t by = y0 / 4; by <= y1 / 4; ++by) {
      uint32_t first = UINT32_MAX, last = 0;
      for (uint32_t y = std::max(by * 4, y0); y <= std::min(by * 4 + 3, y1); ++y)
        for (uint32_t x = x0; x <= x1; ++x)
          if (regions[size_t(y) * width + x]) {
            first = std::min(first, x / 4);
            last = std::max(last, x / 4);
          }
      ImpostorSpans::Row row;
      if (first != UINT32_MAX) {
        row = {uint32_t(s.sourceBlocks.size()), first};
        for (uint32_t bx = first; bx <= last; ++bx)
          s.sourceBlocks.push_back(by * blocksWide + bx);
      }
      s.rows.push_back(row);
    }
  }
  return s;
}

uint32_t regionRowBytes(uint32_t width, uint32_t regionBits) {
  return (width * regionBits + 31) / 32 * 4;
}

} // namespace crowd::pack
