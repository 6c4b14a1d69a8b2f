#include "crowd/bake/anim_bake.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <functional>
#include <mutex>
#include <optional>

#include "anim_accuracy.h"
#include "crowd/bake/evaluate.h"
#include "crowd/bake/fade_accuracy.h"
#include "crowd/bake/morph_frames.h"
#include "crowd/bake/parallel.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"
#include "exact_frames.h"

namespace crowd {

uint64_t AnimBakeResult::textureBytes() const { return accuracy.at(baked).textureBytes; }

uint64_t AnimBakeResult::tracksBytes() const {
  if (!pack.tracks)
    return 0;
  uint64_t bytes = pack::skeletonBytes(pack.tracks->skeleton);
  for (const auto &clip : pack.tracks->clips)
    bytes += pack::clipBytes(clip);
  return bytes;
}

double millimetresPerUnit(const Character &c, bool *heightIsDiagonal) {
  const glm::dvec3 extent = restExtent(c);
  const double diagonal = glm::length(extent);
  const bool flat = !(extent.y >= 0.1 * diagonal);
  if (heightIsDiagonal)
    *heightIsDiagonal = flat;
  return kReferenceHeightMm / (flat ? diagonal : extent.y);
}

namespace {

// A clip whose last frame is its first moved along (a walk exported with root motion) is a cycle
// the player cannot loop: it moves no instance with a clip, so it plays the clip once and holds.
// Said, with how far and how fast it travels, so the clip can be exported in place.
void warnRootMotion(const std::vector<glm::dvec3> &first, const std::vector<glm::dvec3> &last,
                    const ClipFrames &clip, const AnimBakeResult &result, Reporter &reporter) {
  glm::dvec3 travel(0);
  for (size_t v = 0; v < first.size(); ++v)
    travel += (last[v] - first[v]) / double(first.size());
  double residual = 0;
  for (size_t v = 0; v < first.size(); ++v)
    residual = std::max(residual, glm::length(last[v] - first[v] - travel));
  if (residual > 1e-3 * result.diagonal || glm::length(travel) < 1e-2 * result.diagonal)
    return;
  const double metres = glm::length(travel) * result.mmPerUnit / 1000;
  const double seconds = double(clip.count - 1) / clip.fps;
  char text[400];
  std::snprintf(text, sizeof text,
                "clip '%s' is a cycle that travels %.2f m (%.2f m/s at 1.8 m tall): it is not "
                "looped, as the player moves no instance with a clip; export it in place (root "
                "motion removed) to loop it",
                clip.name.c_str(), metres, seconds > 0 ? metres / seconds : 0.0);
  reporter.warn("root_motion", text);
}

// Every clip of the pack as joint tracks (pack.tracks), and their figures; the rest-pose clip
// of a character without clips is one sample of default tracks. Clips are compressed side by
// side, each on one thread: a clip's steps are too small to share out (two threads on one clip
// took 1.5x one thread's time), so a single clip alone gets every thread.
void compressTracks(const Character &c, const std::vector<const AnimationClip *> &sourceClips,
                    const AnimBakeOptions &options, AnimBakeResult &result, Reporter &reporter) {
  const TrackRig rig = trackRig(c);
  pack::JointTracks tracks;
  tracks.skeleton = rig.skeleton;
  TrackCompressionOptions to;
  to.errorBudgetMm = options.errorBudgetMm;
  to.mmPerUnit = result.mmPerUnit;
  const size_t compressed = std::min(sourceClips.size(), result.pack.clips.size());
  to.threads = compressed > 1 ? 1 : options.threads;
  std::vector<CompressedClip> done(compressed);
  std::mutex said;
  std::condition_variable turn;
  size_t next = 0; // the clip whose step is said next: in order, one at a time
  parallelFor(compressed, compressed > 1 ? options.threads : 1, [&](size_t ci) {
    {
      std::unique_lock lock(said);
      turn.wait(lock, [&] { return next == ci; }); // clips are taken in order: no wait is long
      ++next; // the next clip's step waits for the lock, not for this one to succeed
      turn.notify_all();
      reporter.step("joint tracks: clip " + std::to_string(ci + 1) + " of " +
                    std::to_string(sourceClips.size()) + " (" + sourceClips[ci]->name + ")");
    }
    const auto &pk = result.pack; // the player blends its frames' morph weights with the tracks
    done[ci] = compressClip(c, rig, *sourceClips[ci], ci, to,
                            {pk.morphs ? &*pk.morphs : nullptr, &pk.clips[ci]});
  });
  result.tracks.clear();
  for (size_t ci = 0; ci < result.pack.clips.size(); ++ci) {
    if (ci < compressed) {
      done[ci].clip.name = result.pack.clips[ci].name;
      result.tracks.push_back(done[ci].figures);
      tracks.clips.push_back(std::move(done[ci].clip));
      continue;
    }
    pack::TrackClip rest;
    rest.name = result.pack.clips[ci].name;
    rest.times = {0.0f};
    rest.tracks.resize(rig.skeleton.nodeCount() * pack::kTracksPerNode);
    TrackClipFigures f;
    f.clip = rest.name;
    f.keys = f.samples = 1;
    f.defaultTracks = uint32_t(rest.tracks.size());
    f.bytes = pack::clipBytes(rest);
    f.met = true;
    result.tracks.push_back(f);
    tracks.clips.push_back(std::move(rest));
  }
  result.pack.tracks = std::move(tracks);
}

std::string millimetres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g mm", v);
  return buf;
}

// One warning per clip whose stored animation errs over the budget.
void warnOverBudget(const AnimBakeResult &result, Reporter &reporter) {
  const std::string over = ", over the " + millimetres(result.errorBudgetMm) + " budget";
  if (result.storesTexture())
    for (const auto &a : result.accuracy[result.baked].clips)
      if (a.maxAnyTime() * result.mmPerUnit > result.errorBudgetMm)
        reporter.warn("error_budget_not_met",
                      "clip '" + a.clip + "': the player errs by up to " +
                          millimetres(a.maxAnyTime() * result.mmPerUnit) + " at " +
                          result.budget.precision + over +
                          " (a step between keys, or a motion faster than the rates tried, "
                          "cannot be met by a texture; see the report's options_tried, or store "
                          "joint tracks: --store auto)");
  if (result.storesTracks())
    for (const auto &t : result.tracks)
      if (!t.met)
        reporter.warn("error_budget_not_met", "clip '" + t.clip +
                                                  "': its joint tracks err by up to " +
                                                  millimetres(t.maxAnyTimeMm()) + over);
}

// What the pack stores (AnimBakeOptions::store): "auto" asks chooseStore.
void applyStore(const AnimBakeOptions &options, AnimBakeResult &result, Reporter &reporter) {
  if (options.store != "auto") {
    result.stored = options.store;
    return;
  }
  double textureWorst = 0, tracksWorst = 0; // mm
  for (const auto &a : result.accuracy[result.baked].clips)
    textureWorst = std::max(textureWorst, a.maxAnyTime() * result.mmPerUnit);
  for (const auto &t : result.tracks)
    tracksWorst = std::max(tracksWorst, t.maxAnyTimeMm());
  const StoreChoice c = chooseStore(options.errorBudgetMm, {textureWorst, result.textureBytes()},
                                    {tracksWorst, result.tracksBytes()});
  result.stored = c.stored;
  result.storeReason = c.reason;
  reporter.step("stores " + result.stored + ": " + result.storeReason);
}

std::vector<const AnimationClip *> chosenClips(const Character &c, const AnimBakeOptions &options) {
  std::vector<const AnimationClip *> sourceClips;
  for (const auto &clip : c.clips)
    if (options.clip.empty() || clip.name == options.clip)
      sourceClips.push_back(&clip);
  if (sourceClips.empty() && !options.clip.empty())
    throw unknownName("clip", options.clip, c.clipNames());
  return sourceClips;
}

// The budget search's settings: the rates and precisions the options leave open.
BudgetSearch budgetSearch(const std::vector<uint32_t> &matrixJoints, double mmPerUnit,
                          const AnimBakeOptions &options, Reporter &reporter) {
  BudgetSearch search;
  search.budgetMm = options.errorBudgetMm;
  search.mmPerUnit = mmPerUnit;
  if (options.fps > 0)
    search.rates = {options.fps};
  search.sourceRateOnly = options.fps == AnimBakeOptions::kFpsSource;
  for (const auto &p : precisions())
    if (options.precision == "auto" || p.name == options.precision)
      search.tried.push_back(&p);
  search.maxWidth = options.maxWidth;
  search.threads = options.threads;
  search.matrixJoints = matrixJoints;
  search.step = reporter.onStep;
  return search;
}

// Each clip at the rate --fps forces, else on its keys (its source rate, at most the ladder's
// top): the clip table where no texture is searched. The precision is left empty.
BudgetChoice keyRates(const std::vector<const AnimationClip *> &sourceClips,
                      const std::vector<uint32_t> &matrixJoints, const AnimBakeOptions &options) {
  BudgetChoice budget;
  budget.matrixJoints = matrixJoints;
  for (const auto *clip : sourceClips) {
    const double source = sourceRate(*clip);
    budget.clips.push_back({clip->name,
                            options.fps > 0 ? options.fps : std::min(source, kRateLadder.back()),
                            source,
                            {}});
  }
  return budget;
}

// Each clip's rate and the pack's precision: forced, or the budget's choice.
BudgetChoice chooseRates(const Character &c, const std::vector<const AnimationClip *> &sourceClips,
                         const BudgetSearch &search, const AnimBakeOptions &options) {
  const bool forced = options.fps != AnimBakeOptions::kFpsFromBudget && options.precision != "auto";
  if (forced || sourceClips.empty()) {
    BudgetChoice budget;
    budget.precision = options.precision == "auto" ? "float" : options.precision;
    budget.matrixJoints = search.matrixJoints;
    for (const auto *clip : sourceClips)
      budget.clips.push_back(
          {clip->name, options.fps > 0 ? options.fps : sourceRate(*clip), sourceRate(*clip), {}});
    return budget;
  }
  return chooseByBudget(c, sourceClips, search);
}

std::vector<ClipFrames> planClips(const std::vector<const AnimationClip *> &sourceClips,
                                  const BudgetChoice &budget, const AnimBakeOptions &options,
                                  Reporter &reporter) {
  std::vector<ClipFrames> clips;
  for (size_t ci = 0; ci < sourceClips.size(); ++ci)
    clips.push_back(planFrames(*sourceClips[ci], budget.clips[ci].fps));
  if (clips.empty()) {
    reporter.warn("no_animation", "no animation: baked the rest pose as one-frame clip 'rest'");
    clips.push_back({nullptr, "rest", 0, 0, 1, options.fps > 0 ? options.fps : 30.0});
  }
  return clips;
}

// The clip table at result.budget's rates: every frame exactly, and the pack's clips and morph
// frames; its warnings are kept to be said once the table is the pack's.
struct ClipTable {
  std::vector<ClipFrames> clips;
  ExactFrames frames;
  Reporter warnings;
};

bool sameRates(const BudgetChoice &a, const BudgetChoice &b) {
  if (a.clips.size() != b.clips.size())
    return false;
  for (size_t i = 0; i < a.clips.size(); ++i)
    if (a.clips[i].fps != b.clips[i].fps)
      return false;
  return true;
}

// Joint names, each joint's nearest ancestor that is a joint, and the inverse bind matrices.
pack::Skeleton packSkeleton(const Character &c) {
  pack::Skeleton skeleton;
  skeleton.names.resize(c.jointCount());
  for (size_t j = 0; j < c.jointCount(); ++j) {
    skeleton.names[j] = c.jointName(j);
    int parent = -1;
    for (int p = c.nodes[size_t(c.jointNodes[j])].parent; p >= 0 && parent < 0;
         p = c.nodes[size_t(p)].parent) {
      auto it = std::find(c.jointNodes.begin(), c.jointNodes.end(), p);
      if (it != c.jointNodes.end())
        parent = int(it - c.jointNodes.begin());
    }
    skeleton.parents.push_back(parent);
    for (int k = 0; k < 16; ++k)
      skeleton.inverseBind.push_back(float(c.inverseBind[j][k / 4][k % 4]));
  }
  return skeleton;
}

// The clip table: a clip loops where its last frame is its first (within 1e-4 of the diagonal).
void packClips(const Character &c, const std::vector<ClipFrames> &clips, const ExactFrames &frames,
               AnimBakeResult &result, Reporter &reporter) {
  uint32_t first = 0;
  for (const auto &cf : clips) {
    pack::Clip clip;
    clip.name = cf.name;
    clip.fps = float(cf.fps);
    clip.startTime = float(cf.start);
    clip.firstFrame = first;
    clip.frameCount = cf.count;
    const auto start = framePositions(c, frames, first),
               end = framePositions(c, frames, first + cf.count - 1);
    double gap = 0;
    for (size_t v = 0; v < c.mesh.vertexCount(); ++v)
      gap = std::max(gap, glm::length(start[v] - end[v]));
    clip.loop = cf.count > 2 && gap <= 1e-4 * result.diagonal;
    if (cf.count > 2 && !clip.loop)
      warnRootMotion(start, end, cf, result, reporter);
    result.pack.clips.push_back(clip);
    first += cf.count;
  }
}

void packMorphs(const Character &c, const ExactFrames &frames, AnimBakeResult &result,
                Reporter &reporter) {
  result.pack.morphs = buildMorphs(c.mesh, frames.morphWeights, &result.morphOverflow);
  if (result.morphOverflow.frames)
    reporter.warn("morph_slots_full",
                  std::to_string(result.morphOverflow.frames) + " frames have more than " +
                      std::to_string(pack::kMorphSlots) + " morph targets active (up to " +
                      std::to_string(result.morphOverflow.mostActive) +
                      "): the ones moving the mesh least are dropped; the errors include them",
                  result.morphOverflow.frames);
}

bool tracksMeetTheBudget(const AnimBakeResult &result) {
  for (const auto &t : result.tracks)
    if (!t.met)
      return false;
  return !result.tracks.empty();
}

void storeTracksUnmeasured(const std::string &reason, AnimBakeResult &result, Reporter &reporter) {
  result.stored = "tracks";
  result.storeReason = reason;
  reporter.step("stores tracks: " + reason);
}

// Under --store auto, whether the tracks meet the budget on every clip in no more bytes than any
// texture could take (fewestTextureBytes): then the pack stores them and no texture is searched.
bool tracksBeatEveryTexture(const Character &c,
                            const std::vector<const AnimationClip *> &sourceClips,
                            const BudgetSearch &search, AnimBakeResult &result,
                            Reporter &reporter) {
  if (!tracksMeetTheBudget(result))
    return false;
  const uint64_t bytes = result.tracksBytes(), fewest = fewestTextureBytes(c, sourceClips, search);
  if (bytes > fewest)
    return false;
  storeTracksUnmeasured(
      "the tracks meet the budget in " + std::to_string(bytes) +
          " bytes, fewer than any texture takes (at least " + std::to_string(fewest) +
          " bytes at the lowest rate and smallest precision): no texture searched",
      result, reporter);
  return true;
}

// Under --store auto, after a texture search bounded by the tracks' bytes: whether the tracks,
// meeting the budget, still win (no texture found within it in fewer bytes). Then the pack
// keeps the key-rate clip table, the report the options tried, and no texture is measured.
bool tracksBeatTheSearch(BudgetChoice &searched, AnimBakeResult &result, Reporter &reporter) {
  if (!searched.searched || !tracksMeetTheBudget(result))
    return false;
  const uint64_t bytes = result.tracksBytes();
  if (searched.met && searched.bytes < bytes)
    return false;
  for (size_t i = 0; i < searched.clips.size(); ++i)
    searched.clips[i].fps = result.budget.clips[i].fps; // the rate of the table kept
  searched.precision.clear();
  result.budget = std::move(searched);
  storeTracksUnmeasured(
      "the tracks meet the budget in " + std::to_string(bytes) + " bytes; " +
          (result.budget.met
               ? "the texture meets it in " + std::to_string(result.budget.bytes) + " bytes or more"
               : "no texture tried in fewer bytes meets it") +
          ": no texture measured",
      result, reporter);
  return true;
}

// Tracks where asked and not yet compressed, the store chosen (where a texture was measured,
// else the tracks), and what the pack does not store dropped.
void chooseWhatIsStored(const Character &c, const std::vector<const AnimationClip *> &sourceClips,
                        const AnimBakeOptions &options, size_t frames, AnimBakeResult &result,
                        Reporter &reporter) {
  auto &pk = result.pack;
  if (options.compressesTracks() && !pk.tracks)
    compressTracks(c, sourceClips, options, result, reporter);
  if (!result.accuracy.empty())
    applyStore(options, result, reporter);
  else
    result.stored = "tracks";
  warnOverBudget(result, reporter); // of what the pack stores
  if (!result.storesTexture()) {    // the clip table's frames still count the morph weights' frames
    pack::AnimationTexture none;
    none.jointCount = uint32_t(c.jointCount());
    none.frameCount = uint32_t(frames);
    pk.animation = std::move(none);
  }
  if (!result.storesTracks())
    pk.tracks.reset();
}

// The rest mesh, its sub-meshes with their looks, the glTF source of each vertex, the texture.
void packMesh(const Character &c, pack::AnimationPack &pk) {
  auto &mesh = pk.mesh;
  for (size_t v = 0; v < c.mesh.vertexCount(); ++v) {
    for (int k = 0; k < 3; ++k) {
      mesh.positions.push_back(c.mesh.positions[v][k]);
      mesh.normals.push_back(c.mesh.normals[v][k]);
    }
    if (!c.mesh.uvs.empty()) {
      mesh.uvs.push_back(c.mesh.uvs[v].x);
      mesh.uvs.push_back(c.mesh.uvs[v].y);
    }
  }
  mesh.indices = c.mesh.indices;
  if (c.mesh.sources.size() == c.mesh.vertexCount())
    pk.sources = pack::SourceMap::of(c.mesh.sources);
  if (c.diffuse && !c.mesh.uvs.empty())
    pk.diffuse =
        pack::Texture{uint32_t(c.diffuse->width), uint32_t(c.diffuse->height), c.diffuse->rgba};
  pk.looks.emplace();
  for (const auto &part : c.mesh.parts) {
    mesh.subMeshes.push_back({part.name, part.firstIndex, part.indexCount});
    for (int k = 0; k < 4; ++k)
      pk.looks->colours.push_back(std::clamp(part.colour[k], 0.0f, 1.0f));
    pk.looks->textured.push_back(part.textured && pk.diffuse ? 1 : 0);
  }
}

// Each frame's bounding box, where no texture measure found it on the way.
FrameBounds frameBounds(const Character &c, const ExactFrames &frames, int threads) {
  FrameBounds bounds;
  bounds.low.assign(frames.count(), glm::dvec3(INFINITY));
  bounds.high.assign(frames.count(), glm::dvec3(-INFINITY));
  parallelFor(frames.count(), threads, [&](size_t f) {
    for (const auto &q : framePositions(c, frames, f)) {
      bounds.low[f] = glm::min(bounds.low[f], q);
      bounds.high[f] = glm::max(bounds.high[f], q);
    }
  });
  return bounds;
}

// A bounding sphere over every frame of every clip. Matrix blends keep mid-frame positions
// inside the frames' hull; the stored animation's worst error is added on top.
std::array<float, 4> boundingSphere(const Character &c, const ExactFrames &frames,
                                    const std::optional<FrameBounds> &measured,
                                    const AnimBakeResult &result, int threads) {
  const FrameBounds bounds = measured ? *measured : frameBounds(c, frames, threads);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (size_t f = 0; f < frames.count(); ++f) {
    lo = glm::min(lo, bounds.low[f]);
    hi = glm::max(hi, bounds.high[f]);
  }
  glm::dvec3 centre = (lo + hi) * 0.5;
  // A frame's box corner farthest from the centre bounds its vertices' distance: frames are
  // skinned from the farthest-reaching box down, and only while one can still raise the radius
  // (the same radius as skinning every frame).
  std::vector<std::pair<double, size_t>> reach;
  for (size_t f = 0; f < frames.count(); ++f) {
    const glm::dvec3 far =
        glm::max(glm::abs(bounds.low[f] - centre), glm::abs(bounds.high[f] - centre));
    reach.push_back({glm::length(far), f});
  }
  std::sort(reach.begin(), reach.end(), std::greater<>());
  std::atomic<double> radius{0.0};
  parallelFor(reach.size(), threads, [&](size_t i) {
    if (reach[i].first < radius.load())
      return;
    double most = 0;
    for (const auto &q : framePositions(c, frames, reach[i].second))
      most = std::max(most, glm::length(q - centre));
    for (double was = radius.load(); most > was && !radius.compare_exchange_weak(was, most);) {
    }
  });
  double slack = 0; // the worst error of what the pack stores
  if (result.storesTexture())
    for (const auto &a : result.accuracy[result.baked].clips)
      slack = std::max(slack, a.maxAnyTime());
  if (result.storesTracks())
    for (const auto &t : result.tracks)
      slack = std::max(slack, t.maxAnyTimeMm() / result.mmPerUnit);
  const double r = (radius.load() + slack) * (1 + 1e-6) + 1e-6 * result.diagonal;
  return {float(centre.x), float(centre.y), float(centre.z), float(r)};
}

ClipTable layOutClips(const Character &c, const std::vector<const AnimationClip *> &sourceClips,
                      const AnimBakeOptions &options, AnimBakeResult &result) {
  ClipTable t;
  t.warnings.quiet = true;
  t.clips = planClips(sourceClips, result.budget, options, t.warnings);
  t.frames = sampleFrames(c, t.clips, options.threads);
  result.pack.clips.clear();
  packClips(c, t.clips, t.frames, result, t.warnings);
  packMorphs(c, t.frames, result, t.warnings);
  return t;
}

} // namespace

