// The impostor chunk: for each sampled frame of a clip, views of the character from azimuths x
// elevations over the upper hemisphere, each cropped to its silhouette and packed into one atlas
// per frame. Texels: RGB the object-space normal (n * 0.5 + 0.5), A the region id + 1 (0: empty);
// and, when the mesh has UVs, a second atlas of the same layout with 16-bit UVs and the region.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd::pack {

inline constexpr uint32_t kImpostor = fourcc("IMPO");
inline constexpr uint32_t kImpostorVersion = 2; // 1: no outfit field

struct ImpostorView {
  uint16_t x = 0, y = 0, width = 0, height = 0; // crop rectangle in the frame's atlas (texels)
  float pivotX = 0, pivotY = 0; // the sphere centre's position in the crop, texels from its corner
  // Best impostor plane: it faces the view and sits planeOffset model units from the sphere
  // centre towards the camera, at the median depth of the visible surface, which minimises the
  // summed distance of the visible points to a view-facing plane.
  float planeOffset = 0;
};

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
  uint32_t atlasWidth = 0, atlasHeight = 0; // every frame's atlas has this size
  // Frame-major, then elevation, then azimuth (stored ones only): see viewIndex.
  // Azimuth a looks from angle 2 pi a / azimuths about +Y (0: from +Z); elevation e from
  // 90 (e + 0.5) / elevations degrees above the horizon.
  std::vector<ImpostorView> views;
  std::vector<uint8_t> atlases; // frames * atlasWidth * atlasHeight * 4 bytes
  // Same layout, 4 x u16 per texel: u, v (0..65535 over 0..1, wrapped), region id + 1, 0.
  // Empty when the mesh has no UVs.
  std::vector<uint16_t> uvAtlases;
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

std::vector<uint8_t> encode(const Impostor &);
Impostor decodeImpostor(std::span<const uint8_t>, uint32_t version, const std::string &context);

struct ImpostorPack {
  Provenance provenance;
  Impostor impostor;
};
ImpostorPack loadImpostorPack(const Reader &reader);
std::vector<uint8_t> packBytes(const ImpostorPack &pack);

} // namespace crowd::pack
