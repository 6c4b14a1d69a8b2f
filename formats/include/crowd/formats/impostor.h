// The impostor chunk: for each sampled frame of a clip, views of the character from azimuths x
// elevations over the upper hemisphere, each cropped to its silhouette and packed into one atlas
// per frame. Three planes of the same layout, stored as the GPU reads them: the object-space
// normal, octahedral, in BC5 blocks; the region id + 1 (0: empty), a byte per texel, exact; and,
// when the mesh has UVs, the UVs (wrapped into 0..1) in BC5 blocks. Each view has a
// best plane that the player draws it on, blending the three views around the camera. On disk a
// block with no covered texel is not stored (it reads zero); on the GPU the region ids take 4 bits
// where they fit and the blocks only each view's covered spans (impostor_spans.h).
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd::pack {

inline constexpr uint32_t kImpostor = fourcc("IMPO");
// 1: no outfit; 2: RGBA8 + RGBA16 atlases; 3: planes face the view (no slopes)
inline constexpr uint32_t kImpostorVersion = 4;

struct ImpostorView {
  uint16_t x = 0, y = 0, width = 0, height = 0; // crop rectangle in the frame's atlas (texels)
  float pivotX = 0, pivotY = 0; // the sphere centre's position in the crop, texels from its corner
  // Best impostor plane, fitted to the silhouette's texels (their depth, least absolute
  // distance), where parallax moves the outline between views: in the view's frame (x right, y
  // up, z towards the camera, model units from the sphere centre) z = planeOffset + slopeX x +
  // slopeY y. A vertical figure seen from above has slopeY near tan(elevation).
  float planeOffset = 0;
  float slopeX = 0, slopeY = 0; // |slope| <= kMaxPlaneSlope; 0 before chunk version 4
};
inline constexpr float kMaxPlaneSlope = 8; // about 83 degrees from facing the view

struct Impostor {
  std::string clip;
  std::string outfit; // the outfit worn ("" for the body as baked); chunk version 2 on

  float startTime = 0, frameStep = 0; // frame f shows clip time startTime + f * frameStep
  uint32_t frames = 0, azimuths = 0, elevations = 0;
  uint32_t texels = 0; // a full view is texels x texels before cropping
  // Mirrored: only azimuths 0..A/2 are stored; the view from azimuth a > A/2 at frame f is the
  // stored view from A - a at frame f + frames/2, flipped left-right (normal x negated).
  bool mirrored = false;
  std::array<float, 4> sphere{};            // the volume every view frames: centre xyz, radius
  uint32_t atlasWidth = 0, atlasHeight = 0; // every frame's atlas; multiples of 4 (whole blocks)
  // Frame-major, then elevation, then azimuth (stored ones only): see viewIndex.
  // Azimuth a looks from angle 2 pi a / azimuths about +Y (0: from +Z); elevation e from
  // 90 (e + 0.5) / elevations degrees above the horizon.
  std::vector<ImpostorView> views;
  // Frame-major planes (see the top): frames * bc5Bytes(atlasWidth, atlasHeight) bytes of
  // normals, frames * atlasWidth * atlasHeight region bytes, and the UVs as the normals (empty
  // when the mesh has none).
  std::vector<uint8_t> normals, regions, uvs;
  size_t frameTexels() const { return size_t(atlasWidth) * atlasHeight; }
  // One frame's planes at full detail as the GPU holds them (impostor_spans.h), the mean over
  // frames: the region plane, the spans' blocks and their index.
  uint64_t bytesPerFrame() const;
  uint32_t regionBits() const; // on the GPU: 4 when every region id + 1 is at most 15, else 8
  uint32_t storedAzimuths() const { return mirrored ? azimuths / 2 + 1 : azimuths; }
  // Index of a stored view (a < storedAzimuths()).
  size_t viewIndex(uint32_t f, uint32_t e, uint32_t a) const {
    return (size_t(f) * elevations + e) * storedAzimuths() + a;
  }
  // The stored view that shows frame f from (e, a), and whether to flip it left-right.
  std::pair<size_t, bool> lookup(uint32_t f, uint32_t e, uint32_t a) const {
    if (!mirrored || a <= azimuths / 2)
      return {viewIndex(f, e, a), false};
    return {viewIndex((f + frames / 2) % frames, e, azimuths - a), true};
  }
};

// A unit normal as two octahedral coordinates in 0..1, and back (normalized).
std::array<float, 2> octEncode(const std::array<float, 3> &n);
std::array<float, 3> octDecode(float x, float y);

// One frame's planes decoded as the GPU samples them.
struct ImpostorTexels {
  uint32_t width = 0, height = 0;
  std::vector<float> oct;           // 2 per texel: the normal, octahedral (octDecode)
  std::vector<float> uv;            // 2 per texel, 0..1; empty without UVs
  std::span<const uint8_t> regions; // region id + 1 per texel, into the impostor's plane
  std::array<float, 3> normal(size_t texel) const {
    return octDecode(oct[texel * 2], oct[texel * 2 + 1]);
  }
};
ImpostorTexels decodeTexels(const Impostor &, uint32_t frame);

std::vector<uint8_t> encode(const Impostor &);
Impostor decodeImpostor(std::span<const uint8_t>, uint32_t version, const std::string &context);

struct ImpostorPack {
  Provenance provenance;
  Impostor impostor;
};
ImpostorPack loadImpostorPack(const Reader &reader);
std::vector<uint8_t> packBytes(const ImpostorPack &pack);

} // namespace crowd::pack
