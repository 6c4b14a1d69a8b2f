#include "crowd/runtime/track_pose.h"

#include <algorithm>
#include <cmath>

namespace crowd::runtime {

SampleSpan sampleSpan(const pack::TrackClip &clip, float seconds) {
  const auto &t = clip.times;
  const size_t n = t.size();
  if (n == 0)
    return {};
  const size_t next = size_t(std::upper_bound(t.begin(), t.end(), seconds) - t.begin());
  if (next == 0)
    return {0, 0, 0.0f};
  if (next == n)
    return {uint32_t(n - 1), uint32_t(n - 1), 0.0f};
  // t[next] > seconds >= t[next - 1]: a cut's two times never span an interval.
  const float alpha = (seconds - t[next - 1]) / (t[next] - t[next - 1]);
  return {uint32_t(next - 1), uint32_t(next), alpha};
}

glm::quat slerpShorter(glm::quat a, glm::quat b, float s) {
  float d = glm::dot(a, b);
  if (d < 0) {
    b = -b;
    d = -d;
  }
  if (d > 0.9998f) // half-angle under 1.2 degrees: nlerp departs from slerp by under 1e-6 rad
    return glm::normalize(a * (1 - s) + b * s);
  const float theta = std::acos(d), sn = std::sin(theta);
  return a * (std::sin((1 - s) * theta) / sn) + b * (std::sin(s * theta) / sn);
}

glm::quat trackRotation(const std::array<float, 3> &stored, uint32_t dropped) {
  const float rest = std::sqrt(
      std::max(1.0f - stored[0] * stored[0] - stored[1] * stored[1] - stored[2] * stored[2], 0.0f));
  float xyzw[4];
  const uint32_t missing = dropped == 0 ? 3u : dropped - 1u; // its index in x, y, z, w
  for (uint32_t i = 0, k = 0; i < 4; ++i)
    xyzw[i] = i == missing ? rest : stored[k++];
  return glm::normalize(glm::quat(xyzw[3], xyzw[0], xyzw[1], xyzw[2]));
}

LocalPose decodeLocalPose(const pack::TrackSkeleton &s, const pack::TrackClip &clip,
                          float seconds) {
  const size_t nodes = s.nodeCount();
  LocalPose pose;
  pose.rotation.resize(nodes);
  pose.translation.resize(nodes);
  pose.scale.resize(nodes);
  const SampleSpan span = sampleSpan(clip, seconds);
  for (size_t n = 0; n < nodes; ++n) {
    const auto &r = s.rest[n];
    pose.rotation[n] = glm::quat(r[3], r[0], r[1], r[2]);
    pose.translation[n] = {r[4], r[5], r[6]};
    pose.scale[n] = {r[7], r[8], r[9]};
    for (uint32_t p = 0; p < pack::kTracksPerNode; ++p) {
      const pack::Track &track = clip.tracks[n * pack::kTracksPerNode + p];
      if (track.kind == pack::TrackKind::Default)
        continue;
      const bool rotation = p == 0;
      glm::vec3 v;
      glm::quat q;
      if (track.kind == pack::TrackKind::Constant) {
        v = {track.min[0], track.min[1], track.min[2]};
        q = trackRotation(track.min);
      } else {
        const auto a = pack::trackSample(clip, track, span.first);
        const bool hold = track.step || span.first == span.second;
        const auto b = hold ? a : pack::trackSample(clip, track, span.second);
        if (rotation)
          q = hold ? trackRotation(a, track.dropped)
                   : slerpShorter(trackRotation(a, track.dropped), trackRotation(b, track.dropped),
                                  span.alpha);
        else
          v = glm::mix(glm::vec3(a[0], a[1], a[2]), glm::vec3(b[0], b[1], b[2]),
                       hold ? 0.0f : span.alpha);
      }
      if (rotation)
        pose.rotation[n] = q;
      else if (p == 1)
        pose.translation[n] = v;
      else
        pose.scale[n] = v;
    }
  }
  return pose;
}

std::vector<glm::mat4> skinningPalette(const pack::TrackSkeleton &s, const LocalPose &pose,
                                       const std::vector<float> &inverseBind) {
  const size_t nodes = s.nodeCount();
  std::vector<glm::mat4> global(nodes);
  for (size_t n = 0; n < nodes; ++n) {
    glm::mat4 local(1.0f);
    if (s.restIsMatrix[n]) {
      const auto &m = s.rest[n];
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
          local[col][row] = m[size_t(row * 4 + col)];
    } else {
      local = glm::mat4_cast(pose.rotation[n]);
      for (int col = 0; col < 3; ++col)
        local[col] *= pose.scale[n][col];
      local[3] = glm::vec4(pose.translation[n], 1.0f);
    }
    global[n] = s.parents[n] >= 0 ? global[size_t(s.parents[n])] * local : local;
  }
  std::vector<glm::mat4> palette(s.jointNodes.size());
  for (size_t j = 0; j < palette.size(); ++j) {
    glm::mat4 ib;
    for (int k = 0; k < 16; ++k)
      ib[k / 4][k % 4] = inverseBind[j * 16 + size_t(k)];
    palette[j] = global[s.jointNodes[j]] * ib;
  }
  return palette;
}

} // namespace crowd::runtime
