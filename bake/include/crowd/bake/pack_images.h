// Every image a pack holds, as crowdbake export --images writes them: each chunk's, through its
// codec in the chunk registry (so a registered chunk type's images come out with no other code),
// and for a pack with a skeleton a preview (the mesh skinned a quarter of the way into the first
// clip, seen from the front, one tint per sub-mesh).
#pragma once
#include <vector>

#include "crowd/formats/container.h"
#include "crowd/formats/registry.h"

namespace crowd {

// Throws crowd::Error naming the chunk for a type or version this build does not read.
std::vector<pack::Image> packImages(const pack::Reader &reader);

} // namespace crowd
