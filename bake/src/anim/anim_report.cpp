#include "crowd/bake/anim_report.h"

#include "crowd/bake/fade_accuracy.h"

namespace crowd {

using nlohmann::ordered_json;

ordered_json clipErrorsJson(const ClipAccuracy &a, const AnimBakeResult &r) {
  ordered_json j;
  j["max_error_any_time_mm"] = a.maxAnyTime() * r.mmPerUnit;
  j["max_error_any_time"] = a.maxAnyTime() / r.diagonal;
  const struct {
    const char *name;
    double max, mean;
  } at[] = {{"frames", a.maxAtFrames, a.meanAtFrames},
            {"midframes", a.maxAtMidframes, a.meanAtMidframes},
            {"random_times", a.maxAtRandom, a.meanAtRandom}};
  for (const auto &s : at) {
    j[std::string("max_error_at_") + s.name] = s.max / r.diagonal;
    j[std::string("mean_error_at_") + s.name] = s.mean / r.diagonal;
  }
  for (const auto &s : at) {
    j[std::string("max_error_at_") + s.name + "_model_units"] = s.max;
    j[std::string("mean_error_at_") + s.name + "_model_units"] = s.mean;
  }
  return j;
}

namespace {
// A precision's mean bytes per joint per frame, with the pack's matrix joints.
double bytesPerJointPerFrame(const Precision &p, const AnimBakeResult &r) {
  const size_t joints = r.pack.skeleton.jointCount();
  return joints ? double(p.frameBytes(joints, r.budget.matrixJoints.size())) / double(joints) : 0;
}
} // namespace

ordered_json precisionJson(const PrecisionAccuracy &pa, const AnimBakeResult &r) {
  ordered_json j;
  j["precision"] = pa.precision.name;
  j["encoding"] = pack::name(pa.precision.encoding);
  j["texel_format"] = pack::name(pa.precision.format);
  j["bytes_per_joint_per_frame"] = bytesPerJointPerFrame(pa.precision, r);
  j["texture_bytes"] = pa.textureBytes;
  for (const auto &c : pa.clips) {
    ordered_json cj;
    cj["clip"] = c.clip;
    cj["frames"] = c.frames;
    cj.update(clipErrorsJson(c, r));
    j["clips"].push_back(cj);
  }
  return j;
}

ordered_json animFigures(const AnimBakeResult &r) {
  ordered_json f;
  f["diagonal"] = r.diagonal;
  f["mm_per_model_unit"] = r.mmPerUnit; // the character scaled to 1.8 m
  f["scaled_by"] = r.heightIsDiagonal ? "diagonal" : "height";
  // The stored texture's (the texture measured but not stored is in "precisions").
  const PrecisionAccuracy *baked = r.accuracy.empty() ? nullptr : &r.accuracy[r.baked];
  if (baked && r.storesTexture()) {
    f["precision"] = baked->precision.name;
    f["bytes_per_joint_per_frame"] = bytesPerJointPerFrame(baked->precision, r);
  }
  // Joints whose shear or non-uniform scale the quaternion precisions cannot carry: they store
  // them as matrix rows (the budget's half, at the clips' source rates).
  f["matrix_joints"] = ordered_json::array();
  for (uint32_t j : r.budget.matrixJoints)
    f["matrix_joints"].push_back(r.pack.skeleton.names.at(j));
  f["error_budget_mm"] = r.errorBudgetMm;
  // What the pack stores and what it takes; budget_met and each clip's errors are of it.
  f["store"] = r.stored;
  if (!r.storeReason.empty())
    f["store_reason"] = r.storeReason;
  f["animation_bytes"] = (r.storesTexture() ? r.textureBytes() : 0) + r.tracksBytes();
  bool tracksMet = true;
  for (const auto &t : r.tracks)
    tracksMet &= t.met;
  f["budget_met"] = (!r.storesTexture() || r.budget.met) && (!r.storesTracks() || tracksMet);
  f["clips"] = ordered_json::array();
  for (size_t i = 0; i < r.pack.clips.size(); ++i) {
    const auto &c = r.pack.clips[i];
    ordered_json cj = {{"name", c.name},
                       {"frames", c.frameCount},
                       {"fps", c.fps},
                       {"start_time", c.startTime},
                       {"loop", c.loop}};
    const bool tracksAlone = !r.storesTexture();
    if (tracksAlone) { // the player's errors are the tracks'
      const TrackClipFigures &t = r.tracks.at(i);
      cj["max_error_any_time_mm"] = t.maxAnyTimeMm();
      cj["max_error_any_time"] = t.maxAnyTimeMm() / r.mmPerUnit / r.diagonal;
      cj["animation_bytes"] = t.bytes;
    } else {
      cj.update(clipErrorsJson(baked->clips.at(i), r));
      cj["animation_bytes"] =
          uint64_t(c.frameCount) * baked->precision.frameBytes(r.pack.skeleton.jointCount(),
                                                               r.budget.matrixJoints.size()) +
          (r.storesTracks() ? r.tracks.at(i).bytes : 0);
    }
    if (i < r.budget.clips.size()) { // not the rest pose
      const ClipBudget &b = r.budget.clips[i];
      cj["source_fps"] = b.sourceFps;
      for (const auto &o : b.tried) // empty where --fps and --precision forced the choice
        cj["options_tried"].push_back({{"fps", o.fps},
                                       {"precision", o.precision},
                                       {"frames", o.frames},
                                       {"bytes", o.bytes},
                                       {"max_error_any_time_mm", o.maxErrorMm},
                                       {"meets_budget", o.meets}});
    }
    if (i < r.tracks.size()) { // the tracks compressed: the TRAK chunk's clip
      const TrackClipFigures &t = r.tracks[i];
      cj["tracks"] = {{"animation_bytes", t.bytes},
                      {"keys", t.keys},
                      {"samples", t.samples},
                      {"default_tracks", t.defaultTracks},
                      {"constant_tracks", t.constantTracks},
                      {"animated_tracks", t.animatedTracks},
                      {"mean_bits", t.meanBits},
                      {"max_error_any_time_mm", t.maxAnyTimeMm()},
                      {"max_error_at_samples_mm", t.maxAtSamplesMm},
                      {"max_error_at_midsamples_mm", t.maxAtMidsMm},
                      {"max_error_at_random_times_mm", t.maxAtRandomMm},
                      {"mean_error_at_random_times_mm", t.meanAtRandomMm},
                      {"meets_budget", t.met}};
    }
    f["clips"].push_back(cj);
  }
  if (const auto &t = r.pack.tracks) { // what the TRAK chunk takes: the skeleton and every clip
    f["tracks_bytes"] = r.tracksBytes();
    f["tracks_skeleton_bytes"] = pack::skeletonBytes(t->skeleton);
  }
  if (r.fades.pairs) // the player's crossfades between clips, against the exact fade
    f["crossfades"] = {{"pairs", r.fades.pairs},
                       {"samples_per_pair", kFadeSamplesPerPair},
                       {"max_error_mm", r.fades.maxError * r.mmPerUnit},
                       {"mean_error_mm", r.fades.meanError * r.mmPerUnit},
                       {"max_error", r.fades.maxError / r.diagonal}};
  if (const auto &m = r.pack.morphs) { // their error is inside every clip's figures
    const MorphOverflow &o = r.morphOverflow;
    f["morph_targets"] = {{"targets", m->targets.size()},
                          {"slots_per_frame", pack::kMorphSlots},
                          {"most_active_in_a_frame", o.mostActive},
                          {"frames_over_slots", o.frames},
                          {"largest_dropped_offset_mm", o.largestDropped * r.mmPerUnit},
                          {"offset_vertices", m->offsets.size() / 8},
                          {"bytes", (m->offsets.size() + m->slots.size() * 2) * sizeof(float)}};
  }
  for (const auto &pa : r.accuracy)
    f["precisions"].push_back(precisionJson(pa, r));
  return f;
}

} // namespace crowd
