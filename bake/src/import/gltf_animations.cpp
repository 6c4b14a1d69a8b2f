#include "gltf_animations.h"

#include <algorithm>
#include <cmath>

#include "importer.h"

namespace crowd::gltf {

void readSamplerKeys(const tinygltf::AnimationSampler &s, Accessors &accessors,
                     const std::string &file, const std::string &ctx, Reporter &reporter,
                     Channel &out) {
  const auto fail = [&](const std::string &what) { throw Error(file + ": " + what); };
  if (s.interpolation == "STEP")
    out.interpolation = Interpolation::Step;
  else if (s.interpolation == "CUBICSPLINE")
    out.interpolation = Interpolation::CubicSpline;
  else if (s.interpolation == "LINEAR" || s.interpolation.empty())
    out.interpolation = Interpolation::Linear;
  else
    fail(ctx + ": unknown interpolation '" + s.interpolation + "'");
  out.times = *accessors.read(s.input, ctx + " input");
  if (out.times.empty())
    fail(ctx + ": sampler has no keyframes");
  // Two keys at one time are read as a step (the later holds from that time on), with a
  // warning: the specification asks for strictly increasing times.
  size_t steps = 0;
  for (size_t k = 1; k < out.times.size(); ++k)
    if (out.times[k] == out.times[k - 1])
      ++steps;
    else if (!(out.times[k] > out.times[k - 1]))
      fail(ctx + " input: key times decrease at key " + std::to_string(k));
  if (steps)
    reporter.warn("keys_at_one_time",
                  ctx + ": " + std::to_string(steps) +
                      " pairs of keys share a time: read as steps (the later key holds "
                      "from that time)",
                  steps);
  out.values = *accessors.read(s.output, ctx + " output");
  if (out.path == ChannelPath::Rotation)
    out.components = 4;
  const size_t comps = out.components;
  size_t per = out.interpolation == Interpolation::CubicSpline ? 3 : 1;
  if (out.values.size() != out.times.size() * comps * per)
    fail(ctx + " output: " + std::to_string(out.values.size()) + " values for " +
         std::to_string(out.times.size()) + " keys of " + std::to_string(comps * per));
  // Rotation keys are unit quaternions; quantized ones (gltfpack's 16-bit) are off by up to
  // 3e-5, and slerp between keys as they are turns the wrong amount: normalized here (keys
  // within 1e-6 are left as they are; a cubic spline's values hold tangents).
  for (size_t k = 0; out.path == ChannelPath::Rotation && per == 1 && k < out.times.size(); ++k) {
    double *q = &out.values[k * 4];
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n > 0 && std::abs(n - 1) > 1e-6)
      for (int c = 0; c < 4; ++c)
        q[c] /= n;
  }
}

void Importer::readAnimations() {
  size_t strayWeightChannels = 0, duplicateTargets = 0;
  std::string firstDuplicate;
  for (size_t ai = 0; ai < model_.animations.size(); ++ai) {
    const auto &anim = model_.animations[ai];
    AnimationClip clip;
    clip.name = anim.name.empty() ? "clip" + std::to_string(ai) : anim.name;
    std::string actx = "animation '" + clip.name + "'";
    bool first = true;
    std::map<std::pair<int, std::string>, size_t> channelOf; // per target, its first channel
    for (size_t ci = 0; ci < anim.channels.size(); ++ci) {
      const auto &ch = anim.channels[ci];
      std::string ctx = actx + ", channel " + std::to_string(ci);
      Channel out;
      if (ch.target_node < 0 || size_t(ch.target_node) >= out_.nodes.size())
        fail(ctx + ": target node " + std::to_string(ch.target_node) + " does not exist");
      // The specification allows a target once per animation; readers differ on a second
      // (three.js blends the two, others take the last): the first is kept, with a warning.
      if (const auto [at, fresh] = channelOf.try_emplace({ch.target_node, ch.target_path}, ci);
          !fresh) {
        if (duplicateTargets++ == 0)
          firstDuplicate = ctx + " animates node " + std::to_string(ch.target_node) + "'s " +
                           ch.target_path + " as channel " + std::to_string(at->second) + " does";
        continue;
      }
      out.node = ch.target_node;
      if (ch.target_path == "weights") {
        const MorphGroup *group = out_.morphGroupOf(ch.target_node);
        if (!group) { // no baked mesh of this node has targets
          ++strayWeightChannels;
          continue;
        }
        out.components = group->count;
      }
      if (ch.target_path == "translation")
        out.path = ChannelPath::Translation;
      else if (ch.target_path == "rotation")
        out.path = ChannelPath::Rotation;
      else if (ch.target_path == "scale")
        out.path = ChannelPath::Scale;
      else if (ch.target_path == "weights")
        out.path = ChannelPath::Weights;
      else
        fail(ctx + ": unknown target path '" + ch.target_path + "'");
      if (out_.nodes[size_t(out.node)].hasMatrix && out.path != ChannelPath::Weights)
        fail(ctx + ": animates node " + std::to_string(out.node) + " which has a matrix");
      if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size())
        fail(ctx + ": sampler " + std::to_string(ch.sampler) + " does not exist");
      readSamplerKeys(anim.samplers[size_t(ch.sampler)], accessors_, path_, ctx, reporter_, out);
      clip.start = first ? out.times.front() : std::min(clip.start, out.times.front());
      clip.end = first ? out.times.back() : std::max(clip.end, out.times.back());
      first = false;
      clip.channels.push_back(std::move(out));
    }
    if (!clip.channels.empty())
      out_.clips.push_back(std::move(clip));
  }
  makeNamesUnique(out_.clips, "duplicate_clip_names", "clips", "clips are chosen by name");
  warnCount("morph_weights_without_targets", strayWeightChannels,
            "morph-weight channels animate nodes whose baked mesh has no morph targets: ignored");
  warnCount("duplicate_channel_targets", duplicateTargets,
            "channels animate a target an earlier channel of their animation does (the "
            "specification allows one): ignored, the first kept (first: " +
                firstDuplicate + ")");
}

} // namespace crowd::gltf