StoreChoice chooseStore(double budgetMm, StoreCandidate texture, StoreCandidate tracks) {
  const bool textureMeets = texture.worstMm <= budgetMm, tracksMeet = tracks.worstMm <= budgetMm;
  const std::string figures =
      "texture " + std::to_string(texture.bytes) + " bytes, " + millimetres(texture.worstMm) +
      "; tracks " + std::to_string(tracks.bytes) + " bytes, " + millimetres(tracks.worstMm);
  StoreChoice c;
  if (textureMeets && tracksMeet) {
    c.stored = tracks.bytes <= texture.bytes ? "tracks" : "texture";
    c.reason = "both meet the budget, " + c.stored + " in fewer bytes (" + figures + ")";
  } else if (textureMeets || tracksMeet) {
    c.stored = tracksMeet ? "tracks" : "texture";
    c.reason = "only " + c.stored + " meets the budget (" + figures + ")";
  } else {
    c.stored = tracks.worstMm <= texture.worstMm ? "tracks" : "texture";
    c.reason = "neither meets the budget, " + c.stored + " errs less (" + figures + ")";
  }
  return c;
}

// The stages: the clip table (at the keys where tracks come first, else at the budget's rates)
// with the skeleton, skin and morphs; the tracks first under --store tracks or auto, and the
// texture searched only where it could take fewer bytes and measured only where it may be
// stored; what is stored; the fades; the mesh and its bounds.
AnimBakeResult bakeAnimation(const Character &c, const AnimBakeOptions &asked, Reporter &reporter) {
  asked.validate();
  AnimBakeResult result;
  AnimBakeOptions options = asked;
  options.store = asked.storeAsked(&result.storeReason);
  if (!result.storeReason.empty())
    reporter.step("stores texture: " + result.storeReason);
  result.diagonal = restDiagonal(c);
  result.mmPerUnit = millimetresPerUnit(c, &result.heightIsDiagonal);
  result.errorBudgetMm = options.errorBudgetMm;
  const std::vector<const AnimationClip *> sourceClips = chosenClips(c, options);
  const auto matrixJoints = matrixJointsByBudget(c, sourceClips, options.errorBudgetMm,
                                                 result.mmPerUnit, options.threads);
  const BudgetSearch search = budgetSearch(matrixJoints, result.mmPerUnit, options, reporter);
  auto &pk = result.pack;
  pk.skeleton = packSkeleton(c);
  pk.skin = buildSkinTexture(c.mesh, options.maxWidth); // the same for every precision
  const bool tracksFirst = options.store == "tracks" || options.store == "auto";
  bool searchTexture = !tracksFirst;
  ClipTable table;
  if (tracksFirst) {
    result.budget = keyRates(sourceClips, matrixJoints, options);
    table = layOutClips(c, sourceClips, options, result);
    compressTracks(c, sourceClips, options, result, reporter);
    searchTexture = options.store == "auto" &&
                    !tracksBeatEveryTexture(c, sourceClips, search, result, reporter);
  }
  std::optional<FrameBounds> bounds;
  if (searchTexture) {
    BudgetSearch bounded = search; // under auto, only as far as it could take fewer bytes
    if (tracksFirst && tracksMeetTheBudget(result))
      bounded.fewerBytesThan = result.tracksBytes();
    BudgetChoice budget = chooseRates(c, sourceClips, bounded, options);
    if (!tracksFirst || !tracksBeatTheSearch(budget, result, reporter)) {
      const bool newTable = !tracksFirst || !sameRates(budget, result.budget);
      result.budget = std::move(budget);
      if (newTable)
        table = layOutClips(c, sourceClips, options, result);
      if (newTable && tracksFirst && pk.morphs) // the tracks' errors include the frames' morphs
        compressTracks(c, sourceClips, options, result, reporter);
      bounds =
          measurePrecisions(c, table.clips, table.frames, matrixJoints, options, result, reporter);
      result.budget.met = true; // from the full measure, frame times included
      for (const auto &a : result.accuracy[result.baked].clips)
        result.budget.met &= a.maxAnyTime() * result.mmPerUnit <= options.errorBudgetMm;
    }
  }
  for (const auto &w : table.warnings.warnings())
    reporter.warn(w.code, w.message, w.count);
  chooseWhatIsStored(c, sourceClips, options, table.frames.count(), result, reporter);
  if (sourceClips.size() > 1) { // as the player fades what the pack stores
    reporter.step("crossfades between " + std::to_string(sourceClips.size()) + " clips");
    result.fades = measureFades(c, sourceClips, pk, options.threads);
  }
  packMesh(c, pk);
  pk.mesh.boundingSphere = boundingSphere(c, table.frames, bounds, result, options.threads);
  return result;
}

} // namespace crowd
