#include "crowd/bake/anim_frames.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd {

namespace {

// A joint matrix as a unit quaternion and a uniform scale (its 3x3 part's cube-root
// determinant): what the quaternion encodings store of its 3x3 part.
std::pair<glm::dquat, double> rotationAndScale(const glm::dmat4 &m) {
  const glm::dmat3 a(m);
  double s = std::cbrt(glm::determinant(a));
  if (s == 0)
    s = 1e-30;
  glm::dquat q = glm::normalize(glm::quat_cast(a / s));
  if (q.w < 0)
    q = -q; // canonical sign; the sampler picks the short arc between frames
  return {q, s};
}

// Texels of one joint: 3 matrix rows, or quaternion + (translation, uniform scale).
void encodeJoint(const glm::dmat4 &m, bool matrix, float *out) {
  if (matrix) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        out[r * 4 + c] = float(m[c][r]);
    return;
  }
  const auto [q, s] = rotationAndScale(m);
  const double v[8] = {q.x, q.y, q.z, q.w, m[3][0], m[3][1], m[3][2], s};
  for (int k = 0; k < 8; ++k)
    out[k] = float(v[k]);
}

} // namespace

std::vector<uint32_t> matrixJointsFor(const SkinnedMesh &m, size_t jointCount,
                                      const std::vector<std::vector<glm::dmat4>> &frames,
                                      double tolerance) {
  std::vector<glm::dvec3> lo(jointCount, glm::dvec3(INFINITY)),
      hi(jointCount, glm::dvec3(-INFINITY));
  for (size_t v = 0; v < m.vertexCount(); ++v)
    for (int k = 0; k < 4; ++k)
      if (m.weights[v][k] > 0 && m.joints[v][size_t(k)] < jointCount) {
        const size_t j = m.joints[v][size_t(k)];
        lo[j] = glm::min(lo[j], glm::dvec3(m.positions[v]));
        hi[j] = glm::max(hi[j], glm::dvec3(m.positions[v]));
      }
  std::vector<uint32_t> out;
  for (size_t j = 0; j < jointCount; ++j) {
    if (lo[j].x > hi[j].x)
      continue; // moves no vertex
    double worst = 0;
    for (const auto &frame : frames) {
      const auto [q, s] = rotationAndScale(frame[j]);
      // The part of the 3x3 transform the encoding drops; the error is linear in the point, so
      // it is largest at a corner of the box.
      const glm::dmat3 dropped = glm::dmat3(frame[j]) - s * glm::mat3_cast(q);
      for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p(corner & 1 ? hi[j].x : lo[j].x, corner & 2 ? hi[j].y : lo[j].y,
                           corner & 4 ? hi[j].z : lo[j].z);
        worst = std::max(worst, glm::length(dropped * p));
      }
    }
    if (worst > tolerance)
      out.push_back(uint32_t(j));
  }
  return out;
}

