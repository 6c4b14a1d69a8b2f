#include "crowd/runtime/texture_skinning.h"

#include <algorithm>
#include <cmath>
#include <cstring>

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

// A joint's transform as a unit dual quaternion (rotation and translation) and a uniform scale.
struct Rigid {
  glm::vec4 real, dual;
  float scale;
};

// Screw-linear blend: the dual quaternions mixed on one hemisphere and normalized, so a joint
// turning about a fixed pivot keeps turning about it. The scale blends linearly.
Rigid mixRigid(const Rigid &a, Rigid b, float w) {
  if (glm::dot(a.real, b.real) < 0)
    b.real = -b.real, b.dual = -b.dual;
  const glm::vec4 real = glm::mix(a.real, b.real, w), dual = glm::mix(a.dual, b.dual, w);
  const float length = glm::length(real);
  return {real / length, dual / length, glm::mix(a.scale, b.scale, w)};
}

JointRows rowsOf(const Rigid &r) {
  const glm::vec3 translation(2.0f * qmul(r.dual, glm::vec4(-glm::vec3(r.real), r.real.w)));
  return rowsFromQts(r.real, glm::vec4(translation, r.scale));
}

// The rigid part of rows: the scale is the columns' mean length; the rotation is the scaled
// 3x3 part's quaternion (Shepperd's branches). Shear and non-uniform scale do not survive.
Rigid rigidOf(const JointRows &r) {
  const float scale = (glm::length(glm::vec3(r[0].x, r[1].x, r[2].x)) +
                       glm::length(glm::vec3(r[0].y, r[1].y, r[2].y)) +
                       glm::length(glm::vec3(r[0].z, r[1].z, r[2].z))) /
                      3.0f;
  auto m = [&](int i, int j) { return r[size_t(i)][j] / scale; };
  glm::vec4 q;
  const float trace = m(0, 0) + m(1, 1) + m(2, 2);
  if (trace > 0) {
    const float s = 2.0f * std::sqrt(trace + 1.0f);
    q = {(m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s, 0.25f * s};
  } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
    const float s = 2.0f * std::sqrt(1.0f + m(0, 0) - m(1, 1) - m(2, 2));
    q = {0.25f * s, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s, (m(2, 1) - m(1, 2)) / s};
  } else if (m(1, 1) > m(2, 2)) {
    const float s = 2.0f * std::sqrt(1.0f + m(1, 1) - m(0, 0) - m(2, 2));
    q = {(m(0, 1) + m(1, 0)) / s, 0.25f * s, (m(1, 2) + m(2, 1)) / s, (m(0, 2) - m(2, 0)) / s};
  } else {
    const float s = 2.0f * std::sqrt(1.0f + m(2, 2) - m(0, 0) - m(1, 1));
    q = {(m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, 0.25f * s, (m(1, 0) - m(0, 1)) / s};
  }
  q = glm::normalize(q);
  return {q, dualOf(q, glm::vec4(r[0].w, r[1].w, r[2].w, 0)), scale};
}

} // namespace

namespace {

// A joint between two frames as a rigid transform: qts frames as they are, matrix frames through
// rigidOf, each frame on its own (a linear blend of two rotations is no rotation, and its
// quaternion would depend on the branch taken), then the screw-linear blend.
Rigid sampleRigid(const pack::AnimationTexture &t, uint32_t f0, uint32_t f1, float alpha,
                  uint32_t joint) {
  auto at = [&](uint32_t f) -> Rigid {
    if (t.isMatrix(joint))
      return rigidOf({fetch(t, f, joint, 0), fetch(t, f, joint, 1), fetch(t, f, joint, 2)});
    const glm::vec4 q = fetch(t, f, joint, 0), ts = fetch(t, f, joint, 1);
    return {q, dualOf(q, ts), ts.w};
  };
  return mixRigid(at(f0), at(f1), alpha);
}

// Global frames around (frame, alpha) of a clip (the second clamped to the clip's last frame).
std::pair<uint32_t, uint32_t> framesOf(const pack::Clip &clip, uint32_t frame) {
  return {clip.firstFrame + std::min(frame, clip.frameCount - 1),
          clip.firstFrame + std::min(frame + 1, clip.frameCount - 1)};
}

} // namespace

