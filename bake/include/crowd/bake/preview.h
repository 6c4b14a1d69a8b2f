// A shaded still of a baked pack: the mesh skinned from the animation texture at one frame of
// one clip (the player's math), drawn with the deterministic rasterizer from the front.
#pragma once
#include <cstdint>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd {

// RGB8 pixels, size x size, row 0 at the top. Sub-meshes get distinct tints, lit from the
// camera side; the background is dark grey.
std::vector<uint8_t> renderPreview(const pack::AnimationPack &pack, size_t clip, uint32_t frame,
                                   int size);

} // namespace crowd
