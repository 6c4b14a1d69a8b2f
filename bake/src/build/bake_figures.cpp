#include "crowd/bake/bake_figures.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace crowd {

using nlohmann::ordered_json;

ordered_json lodFigures(const pack::Lod &l, size_t inputTriangles,
                        const std::vector<float> *colourChange) {
  const uint32_t n = uint32_t(l.collapse.size());
  auto triangles = [&](uint32_t v) { return l.totalTriangles(v); };
  ordered_json f;
  f["input_triangles"] = inputTriangles;
  f["triangles"] = triangles(n);
  f["vertices"] = n;
  f["floor_vertices"] = l.floorVertices;
  f["floor_triangles"] = triangles(l.floorVertices);
  for (double share : {0.5, 0.25, 0.1, 0.05}) { // the fewest vertices holding the share
    uint32_t v = n;
    while (v > l.floorVertices && double(triangles(v - 1)) >= share * double(triangles(n)))
      --v;
    f["levels"].push_back({{"share", share},
                           {"vertices", v},
                           {"triangles", triangles(v)},
                           {"quadric_error", n ? l.error[std::min(v, n - 1)] : 0.0f}});
    if (colourChange && colourChange->size() == n) {
      float largest = 0; // over the removals the cut has taken: vertices v and above
      for (uint32_t k = v; k < n; ++k)
        largest = std::max(largest, (*colourChange)[k]);
      f["levels"].back()["colour_change"] = largest;
    }
  }
  return f;
}

ordered_json outfitFigures(const OutfitBakeResult &r, const OutfitOptions &options) {
  ordered_json f;
  f["body_faces"] = r.bodyTriangles;
  f["body_faces_hidden_without_outfit"] = r.bareHiddenFaces;
  f["frames_tested"] = r.framesTested;
  f["loop_frames_tested"] = r.loopFramesTested; // cloth loops: their frames, tested too
  f["min_saving"] = options.minSaving;
  for (const auto &o : r.outfits) {
    ordered_json oj = {{"name", o.name},
                       {"garment_faces", o.garmentFaces},
                       {"hidden_faces", o.hiddenFaces},
                       {"removed_faces", o.removedFaces},
                       {"visibility_s", o.seconds}};
    for (const auto &s : o.subMeshes)
      oj["sub_meshes"].push_back({{"name", s.subMesh},
                                  {"faces", s.faces},
                                  {"hidden", s.hidden},
                                  {"coverage", s.coverage},
                                  {"kept_whole", s.keptWhole}});
    f["outfits"].push_back(oj);
  }
  const double tagged = double(r.taggedFaces), naive = double(r.naiveFaces);
  f["faces_stored"] = {{"naive", r.naiveFaces},
                       {"prefitted", r.prefittedFaces},
                       {"tagged", r.taggedFaces},
                       {"outfit_specific", r.specificFaces},
                       {"outfit_specific_share", double(r.specificFaces) / tagged},
                       {"tagged_over_naive", tagged / naive},
                       {"tagged_over_prefitted", tagged / double(r.prefittedFaces)}};
  // Figure 6 of the seed: storage as outfits are added, from these outfits' means.
  const double n = double(std::max<size_t>(r.outfits.size(), 1)), body = r.bodyTriangles;
  const double garments = (naive - body) / n, prefitted = double(r.prefittedFaces) / n,
               specific = double(r.specificFaces) / n;
  for (int k = 1; k <= 10; ++k)
    f["extrapolated"].push_back({{"outfits", k},
                                 {"naive", body + k * garments},
                                 {"prefitted", k * prefitted},
                                 {"tagged", body + k * (specific + garments)}});
  if (options.check > 0) {
    auto &h = f["hole_check"];
    h["frame_step"] = options.check;
    h["frames"] = r.holes.frames;
    h["views"] = r.holes.views;
    for (const auto &o : r.holes.outfits)
      h["outfits"].push_back({{"name", o.name},
                              {"images", o.images},
                              {"differing_pixels", o.differingPixels},
                              {"removed_faces", o.removed},
                              {"never_seen_faces", o.neverSeen},
                              {"removed_never_seen", o.removedUnseen},
                              {"recall", o.recall()}});
  }
  return f;
}

namespace {
// What the BC5 blocks cost against the rendered texels; region ids are stored exactly.
ordered_json compressionFigures(const ImpostorCompression &c) {
  ordered_json f{{"normals", "bc5 octahedral"},
                 {"uvs", "bc5"},
                 {"regions", "exact, " + std::to_string(c.regionBits) + " bits"},
                 {"normal_error_mean_deg", c.normalMeanDeg},
                 {"normal_error_max_deg", c.normalMaxDeg},
                 {"uv_error_mean", c.uvMean},
                 {"uv_error_max", c.uvMax}};
  if (c.textureWidth) {
    f["uv_error_mean_texels"] = c.uvMean * c.textureWidth;
    f["uv_error_max_texels"] = c.uvMax * c.textureWidth;
  }
  return f;
}
} // namespace

ordered_json impostorFigures(const ImpostorBakeResult &r, const ImpostorOptions &o) {
  const auto &m = r.impostor;
  return {{"clip", m.clip},
          {"frames", o.frames},
          {"views", std::to_string(o.azimuths) + "x" + std::to_string(o.elevations)},
          {"texels", m.texels},
          {"atlas", std::to_string(m.atlasWidth) + "x" + std::to_string(m.atlasHeight)},
          {"occupancy", r.occupancy},
          {"bytes_per_frame", r.bytesPerFrame},
          {"naive_bytes_per_frame", r.naiveBytesPerFrame},
          {"mirror_iou_min", r.mirrorIouMin},
          {"mirror_iou_mean", r.mirrorIouMean},
          {"compression", compressionFigures(r.compression)}};
}

