#include "crowd/runtime/track_palettes.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "crowd/formats/error.h"

namespace crowd::runtime {

namespace {

uint32_t bitsOf(float f) {
  uint32_t w;
  std::memcpy(&w, &f, 4);
  return w;
}

const pack::JointTracks &tracksOf(const pack::AnimationPack &p) {
  if (!p.tracks)
    throw Error("the pack has no joint tracks (bake it with crowdbake anim --store tracks)");
  return *p.tracks;
}

// Seconds into a clip of `duration`: wrapped past its ends where it loops (frameAt's rule: the
// end itself is the last sample), else clamped.
float clipSeconds(float t, float duration, bool loop) {
  if (loop && duration > 0 && (t < 0 || t > duration))
    t = t - duration * std::floor(t / duration);
  return std::clamp(t, 0.0f, duration);
}

// A clip time on its slot, clamped into the clip; slot 0 leaves it.
float onSlot(float t, float duration, float slot) {
  if (!(slot > 0))
    return t;
  return std::clamp(slot * std::round(t / slot), 0.0f, duration);
}

} // namespace

TrackWords trackWords(const pack::AnimationPack &p) {
  const pack::JointTracks &t = tracksOf(p);
  TrackWords w;
  w.nodes = uint32_t(t.skeleton.nodeCount());
  w.joints = uint32_t(t.skeleton.jointNodes.size());
  w.clips = uint32_t(t.clips.size());
  for (size_t n = 0; n < w.nodes; ++n) {
    w.rig.push_back(uint32_t(t.skeleton.parents[n]));
    w.rig.push_back(t.skeleton.restIsMatrix[n]);
    for (float f : t.skeleton.rest[n])
      w.rig.push_back(bitsOf(f));
    w.rig.resize(w.rig.size() + 2, 0);
  }
  for (size_t j = 0; j < w.joints; ++j) {
    w.rig.insert(w.rig.end(), {t.skeleton.jointNodes[j], 0, 0, 0});
    for (size_t k = 0; k < 16; ++k)
      w.rig.push_back(bitsOf(p.skeleton.inverseBind[j * 16 + k]));
  }
  uint32_t firstTrack = 0;
  for (const pack::TrackClip &c : t.clips) {
    w.tracks.insert(w.tracks.end(), {uint32_t(w.times.size()), uint32_t(c.times.size()), firstTrack,
                                     uint32_t(w.stream.size())});
    w.times.insert(w.times.end(), c.times.begin(), c.times.end());
    w.stream.insert(w.stream.end(), c.stream.begin(), c.stream.end());
    firstTrack += uint32_t(c.tracks.size());
  }
  for (const pack::TrackClip &c : t.clips)
    for (const pack::Track &track : c.tracks) {
      // The pass addresses a clip's stream with 32-bit bit offsets.
      const uint64_t end = track.firstBit + uint64_t(c.times.size()) * 3 * track.bits;
      if (end > kMaxClipStreamBits)
        throw Error("clip '" + c.name + "': its joint tracks take " + std::to_string(end) +
                    " bits, more than the palette pass addresses (" +
                    std::to_string(kMaxClipStreamBits) + "); bake it shorter or split it");
      w.tracks.push_back(uint32_t(track.kind) | uint32_t(track.step) << 8 |
                         uint32_t(track.bits) << 16 | uint32_t(track.dropped) << 24);
      w.tracks.push_back(uint32_t(track.firstBit));
      for (float f : track.min)
        w.tracks.push_back(bitsOf(f));
      for (size_t k = 0; k < 3; ++k)
        w.tracks.push_back(bitsOf(track.extent[k]));
    }
  if (w.stream.empty())
    w.stream.push_back(0); // a buffer is never empty
  return w;
}

std::vector<float> paletteSlots(const pack::AnimationPack &p, float slot) {
  const pack::JointTracks &t = tracksOf(p);
  std::vector<float> out;
  for (size_t c = 0; c < t.clips.size(); ++c) {
    float s = slot;
    if (s < 0) {
      const pack::TimeTicks ticks = pack::timeTicks(t.clips[c].times);
      s = ticks.bits ? ticks.tick : 1.0f / p.clips[c].fps;
    }
    out.push_back(s);
  }
  return out;
}

PaletteRequest paletteRequest(const pack::AnimationPack &p, const glm::vec4 &params,
                              const glm::vec4 &fade, float seconds, std::span<const float> slots) {
  const pack::JointTracks &t = tracksOf(p);
  const auto at = [&](float clip, float offset) {
    const size_t c = size_t(clip);
    const float duration = t.clips[c].duration();
    return onSlot(clipSeconds(seconds * params.z + offset, duration, p.clips[c].loop), duration,
                  slots.empty() ? 0.0f : slots[c]);
  };
  PaletteRequest r;
  r.clip = params.x;
  r.seconds = at(params.x, params.y);
  r.weight = fade.x < 0 || fade.w <= 0 ? 1.0f : std::clamp((seconds - fade.z) / fade.w, 0.0f, 1.0f);
  if (r.weight < 1) {
    r.from = fade.x;
    r.fromSeconds = at(fade.x, fade.y);
  }
  return r;
}

LocalPose blendPoses(const LocalPose &from, const LocalPose &to, float weight) {
  LocalPose out = to;
  for (size_t n = 0; n < out.rotation.size(); ++n) {
    out.rotation[n] = slerpShorter(from.rotation[n], to.rotation[n], weight);
    out.translation[n] = glm::mix(from.translation[n], to.translation[n], weight);
    out.scale[n] = glm::mix(from.scale[n], to.scale[n], weight);
  }
  return out;
}

std::vector<glm::mat4> decodePalette(const pack::AnimationPack &p, const PaletteRequest &r) {
  const pack::JointTracks &t = tracksOf(p);
  LocalPose pose = decodeLocalPose(t.skeleton, t.clips[size_t(r.clip)], r.seconds);
  if (r.from >= 0)
    pose = blendPoses(decodeLocalPose(t.skeleton, t.clips[size_t(r.from)], r.fromSeconds), pose,
                      r.weight);
  return skinningPalette(t.skeleton, pose, p.skeleton.inverseBind);
}

} // namespace crowd::runtime
