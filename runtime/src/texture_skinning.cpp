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

// Hamilton product of quaternions stored (x, y, z, w), as the shader's qmul.
glm::vec4 qmul(glm::vec4 a, glm::vec4 b) {
  const glm::vec3 av(a), bv(b);
  return glm::vec4(a.w * bv + b.w * av + glm::cross(av, bv), a.w * b.w - glm::dot(av, bv));
}

// The dual part of the rigid transform (rotation q, translation t): t q / 2.
glm::vec4 dualOf(glm::vec4 q, glm::vec4 ts) { return 0.5f * qmul(glm::vec4(glm::vec3(ts), 0), q); }

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
  // Rotation and translation blend as dual quaternions (screw-linear): a joint turning about a
  // fixed pivot keeps turning about it between frames, where blending the translation linearly
  // would cut the arc's chord. The uniform scale blends linearly.
  glm::vec4 q0 = fetch(t, f0, joint, 0), q1 = fetch(t, f1, joint, 0);
  const glm::vec4 ts0 = fetch(t, f0, joint, 1), ts1 = fetch(t, f1, joint, 1);
  if (glm::dot(q0, q1) < 0)
    q1 = -q1;
  glm::vec4 real = glm::mix(q0, q1, alpha),
            dual = glm::mix(dualOf(q0, ts0), dualOf(q1, ts1), alpha);
  const float length = glm::length(real);
  real /= length;
  dual /= length;
  const glm::vec3 translation(2.0f * qmul(dual, glm::vec4(-glm::vec3(real), real.w)));
  return rowsFromQts(real, glm::vec4(translation, glm::mix(ts0.w, ts1.w, alpha)));
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
