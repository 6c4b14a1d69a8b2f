// How the player holds an impostor frame on the GPU, compactly. The region plane stays a full
// atlas, since coverage is read there first, but at 4 bits a texel when every id + 1 fits. The
// normal and UV planes keep only, per view and per row of 4x4 blocks, the run of blocks from the
// first to the last one holding a covered texel of that view's crop: a "pool" of BC5 blocks, each
// copied as stored. The player reads a covered texel's normal and UV through its row's span; it
// never reads an empty texel's. On the sample humanoid's walk (128 texels, mirrored) the spans hold
// 47% of the atlas's blocks.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "crowd/formats/impostor.h"

namespace crowd::pack {

struct ImpostorSpans {
  struct Row {
    uint32_t start = 0;       // pool index of the row's first stored block
    uint32_t firstColumn = 0; // that block's column in the atlas (blocks)
  };
  // Per view: the index in `rows` of its crop's first block row; its rows follow in order, one per
  // block row the crop touches (an empty row is stored too, reads nothing and holds no block).
  std::vector<uint32_t> viewRows;
  std::vector<Row> rows;
  // Per stored block, in pool order: its index in the atlas's blocks (row-major).
  std::vector<uint32_t> sourceBlocks;
};

// The spans of one frame's atlas at a mip level: `regions` is that level's plane (width x height,
// region id + 1 per texel); each view's crop at level l covers the texels its level-0 crop's
// corners fall into (coordinates shifted right by l), as impostor.frag reads them.
ImpostorSpans impostorSpans(std::span<const ImpostorView> views, std::span<const uint8_t> regions,
                            uint32_t width, uint32_t height, uint32_t level);

// Bytes of one row of a region plane `width` texels wide as the GPU holds it: `regionBits` (4 or
// 8) a texel, in whole 32-bit words.
uint32_t regionRowBytes(uint32_t width, uint32_t regionBits);

} // namespace crowd::pack