ordered_json impostorAccuracyFigures(const ImpostorAccuracy &a) {
  auto figures = [](const ImpostorAccuracy::Figures &f) {
    return ordered_json{{"iou_mean", f.iouMean},
                        {"iou_min", f.iouMin},
                        {"normal_error_mean_deg", f.normalMeanDeg},
                        {"normal_error_max_deg", f.normalMaxDeg},
                        {"uv_error_mean", f.uvMean},
                        {"uv_error_max", f.uvMax},
                        {"iou_mean_by_elevation", f.iouMeanByElevation}};
  };
  return {{"frame", 0},
          {"at_views", figures(a.atViews)},
          {"between_views", figures(a.betweenViews)},
          {"worst",
           {{"azimuth_deg", a.worstAzimuthDeg},
            {"elevation_deg", a.worstElevationDeg},
            {"iou", a.worstIou}}},
          {"popping",
           {{"orbit_steps", a.popping.steps},
            {"elevation_deg", a.popping.elevationDeg},
            {"geometry_change_mean", a.popping.geometryMean},
            {"geometry_change_max", a.popping.geometryMax},
            {"impostor_change_mean", a.popping.impostorMean},
            {"impostor_change_max", a.popping.impostorMax}}}};
}

ordered_json clothFigures(const ClothBakeResult &r) {
  const auto &c = r.chunk;
  const auto &l = r.loop;
  const double mm = r.mmPerUnit;
  ordered_json f;
  f["outfit"] = c.outfit;
  f["garment"] = c.garment;
  f["clip"] = c.clip;
  f["vertices"] = c.vertexCount();
  f["fps"] = c.fps;
  f["start"] = c.cacheStart;
  f["frames"] = c.frameCount();
  f["cycles"] = c.cycles;
  f["acceptable"] = l.acceptable;
  f["verdict"] = l.verdict;
  // The chosen seam's jumps (unblended) against the mean per-frame motion and velocity change:
  // at most 1 plays without a visible pop. Velocities in mm/s at the cache's frame rate.
  f["seam_position_jump_ratio"] = l.positionRatio;
  f["seam_velocity_jump_ratio"] = l.velocityRatio;
  f["best_to_median"] = l.bestToMedian;
  f["mean_motion_mm"] = l.meanMotion * mm;
  f["mean_velocity_change_mm_s"] = l.meanVelocityChange * mm * c.fps;
  // The frame rate read, against the common rate that fits best (cloth_input.h: FrameRateFit).
  f["fps_fit"] = {{"residual_mm", r.rate.residual * mm},
                  {"best_other_rate", r.rate.bestRate},
                  {"best_other_residual_mm", r.rate.bestResidual * mm},
                  {"mismatch", r.rate.mismatch}};
  f["blend_frames"] = c.blendFrames;
  f["blend_clamped"] = r.blendClamped;
  f["pushed_out"] = {
      {"vertices", r.pushedVertices}, {"max_mm", r.pushMaxMm}, {"mean_mm", r.pushMeanMm}};
  f["bytes"] = c.positions.size() * 2 + pack::encode(c.sources).size();
  f["quantisation"] = {{"max_mm", r.quantMaxMm}, {"mean_mm", r.quantMeanMm}};
  for (const auto &k : l.candidates)
    f["candidates"].push_back(
        {{"start", k.seam.start},
         {"cycles", k.seam.cycles},
         {"frames", k.seam.length},
         {"pass1_rank", k.pass1Rank},
         {"pass1_distance", k.seam.distance},
         {"position_jump_mm", k.seam.positionJump * mm},
         {"velocity_jump_mm_s", k.seam.velocityJump * mm * c.fps},
         {"position_jump_ratio", l.meanMotion > 0 ? k.seam.positionJump / l.meanMotion : 0.0},
         {"velocity_jump_ratio",
          l.meanVelocityChange > 0 ? k.seam.velocityJump / l.meanVelocityChange : 0.0},
         {"pass2_edge_px", k.edgeDistance},
         {"pass2_edge_px_per_view", k.edgeDistances}});
  // Pass 1 over (start, length), for charts: per loop length its best seam, and at the chosen
  // length every start (null where none can).
  ordered_json byCycles = ordered_json::array(), byStart = ordered_json::array();
  for (uint32_t cy = l.minCycles; cy <= l.maxCycles && l.frames > 0; ++cy) {
    double best = NAN;
    uint32_t at = 0;
    for (uint32_t s = 0; s < l.frames; ++s) {
      const double d = l.distances[size_t(cy - l.minCycles) * l.frames + s];
      if (!std::isnan(d) && !(d >= best)) {
        best = d;
        at = s;
      }
    }
    if (!std::isnan(best))
      byCycles.push_back({{"cycles", cy}, {"distance", best}, {"start", at}});
  }
  if (c.cycles >= l.minCycles && c.cycles <= l.maxCycles)
    for (uint32_t s = 0; s < l.frames; ++s) {
      const double d = l.distances[size_t(c.cycles - l.minCycles) * l.frames + s];
      byStart.push_back(std::isnan(d) ? ordered_json() : ordered_json(d));
    }
  f["pass1"] = {{"by_cycles", byCycles}, {"chosen_cycles_by_start", byStart}};
  f["pass1_s"] = l.pass1Seconds;
  f["pass2_s"] = l.pass2Seconds;
  f["bake_s"] = r.seconds;
  return f;
}

} // namespace crowd
