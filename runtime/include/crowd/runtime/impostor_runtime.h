// Run-time side of impostors, on the CPU: which stored view and frame shows a character from a
// direction at a clip time (impostor.vert does the same on the GPU), the distance past which an
// impostor texel is no bigger than a pixel, and the mip levels of a frame's atlases, built so
// that region ids are never averaged.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/impostor.h"

namespace crowd::runtime {

struct ImpostorChoice {
  uint32_t frame = 0;   // the frame shown (the atlas layer holding the view)
  uint32_t azimuth = 0; // the sampled direction nearest to the camera
  uint32_t elevation = 0;
  size_t view = 0;   // index into Impostor::views
  bool flip = false; // mirrored: draw the stored view flipped left-right
};

// `toEye`: from the character's sphere centre towards the camera, in the character's frame.
// `clipTime`: seconds since the clip's start (wrapped when `loop`).
ImpostorChoice chooseImpostorView(const pack::Impostor &m, glm::vec3 toEye, double clipTime,
                                  bool loop);

// Distance from the camera at which one texel of the impostor covers one pixel, for a
// perspective camera with vertical field of view `fovY` (radians) drawing `viewportHeight`
// pixels. Farther than this, an impostor shows at least as much detail as the screen can.
double oneToOneDistance(const pack::Impostor &m, double fovY, int viewportHeight);

// Mip chain of one frame's atlases (level 0 first: the stored blocks). A texel of level k+1 covers
// a 2x2 block of level k (fewer at an odd edge): it is covered when at least half of them are; its
// region is the most frequent region among them (ties: the lower id) and its normal and UV those
// of the first texel of that region, so no id and no UV across a seam is ever averaged. Levels
// past 0 are encoded to BC5 again, as the pack's planes are.
struct ImpostorMip {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> normals; // BC5 blocks, octahedral
  std::vector<uint8_t> regions; // region id + 1 per texel
  std::vector<uint8_t> uvs;     // BC5 blocks, empty without UVs
};
std::vector<ImpostorMip> impostorMips(const pack::Impostor &m, uint32_t frame, uint32_t levels);

// How many mip levels the player builds: at most 6, stopping where a level would mix whole views
// (half the smallest crop's shorter side).
uint32_t impostorMipLevels(const pack::Impostor &m);

} // namespace crowd::runtime
