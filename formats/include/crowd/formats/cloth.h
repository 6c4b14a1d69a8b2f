// The cloth-loop chunk: one looped garment of an outfit over one body clip (crowdbake cloth).
// The loop's frames are the garment's vertex positions in the body's root frame (the skeleton's
// top joint at the clip time of each frame), quantised to 16 bits per axis over the loop's box:
// position = origin + q x step. Frame f of the loop plays at clip time f / fps, wrapping every
// `cycles` clip cycles, so the garment loops in phase with the body.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd::pack {

inline constexpr uint32_t kCloth = fourcc("CLTH");
inline constexpr uint32_t kClothVersion = 1;

struct ClothLoop {
  std::string outfit, garment, clip;
  float fps = 0;                 // the cache's frame rate
  uint32_t cycles = 0;           // body-clip cycles the loop spans
  uint32_t cacheStart = 0;       // the cache frame the loop starts at
  uint32_t blendFrames = 0;      // frames cross-faded before the seam (0: a hard cut)
  std::array<float, 3> origin{}; // the box the positions are quantised over
  std::array<float, 3> step{};
  // The garment's vertices in the cache's order: where the outfit glTF has them (file 0, its
  // own). A character pack numbers an outfit's file by its place in the outfit table, plus 1.
  SourceMap sources;
  std::vector<uint16_t> positions; // frame-major: frames x vertices x xyz
  uint32_t vertexCount() const { return uint32_t(sources.vertexCount()); }
  uint32_t frameCount() const;
  std::array<float, 3> position(uint32_t frame, uint32_t vertex) const;
};

std::vector<uint8_t> encode(const ClothLoop &);
ClothLoop decodeClothLoop(std::span<const uint8_t> bytes, const std::string &context);

// Per mesh vertex of `body`: the loop vertex it plays (the one of the same source vertex of the
// loop's outfit), or -1. Throws crowd::Error, prefixed by `context`, when the body has no vertex
// sources or outfit table, or when a loop vertex matches no mesh vertex (a loop of another
// outfit file).
std::vector<int32_t> clothVertexOf(const AnimationPack &body, const ClothLoop &loop,
                                   const std::string &context);

} // namespace crowd::pack
