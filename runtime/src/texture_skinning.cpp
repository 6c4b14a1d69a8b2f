#include "crowd/runtime/texture_skinning.h"

#include <algorithm>
#include <cmath>

namespace crowd::runtime {
namespace {

glm::vec4 fetch(const pack::AnimationTexture &t, uint32_t frame, uint32_t joint, uint32_t texel) {
  auto [x, y] = t.texelOf(frame, joint);
  auto v = t.texel(x + texel, y);
  return {v[0], v[1], v[2], v[3]};
}

JointRows rowsFromQts(glm::vec4 q, glm::vec4 ts) {
  float x = q.x, y = q.y, z = q.z, w = q.w, s = ts.w;
  return {glm::vec4(s * (1 - 2 * (y * y + z * z)), s * 2 * (x * y - w * z), s * 2 * (x * z + w * y),
                    ts.x),
          glm::vec4(s * 2 * (x * y + w * z), s * (1 - 2 * (x * x + z * z)), s * 2 * (y * z - w * x),
                    ts.y),
          glm::vec4(s * 2 * (x * z - w * y), s * 2 * (y * z + w * x), s * (1 - 2 * (x * x + y * y)),
                    ts.z)};
}

} // namespace

JointRows sampleJoint(const pack::AnimationTexture &t, const pack::Clip &clip, uint32_t frame,
                      float alpha, uint32_t joint) {
  uint32_t f0 = clip.firstFrame + std::min(frame, clip.frameCount - 1);
  uint32_t f1 = clip.firstFrame + std::min(frame + 1, clip.frameCount - 1);
  if (t.encoding == pack::JointEncoding::Matrix3x4) {
    JointRows r;
    for (uint32_t k = 0; k < 3; ++k)
      r[k] = glm::mix(fetch(t, f0, joint, k), fetch(t, f1, joint, k), alpha);
    return r;
  }
  glm::vec4 q0 = fetch(t, f0, joint, 0), q1 = fetch(t, f1, joint, 0);
  if (glm::dot(q0, q1) < 0)
    q1 = -q1;
  glm::vec4 q = glm::normalize(glm::mix(q0, q1, alpha));
  return rowsFromQts(q, glm::mix(fetch(t, f0, joint, 1), fetch(t, f1, joint, 1), alpha));
}

void frameAt(const pack::Clip &clip, float seconds, uint32_t &frame, float &alpha) {
  float last = float(clip.frameCount - 1);
  float f = seconds * clip.fps;
  if (clip.loop && last > 0)
    f = f - last * std::floor(f / last);
  f = std::clamp(f, 0.0f, last);
  frame = uint32_t(std::floor(f));
  alpha = f - float(frame);
}

SkinnedVertex skinVertex(const pack::AnimationTexture &t, const pack::SkinTexture &skin,
                         const pack::Clip &clip, uint32_t frame, float alpha, uint32_t vertex,
                         const glm::vec3 &position, const glm::vec3 &normal) {
  const float *ids = &skin.texels[size_t(vertex) * 8];
  const float *w = ids + 4;
  const glm::vec4 p(position, 1.0f), n(normal, 0.0f);
  SkinnedVertex out{glm::vec3(0.0f), glm::vec3(0.0f)};
  for (int k = 0; k < 4; ++k) {
    if (w[k] == 0)
      continue;
    JointRows r = sampleJoint(t, clip, frame, alpha, uint32_t(ids[k]));
    out.position += w[k] * glm::vec3(glm::dot(r[0], p), glm::dot(r[1], p), glm::dot(r[2], p));
    out.normal += w[k] * glm::vec3(glm::dot(r[0], n), glm::dot(r[1], n), glm::dot(r[2], n));
  }
  return out;
}

glm::vec3 skinVertex(const pack::AnimationTexture &t, const pack::SkinTexture &skin,
                     const pack::Clip &clip, uint32_t frame, float alpha, uint32_t vertex,
                     const glm::vec3 &position) {
  return skinVertex(t, skin, clip, frame, alpha, vertex, position, glm::vec3(0.0f)).position;
}

} // namespace crowd::runtime
