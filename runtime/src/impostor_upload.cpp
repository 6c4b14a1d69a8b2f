#include "impostor_upload.h"

#include <algorithm>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include "crowd/formats/bc5.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor_spans.h"
#include "crowd/runtime/impostor_runtime.h"

namespace crowd::runtime {

namespace {

// One frame as uploaded: its region layer (every level), and the spans' blocks of every level
// (pool order).
struct FrameUpload {
  std::vector<uint8_t> regions;
  std::vector<uint8_t> normals, uvs;
  std::vector<uint32_t> levelStart; // per level: its first block in the frame's pool
  std::vector<pack::ImpostorSpans> spans;
};

// The region layer's size, and where each level goes in it (ImpostorGpu::regionOrigin).
std::array<uint32_t, 2> placeRegionLevels(const pack::Impostor &m, ImpostorGpu &g) {
  std::array<uint32_t, 2> size{pack::regionRowBytes(m.atlasWidth, g.regionBits), m.atlasHeight};
  uint32_t x = 0; // levels 1 on, left to right below level 0
  for (uint32_t l = 1; l < g.levels; ++l) {
    g.regionOrigin[l] = {int32_t(x), int32_t(m.atlasHeight)};
    x += pack::regionRowBytes(std::max(1u, m.atlasWidth >> l), g.regionBits);
  }
  if (g.levels > 1)
    size = {std::max(size[0], x), m.atlasHeight + std::max(1u, m.atlasHeight >> 1)};
  return size;
}

FrameUpload frameUpload(const pack::Impostor &m, uint32_t f, const ImpostorGpu &g,
                        std::array<uint32_t, 2> layer) {
  FrameUpload u;
  const size_t perFrame = m.views.size() / m.frames;
  const auto views = std::span(m.views).subspan(f * perFrame, perFrame);
  u.regions.assign(size_t(layer[0]) * layer[1], 0);
  auto mips = impostorMips(m, f, g.levels);
  for (uint32_t l = 0; l < mips.size(); ++l) {
    const ImpostorMip &mip = mips[l];
    // Two texels a byte (4 bits: the even column low) or a byte each, at the level's corner.
    const uint32_t shift = g.regionBits == 4 ? 1 : 0;
    for (uint32_t y = 0; y < mip.height; ++y)
      for (uint32_t x = 0; x < mip.width; ++x)
        u.regions[size_t(g.regionOrigin[l][1] + y) * layer[0] + g.regionOrigin[l][0] +
                  (x >> shift)] |=
            uint8_t(mip.regions[size_t(y) * mip.width + x] << (g.regionBits * (x & shift)));
    u.spans.push_back(pack::impostorSpans(views, mip.regions, mip.width, mip.height, l));
    u.levelStart.push_back(uint32_t(u.normals.size() / pack::kBc5BlockBytes));
    for (uint32_t block : u.spans.back().sourceBlocks) {
      const size_t at = size_t(block) * pack::kBc5BlockBytes;
      u.normals.insert(u.normals.end(), &mip.normals[at], &mip.normals[at] + 16);
      if (!mip.uvs.empty())
        u.uvs.insert(u.uvs.end(), &mip.uvs[at], &mip.uvs[at] + 16);
    }
  }
  return u;
}

} // namespace

ImpostorGpu uploadImpostor(const pack::Impostor &m, const unsigned textures[3],
                           const unsigned buffers[2]) {
  ImpostorGpu g;
  g.levels = std::min(impostorMipLevels(m), kImpostorMaxLevels);
  g.regionBits = m.regionBits();
  const std::array<uint32_t, 2> layer = placeRegionLevels(m, g);
  std::vector<FrameUpload> frames;
  size_t poolBlocks = 1;
  for (uint32_t f = 0; f < m.frames; ++f) {
    frames.push_back(frameUpload(m, f, g, layer));
    poolBlocks = std::max(poolBlocks, frames.back().normals.size() / pack::kBc5BlockBytes);
  }
  // A roughly square pool, rows of a power of two blocks (the shader shifts and masks).
  while ((size_t(1) << (2 * g.poolShift)) < poolBlocks)
    ++g.poolShift;
  const uint32_t poolWidth = 4u << g.poolShift;
  const uint32_t poolRows = uint32_t((poolBlocks + (size_t(1) << g.poolShift) - 1) >> g.poolShift);
  GLint side = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &side);
  for (auto [w, h] : {std::pair{poolWidth, 4 * poolRows}, std::pair{layer[0], layer[1]}})
    if (w > uint32_t(side) || h > uint32_t(side))
      throw Error("impostor: its planes need a " + std::to_string(w) + "x" + std::to_string(h) +
                  " texture, more than this OpenGL allows (" + std::to_string(side) +
                  " texels a side); bake it with fewer texels");
  const size_t layerBytes = size_t(poolRows) << g.poolShift << 4;
  const auto d = GLsizei(m.frames);
  const bool uvs = !m.uvs.empty();
  glTextureStorage3D(textures[0], 1, GL_COMPRESSED_RG_RGTC2, GLsizei(poolWidth),
                     GLsizei(4 * poolRows), d);
  if (uvs)
    glTextureStorage3D(textures[1], 1, GL_COMPRESSED_RG_RGTC2, GLsizei(poolWidth),
                       GLsizei(4 * poolRows), d);
  glTextureStorage3D(textures[2], 1, GL_R8UI, GLsizei(layer[0]), GLsizei(layer[1]), d);
  // An integer texture is incomplete, and reads 0, under a linear filter.
  glTextureParameteri(textures[2], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(textures[2], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(textures[2], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(textures[2], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  // Region rows are a byte wide per texel or two: packed, not 4-byte aligned (GL's default would
  // read past the layer's end).
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  g.bytes = size_t(m.frames) * layerBytes * (uvs ? 2 : 1);
  std::vector<uint32_t> spans(size_t(g.levels) * m.views.size() * 2, 0);
  const size_t perFrame = m.views.size() / m.frames;
  for (uint32_t f = 0; f < m.frames; ++f) {
    FrameUpload &u = frames[f];
    glTextureSubImage3D(textures[2], 0, 0, 0, GLint(f), GLsizei(layer[0]), GLsizei(layer[1]), 1,
                        GL_RED_INTEGER, GL_UNSIGNED_BYTE, u.regions.data());
    g.bytes += u.regions.size();
    for (uint32_t l = 0; l < u.spans.size(); ++l) {
      const pack::ImpostorSpans &s = u.spans[l];
      for (size_t v = 0; v < perFrame; ++v)
        spans[(l * m.views.size() + f * perFrame + v) * 2] =
            uint32_t(spans.size() / 2 + s.viewRows[v]);
      for (const auto &row : s.rows)
        spans.insert(spans.end(), {u.levelStart[l] + row.start, row.firstColumn});
    }
    for (auto [plane, texture] : {std::pair{&u.normals, textures[0]}, {&u.uvs, textures[1]}}) {
      if (plane->empty())
        continue;
      plane->resize(layerBytes, 0);
      glCompressedTextureSubImage3D(texture, 0, 0, 0, GLint(f), GLsizei(poolWidth),
                                    GLsizei(4 * poolRows), 1, GL_COMPRESSED_RG_RGTC2,
                                    GLsizei(layerBytes), plane->data());
    }
    u = {};
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glNamedBufferStorage(buffers[1], GLsizeiptr(spans.size() * sizeof(uint32_t)), spans.data(), 0);
  std::vector<float> table;
  for (const auto &v : m.views)
    table.insert(table.end(), {float(v.x), float(v.y), float(v.width), float(v.height), v.pivotX,
                               v.pivotY, v.planeOffset, 0.0f, v.slopeX, v.slopeY, 0.0f, 0.0f});
  glNamedBufferStorage(buffers[0], GLsizeiptr(table.size() * sizeof(float)), table.data(), 0);
  g.bytes += (spans.size() + table.size()) * 4;
  return g;
}

} // namespace crowd::runtime