JointRows sampleJoint(const pack::AnimationTexture &t, const pack::Clip &clip, uint32_t frame,
                      float alpha, uint32_t joint) {
  const auto [f0, f1] = framesOf(clip, frame);
  if (t.isMatrix(joint)) {
    JointRows r;
    for (uint32_t k = 0; k < 3; ++k)
      r[k] = glm::mix(fetch(t, f0, joint, k), fetch(t, f1, joint, k), alpha);
    return r;
  }
  // Rotation and translation blend as dual quaternions (screw-linear), as crossfades do.
  return rowsOf(sampleRigid(t, f0, f1, alpha, joint));
}

JointRows blendJoints(const JointRows &from, const JointRows &to, float weight) {
  return rowsOf(mixRigid(rigidOf(from), rigidOf(to), weight));
}

ClipTime clipTimeAt(const pack::Clip &clip, float seconds) {
  ClipTime c{&clip, 0, 0.0f};
  frameAt(clip, seconds, c.frame, c.alpha);
  return c;
}

void frameAt(const pack::Clip &clip, float seconds, uint32_t &frame, float &alpha) {
  float last = float(clip.frameCount - 1);
  float f = seconds * clip.fps;
  // A loop wraps past its end, not at it: clip time `last` / fps is the source's last key, which
  // the closing frame holds (the first frame is only within the loop test's tolerance of it).
  if (clip.loop && last > 0 && (f < 0 || f > last))
    f = f - last * std::floor(f / last);
  f = std::clamp(f, 0.0f, last);
  frame = uint32_t(std::floor(f));
  alpha = f - float(frame);
}

namespace {

// Skins with the weighted sum of the vertex's joints' transforms, `rowsOf(joint)`; the normal
// only `withNormal` (the error measures skin every vertex at every time they try, and the
// normal was half their work for nothing).
template <bool withNormal = true, class Rows>
SkinnedVertex skinWith(const pack::SkinTexture &skin, uint32_t vertex, const glm::vec3 &position,
                       const glm::vec3 &normal, Rows rowsOf) {
  const float *ids = &skin.texels[size_t(vertex) * 8];
  const float *w = ids + 4;
  const glm::vec4 p(position, 1.0f), n(normal, 0.0f);
  SkinnedVertex out{glm::vec3(0.0f), glm::vec3(0.0f)};
  for (int k = 0; k < 4; ++k) {
    if (w[k] == 0)
      continue;
    const JointRows r = rowsOf(uint32_t(ids[k]));
    out.position += w[k] * glm::vec3(glm::dot(r[0], p), glm::dot(r[1], p), glm::dot(r[2], p));
    if constexpr (withNormal)
      out.normal += w[k] * glm::vec3(glm::dot(r[0], n), glm::dot(r[1], n), glm::dot(r[2], n));
  }
  return out;
}

} // namespace

SkinnedVertex skinVertex(const pack::AnimationTexture &t, const pack::SkinTexture &skin,
                         const pack::Clip &clip, uint32_t frame, float alpha, uint32_t vertex,
                         const glm::vec3 &position, const glm::vec3 &normal) {
  return skinWith(skin, vertex, position, normal,
                  [&](uint32_t j) { return sampleJoint(t, clip, frame, alpha, j); });
}

glm::vec3 skinVertex(const pack::AnimationTexture &t, const pack::SkinTexture &skin,
                     const pack::Clip &clip, uint32_t frame, float alpha, uint32_t vertex,
                     const glm::vec3 &position) {
  return skinWith<false>(skin, vertex, position, {},
                         [&](uint32_t j) { return sampleJoint(t, clip, frame, alpha, j); })
      .position;
}

std::vector<JointRows> sampleJoints(const pack::AnimationTexture &t, const pack::Clip &clip,
                                    uint32_t frame, float alpha) {
  std::vector<JointRows> joints(t.jointCount);
  for (uint32_t j = 0; j < t.jointCount; ++j)
    joints[j] = sampleJoint(t, clip, frame, alpha, j);
  return joints;
}

SkinnedVertex skinVertex(const std::vector<JointRows> &joints, const pack::SkinTexture &skin,
                         uint32_t vertex, const glm::vec3 &position, const glm::vec3 &normal) {
  return skinWith(skin, vertex, position, normal, [&](uint32_t j) { return joints[j]; });
}

