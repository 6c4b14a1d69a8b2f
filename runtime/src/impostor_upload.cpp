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

// One frame as uploaded: its region words (every level), and the spans and their blocks (pool
// order) of every level.
struct FrameUpload {
  std::vector<uint32_t> regions;
  std::vector<uint8_t> normals, uvs;
  std::vector<uint32_t> levelStart; // per level: its first block in the frame's pool
  std::vector<pack::ImpostorSpans> spans;
};

// Where each level's ids go in a frame's words (ImpostorGpu's region fields).
void placeRegionLevels(const pack::Impostor &m, ImpostorGpu &g) {
  uint32_t words = 0;
  for (uint32_t l = 0; l < g.levels; ++l) {
    const uint32_t w = std::max(1u, m.atlasWidth >> l), h = std::max(1u, m.atlasHeight >> l);
    g.regionLevelWord[l] = int32_t(words);
    g.regionRowWords[l] = int32_t(pack::regionRowBytes(w, g.regionBits) / 4);
    words += uint32_t(g.regionRowWords[l]) * h;
  }
  g.regionFrameWords = words;
}

FrameUpload frameUpload(const pack::Impostor &m, uint32_t f, const ImpostorGpu &g) {
  FrameUpload u;
  const size_t perFrame = m.views.size() / m.frames;
  const auto views = std::span(m.views).subspan(f * perFrame, perFrame);
  u.regions.assign(g.regionFrameWords, 0);
  auto mips = impostorMips(m, f, g.levels);
  for (uint32_t l = 0; l < mips.size(); ++l) {
    const ImpostorMip &mip = mips[l];
    for (uint32_t y = 0; y < mip.height; ++y)
      for (uint32_t x = 0; x < mip.width; ++x) {
        const uint32_t bit = x * g.regionBits;
        u.regions[size_t(g.regionLevelWord[l]) + size_t(y) * uint32_t(g.regionRowWords[l]) +
                  bit / 32] |= uint32_t(mip.regions[size_t(y) * mip.width + x]) << (bit % 32);
      }
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

ImpostorGpu uploadImpostor(const pack::Impostor &m, const unsigned textures[2],
                           const unsigned buffers[3]) {
  ImpostorGpu g;
  g.levels = impostorMipLevels(m);
  g.regionBits = m.regionBits();
  placeRegionLevels(m, g);
  std::vector<FrameUpload> frames;
  size_t poolBlocks = 1;
  for (uint32_t f = 0; f < m.frames; ++f) {
    frames.push_back(frameUpload(m, f, g));
    poolBlocks = std::max(poolBlocks, frames.back().normals.size() / pack::kBc5BlockBytes);
  }
  // A roughly square pool, rows of a power of two blocks (the shader shifts and masks).
  while ((size_t(1) << (2 * g.poolShift)) < poolBlocks)
    ++g.poolShift;
  const uint32_t poolWidth = 4u << g.poolShift;
  const uint32_t poolRows = uint32_t((poolBlocks + (size_t(1) << g.poolShift) - 1) >> g.poolShift);
  const uint64_t regionBytes = uint64_t(g.regionFrameWords) * m.frames * 4;
  GLint side = 0, block = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &side);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
  if (poolWidth > uint32_t(side) || 4 * poolRows > uint32_t(side))
    throw Error("impostor: its blocks need a " + std::to_string(poolWidth) + "x" +
                std::to_string(4 * poolRows) + " texture, more than this OpenGL allows (" +
                std::to_string(side) + " texels a side); bake it with fewer texels");
  if (regionBytes > uint64_t(uint32_t(block)))
    throw Error("impostor: its region ids take " + std::to_string(regionBytes) +
                " bytes, more than this OpenGL's storage blocks hold (" + std::to_string(block) +
                "); bake it with fewer texels, views or frames");
  const size_t layerBytes = size_t(poolRows) << g.poolShift << 4;
  const bool uvs = !m.uvs.empty();
  for (int k = 0; k < (uvs ? 2 : 1); ++k)
    glTextureStorage3D(textures[k], 1, GL_COMPRESSED_RG_RGTC2, GLsizei(poolWidth),
                       GLsizei(4 * poolRows), GLsizei(m.frames));
  std::vector<uint32_t> spans(size_t(g.levels) * m.views.size() * 2, 0), regions;
  regions.reserve(size_t(g.regionFrameWords) * m.frames);
  const size_t perFrame = m.views.size() / m.frames;
  for (uint32_t f = 0; f < m.frames; ++f) {
    FrameUpload &u = frames[f];
    regions.insert(regions.end(), u.regions.begin(), u.regions.end());
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
  std::vector<float> table;
  for (const auto &v : m.views)
    table.insert(table.end(), {float(v.x), float(v.y), float(v.width), float(v.height), v.pivotX,
                               v.pivotY, v.planeOffset, 0.0f, v.slopeX, v.slopeY, 0.0f, 0.0f});
  glNamedBufferStorage(buffers[0], GLsizeiptr(table.size() * sizeof(float)), table.data(), 0);
  glNamedBufferStorage(buffers[1], GLsizeiptr(spans.size() * sizeof(uint32_t)), spans.data(), 0);
  glNamedBufferStorage(buffers[2], GLsizeiptr(regions.size() * sizeof(uint32_t)), regions.data(),
                       0);
  g.bytes = uint64_t(m.frames) * layerBytes * (uvs ? 2 : 1) +
            (table.size() + spans.size() + regions.size()) * 4;
  return g;
}

} // namespace crowd::runtime