pack::AnimationTexture buildAnimationTexture(const std::vector<std::vector<glm::dmat4>> &frames,
                                             size_t jointCount, const Precision &p,
                                             uint32_t maxWidth,
                                             const std::vector<uint32_t> &matrixJoints) {
  pack::AnimationTexture t;
  t.encoding = p.encoding;
  t.format = p.format;
  t.jointCount = uint32_t(jointCount);
  t.frameCount = uint32_t(frames.size());
  if (p.encoding == pack::JointEncoding::QuatTransScale && !matrixJoints.empty()) {
    t.encoding = pack::JointEncoding::QtsWithMatrices;
    t.matrixJoints = matrixJoints;
  }
  const uint64_t frameTexels = t.frameTexels();
  t.framesPerRow = uint32_t(maxWidth / frameTexels);
  if (t.framesPerRow == 0)
    throw Error("a frame of " + std::to_string(jointCount) + " joints needs " +
                std::to_string(frameTexels) + " texels, more than --max-width " +
                std::to_string(maxWidth));
  t.framesPerRow = std::min(t.framesPerRow, t.frameCount);
  t.width = uint32_t(t.framesPerRow * frameTexels);
  t.height = (t.frameCount + t.framesPerRow - 1) / t.framesPerRow;
  if (t.height > limits::kTextureSide)
    throw Error("animation texture would be taller than " + std::to_string(limits::kTextureSide) +
                " rows");
  size_t texelCount = size_t(t.width) * t.height;
  std::vector<float> values(texelCount * 4, 0.0f);
  for (uint32_t f = 0; f < t.frameCount; ++f)
    for (uint32_t j = 0; j < jointCount; ++j) {
      auto [x, y] = t.texelOf(f, j);
      encodeJoint(frames[f][j], t.isMatrix(j), &values[(size_t(y) * t.width + x) * 4]);
    }
  if (p.format == pack::TexelFormat::RGBA32F) {
    t.texels.resize(values.size() * 4);
    std::memcpy(t.texels.data(), values.data(), t.texels.size());
  } else {
    t.texels.resize(values.size() * 2);
    for (size_t i = 0; i < values.size(); ++i) {
      uint16_t h = pack::floatToHalf(values[i]);
      std::memcpy(&t.texels[i * 2], &h, 2);
    }
  }
  return t;
}

double sourceRate(const AnimationClip &clip) {
  double shortest = 0;
  for (const auto &ch : clip.channels)
    for (size_t k = 1; k < ch.times.size(); ++k) {
      double dt = ch.times[k] - ch.times[k - 1];
      if (dt > 1e-6 && (shortest == 0 || dt < shortest))
        shortest = dt;
    }
  return shortest > 0 ? std::min(1000.0, 1.0 / shortest) : 30.0;
}

pack::SkinTexture buildSkinTexture(const SkinnedMesh &m, uint32_t maxWidth) {
  pack::SkinTexture s;
  s.vertexCount = uint32_t(m.vertexCount());
  uint64_t texels = uint64_t(s.vertexCount) * 2;
  s.width = uint32_t(std::min<uint64_t>(maxWidth & ~1u, texels));
  s.height = uint32_t((texels + s.width - 1) / s.width);
  if (s.height > limits::kTextureSide)
    throw Error("skin texture would be taller than " + std::to_string(limits::kTextureSide) +
                " rows");
  s.texels.assign(size_t(s.width) * s.height * 4, 0.0f);
  for (size_t v = 0; v < m.vertexCount(); ++v)
    for (int k = 0; k < 4; ++k) {
      s.texels[v * 8 + size_t(k)] = float(m.joints[v][size_t(k)]);
      s.texels[v * 8 + 4 + size_t(k)] = m.weights[v][k];
    }
  return s;
}

ClipFrames planFrames(const AnimationClip &clip, double fps) {
  const double duration = clip.end - clip.start;
  const double wanted = duration > 0 ? std::max(1.0, std::round(duration * fps)) : 0.0;
  if (wanted >= double(limits::kClipFrames)) // before the cast: an absurd duration overflows it
    throw Error("clip '" + clip.name + "': " + std::to_string(duration) + " s at " +
                std::to_string(fps) + " fps needs more than " +
                std::to_string(limits::kClipFrames) + " frames (use --fps or --clip)");
  const auto intervals = uint32_t(wanted);
  return {&clip,         clip.name,
          clip.start,    intervals ? duration / intervals : 0.0,
          intervals + 1, intervals ? intervals / duration : fps};
}

std::vector<double> seededTimes(size_t clipIndex, double duration) {
  std::vector<double> times;
  uint64_t state = 0x9e3779b97f4a7c15ull * (clipIndex + 1);
  for (uint32_t k = 0; k < kRandomTimesPerClip; ++k) {
    state = state * 6364136223846793005ull + 1442695040888963407ull; // PCG's LCG step
    times.push_back(double(state >> 11) * 0x1.0p-53 * duration);
  }
  return times;
}

} // namespace crowd