glm::vec3 skinVertex(const std::vector<JointRows> &joints, const pack::SkinTexture &skin,
                     uint32_t vertex, const glm::vec3 &position) {
  return skinWith<false>(skin, vertex, position, {}, [&](uint32_t j) { return joints[j]; })
      .position;
}

namespace {

// Adds `factor` times the offsets of the active targets of global frame `frame` to `out`.
void addMorphs(const pack::Morphs &m, uint32_t frame, float factor, uint32_t vertex,
               SkinnedVertex &out) {
  for (uint32_t s = 0; s < pack::kMorphSlots; ++s) {
    const pack::Morphs::Slot &slot = m.slots[size_t(frame) * pack::kMorphSlots + s];
    const float w = slot.weight * factor;
    const pack::Morphs::Target &t = m.targets[size_t(slot.target)];
    if (w == 0.0f || vertex < t.firstVertex || vertex - t.firstVertex >= t.vertexCount)
      continue;
    const float *o = &m.offsets[t.firstOffset + size_t(vertex - t.firstVertex) * 8];
    out.position += w * glm::vec3(o[0], o[1], o[2]);
    out.normal += w * glm::vec3(o[4], o[5], o[6]);
  }
}

// A clip time's morph offsets, `factor` of them, added to `out`.
void addMorphs(const pack::Morphs &m, const ClipTime &at, float factor, uint32_t vertex,
               SkinnedVertex &out) {
  const auto [f0, f1] = framesOf(*at.clip, at.frame);
  addMorphs(m, f0, factor * (1.0f - at.alpha), vertex, out);
  addMorphs(m, f1, factor * at.alpha, vertex, out);
}

} // namespace

SkinnedVertex morphVertex(const pack::Morphs &m, const ClipTime &at, uint32_t vertex,
                          SkinnedVertex bind) {
  addMorphs(m, at, 1.0f, vertex, bind);
  return bind;
}

SkinnedVertex morphVertexFaded(const pack::Morphs &m, const ClipTime &from, const ClipTime &to,
                               float weight, uint32_t vertex, SkinnedVertex bind) {
  if (weight >= 1.0f)
    return morphVertex(m, to, vertex, bind);
  addMorphs(m, from, 1.0f - weight, vertex, bind);
  addMorphs(m, to, weight, vertex, bind);
  return bind;
}

std::vector<int32_t> jointTexelWords(const pack::AnimationTexture &t) {
  std::vector<int32_t> words;
  for (uint32_t j = 0; j < t.jointCount; ++j)
    words.insert(words.end(), {int32_t(t.texelOf(0, j).first), t.isMatrix(j) ? 3 : 2});
  return words;
}

std::vector<int32_t> morphSlotWords(const pack::Morphs *m) {
  std::vector<int32_t> words;
  if (!m) {
    words.assign(size_t(pack::kMorphSlots) * 4, 0);
    return words;
  }
  for (const auto &slot : m->slots) {
    const auto &t = m->targets[size_t(slot.target)];
    int32_t bits;
    std::memcpy(&bits, &slot.weight, 4);
    words.insert(words.end(), {int32_t(t.firstOffset / 8), int32_t(t.firstVertex),
                               int32_t(t.vertexCount), bits});
  }
  return words;
}

SkinnedVertex skinVertexFaded(const pack::AnimationTexture &t, const pack::SkinTexture &skin,
                              const ClipTime &from, const ClipTime &to, float weight,
                              uint32_t vertex, const glm::vec3 &position, const glm::vec3 &normal) {
  if (weight >= 1.0f) // the fade is over: `to` alone, as the shader draws it
    return skinVertex(t, skin, *to.clip, to.frame, to.alpha, vertex, position, normal);
  return skinWith(skin, vertex, position, normal, [&](uint32_t j) {
    const auto [a0, a1] = framesOf(*from.clip, from.frame);
    const auto [b0, b1] = framesOf(*to.clip, to.frame);
    return rowsOf(mixRigid(sampleRigid(t, a0, a1, from.alpha, j),
                           sampleRigid(t, b0, b1, to.alpha, j), weight));
  });
}

} // namespace crowd::runtime
