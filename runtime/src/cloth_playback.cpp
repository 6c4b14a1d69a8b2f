#include "crowd/runtime/cloth_playback.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "crowd/formats/error.h"
#include "crowd/runtime/pack_joints.h"

namespace crowd::runtime {

namespace {

uint32_t topJoint(const pack::Skeleton &s) {
  for (uint32_t j = 0; j < s.parents.size(); ++j)
    if (s.parents[j] < 0)
      return j;
  return 0;
}

float lastFrame(const pack::Clip &clip) { return float(clip.frameCount) - 1.0f; }

} // namespace

ClothBuffers clothBuffers(const pack::AnimationPack &p, ClothLoops loops) {
  ClothBuffers b;
  if (loops.empty())
    return b;
  b.clips = uint32_t(p.clips.size());
  b.rootJoint = topJoint(p.skeleton);
  if (!p.skeleton.inverseBind.empty())
    b.rootBind = glm::inverse(glm::make_mat4(&p.skeleton.inverseBind[16 * b.rootJoint]));
  const size_t vertexCount = p.mesh.positions.size() / 3;
  b.vertices.assign(2 * vertexCount, -1);
  std::vector<std::pair<std::string, std::string>> garments; // (outfit, garment) per slot
  std::vector<std::vector<int32_t>> placed;                  // per slot: clothVertexOf
  for (size_t k = 0; k < loops.size(); ++k) {
    const pack::ClothLoop &loop = loops[k];
    const std::string ctx =
        "cloth loop of garment '" + loop.garment + "' over clip '" + loop.clip + "'";
    auto of = pack::clothVertexOf(p, loop, ctx);
    const std::pair<std::string, std::string> key{loop.outfit, loop.garment};
    auto slot = uint32_t(std::find(garments.begin(), garments.end(), key) - garments.begin());
    if (slot == garments.size()) {
      garments.push_back(key);
      placed.push_back(std::move(of));
    } else if (of != placed[slot]) {
      throw Error(ctx + ": its vertices are not those of the garment's other loops");
    }
  }
  b.garments = uint32_t(garments.size());
  for (uint32_t slot = 0; slot < b.garments; ++slot)
    for (size_t v = 0; v < vertexCount; ++v)
      if (placed[slot][v] >= 0) {
        b.vertices[2 * v] = int32_t(slot);
        b.vertices[2 * v + 1] = placed[slot][v];
      }

  b.loops.resize(size_t(b.garments) * b.clips);
  const auto &s = p.mesh.boundingSphere;
  const glm::vec3 centre(s[0], s[1], s[2]);
  float radius = s[3];
  for (const pack::ClothLoop &loop : loops) {
    const auto slot =
        uint32_t(std::find(garments.begin(), garments.end(), std::pair{loop.outfit, loop.garment}) -
                 garments.begin());
    const auto clip =
        uint32_t(std::find_if(p.clips.begin(), p.clips.end(),
                              [&](const pack::Clip &c) { return c.name == loop.clip; }) -
                 p.clips.begin());
    const pack::Clip &c = p.clips.at(clip);
    GpuClothLoop &g = b.loops[size_t(slot) * b.clips + clip];
    g.first = int32_t(b.positions.size() / 2);
    g.vertices = int32_t(loop.vertexCount());
    g.frames = int32_t(loop.frameCount());
    g.cycles = int32_t(loop.cycles);
    std::copy(loop.origin.begin(), loop.origin.end(), g.origin);
    std::copy(loop.step.begin(), loop.step.end(), g.step);
    g.framesPerCycle = lastFrame(c) > 0 ? loop.fps * lastFrame(c) / c.fps : 1.0f;
    g.startCycle = float(loop.cacheStart) / g.framesPerCycle;
    for (size_t i = 0; i < loop.positions.size(); i += 3) {
      b.positions.push_back(uint32_t(loop.positions[i]) | uint32_t(loop.positions[i + 1]) << 16);
      b.positions.push_back(loop.positions[i + 2]);
    }
    // Each loop frame placed by the top joint at the clip time it plays with.
    for (uint32_t f = 0; f < loop.frameCount(); ++f) {
      float phase = g.startCycle + float(f) / g.framesPerCycle;
      phase -= std::floor(phase);
      const auto at = clipTimeAt(c, phase * lastFrame(c) / c.fps);
      const JointRows m = sampleJoint(p, clip, at.frame, at.alpha, b.rootJoint);
      for (uint32_t v = 0; v < loop.vertexCount(); ++v) {
        const glm::vec4 q(clothBindPosition(b, g, {f, f, 0.0f}, v), 1.0f);
        const glm::vec3 world(glm::dot(m[0], q), glm::dot(m[1], q), glm::dot(m[2], q));
        radius = std::max(radius, glm::length(world - centre));
      }
    }
  }
  b.sphere = {s[0], s[1], s[2], radius};
  return b;
}

LoopTime loopTimeAt(const pack::Clip &clip, const GpuClothLoop &loop, float clipSeconds) {
  const float last = lastFrame(clip);
  float u = last > 0.0f ? clipSeconds * clip.fps / last : 0.0f; // clip cycles
  if (!clip.loop)
    u = std::clamp(u, 0.0f, 1.0f);
  const float cycles = float(loop.cycles);
  float phase = u - loop.startCycle;
  phase -= cycles * std::floor(phase / cycles);
  const float f = phase * loop.framesPerCycle;
  const float whole = std::floor(f);
  const auto frames = uint32_t(loop.frames);
  const uint32_t f0 = uint32_t(whole) % frames;
  return {f0, (f0 + 1) % frames, f - whole};
}

glm::vec3 clothBindPosition(const ClothBuffers &b, const GpuClothLoop &loop, const LoopTime &t,
                            uint32_t vertex) {
  auto at = [&](uint32_t frame) {
    const size_t i = 2 * (size_t(loop.first) + size_t(frame) * size_t(loop.vertices) + vertex);
    const uint32_t xy = b.positions[i], z = b.positions[i + 1];
    return glm::vec3(loop.origin[0] + float(xy & 0xffffu) * loop.step[0],
                     loop.origin[1] + float(xy >> 16) * loop.step[1],
                     loop.origin[2] + float(z) * loop.step[2]);
  };
  const glm::vec3 q = glm::mix(at(t.f0), at(t.f1), t.alpha);
  return glm::vec3(b.rootBind * glm::vec4(q, 1.0f));
}

bool clothVertexAt(const pack::AnimationPack &pack, const ClothBuffers &b, uint32_t clip,
                   float clipSeconds, uint32_t v, glm::vec3 &position) {
  if (b.empty() || b.vertices[2 * size_t(v)] < 0)
    return false;
  const GpuClothLoop &g = b.loops[size_t(b.vertices[2 * size_t(v)]) * b.clips + clip];
  if (g.frames == 0)
    return false;
  const pack::Clip &c = pack.clips[clip];
  const auto at = clipTimeAt(c, clipSeconds);
  const glm::vec4 q(clothBindPosition(b, g, loopTimeAt(c, g, clipSeconds),
                                      uint32_t(b.vertices[2 * size_t(v) + 1])),
                    1.0f);
  const JointRows m = sampleJoint(pack, clip, at.frame, at.alpha, b.rootJoint);
  position = glm::vec3(glm::dot(m[0], q), glm::dot(m[1], q), glm::dot(m[2], q));
  return true;
}

} // namespace crowd::runtime
