// The outfit bake's hole check (a sampled test, not a proof): naive and tagged renders of every
// outfit compared pixel by pixel with the deterministic rasterizer (see outfit_bake.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/bake/parallel.h"
#include "crowd/bake/raster.h"

namespace crowd {

namespace {

// Triangles to draw, ordered by the source triangle each shows, so that the rasterizer's depth
// ties (won by the lower index) fall the same way in both renders.
struct DrawList {
  std::vector<uint32_t> indices, ids;
};

DrawList drawList(const OutfitBakeResult &b, const std::vector<uint32_t> &triangles) {
  std::vector<std::pair<uint32_t, uint32_t>> order; // (source id, triangle)
  for (uint32_t t : triangles)
    order.emplace_back(b.sourceTriangle[t], t);
  std::sort(order.begin(), order.end());
  DrawList d;
  for (auto [id, t] : order) {
    d.ids.push_back(id);
    for (int k = 0; k < 3; ++k)
      d.indices.push_back(b.merged.mesh.indices[3 * t + k]);
  }
  return d;
}

std::string degrees(double radians) {
  return std::to_string(int(std::lround(radians * 180 / M_PI)));
}

constexpr double kFps = 30; // the check's frame rate (every `frameStep`-th frame of it)

std::string describe(const OutfitPose &pose) {
  const std::string clip = pose.clip ? "clip '" + pose.clip->name + "'" : "the bind pose";
  if (pose.loop)
    return clip + ", cloth loop frame " + std::to_string(pose.frame);
  char at[64];
  std::snprintf(at, sizeof at, " frame %ld (%.3f s)", std::lround(pose.time * kFps), pose.time);
  return clip + at;
}

// The check's cameras around the sphere at `centre` with `radius`, each with its description
// for the error that names it: the impostor camera set, then player-like views (eye height and
// 4 m away, 8 directions).
struct Cameras {
  std::vector<raster::Camera> cameras;
  std::vector<std::string> views;
};
Cameras checkCameras(const HoleCheckOptions &o, const glm::dvec3 &centre, double radius) {
  Cameras c;
  for (uint32_t e = 0; e < o.elevations; ++e)
    for (uint32_t a = 0; a < o.azimuths; ++a) {
      double az = 2 * M_PI * a / o.azimuths, el = 0.5 * M_PI * (e + 0.5) / o.elevations;
      glm::dvec3 dir(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
      c.cameras.push_back(raster::orthographic(centre + dir * (2 * radius), centre, {0, 1, 0},
                                               radius, radius, 0.5 * radius, 3.5 * radius));
      c.views.push_back("orthographic view azimuth " + degrees(az) + " deg, elevation " +
                        degrees(el) + " deg");
    }
  for (double height : {1.7, 4.0})
    for (int a = 0; a < 8; ++a) {
      double az = 2 * M_PI * (a + 0.5) / 8;
      glm::dvec3 eye(centre.x + 4 * std::sin(az), height, centre.z + 4 * std::cos(az));
      c.cameras.push_back(
          raster::perspective(eye, centre, {0, 1, 0}, glm::radians(50.0), 1.0, 0.1, 100.0));
      char eyeAt[64];
      std::snprintf(eyeAt, sizeof eyeAt, "eye at %.1f m height, 4 m away", height);
      c.views.push_back("perspective view azimuth " + degrees(az) + " deg, " + eyeAt);
    }
  return c;
}

// Outfit `oi`'s naive render (the whole body under its garments) against its tagged one (the
// body faces the bake kept) in every frame it wears and every camera, pixel by pixel.
HoleCheck::PerOutfit checkOutfit(const OutfitBakeResult &b, size_t oi,
                                 const std::vector<OutfitPose> &frames,
                                 const std::vector<std::vector<glm::vec3>> &posed,
                                 const Cameras &cams, const HoleCheckOptions &o) {
  const auto &mesh = b.anim.pack.mesh;
  const auto &outfit = b.anim.pack.outfits->outfits[oi];
  const auto &cameras = cams.cameras;
  const int n = int(o.texels);
  HoleCheck::PerOutfit r;
  r.name = outfit.name;
  std::vector<uint32_t> drawn, naive;
  for (uint32_t t = 0; t < b.bodyTriangles; ++t)
    naive.push_back(t);
  for (uint32_t s : outfit.subMeshes) {
    const auto &sub = mesh.subMeshes[s];
    for (uint32_t t = sub.firstIndex / 3; t < (sub.firstIndex + sub.indexCount) / 3; ++t) {
      drawn.push_back(t);
      if (b.sourceTriangle[t] >= b.bodyTriangles)
        naive.push_back(t);
    }
  }
  const DrawList full = drawList(b, naive), tagged = drawList(b, drawn);
  std::vector<uint8_t> kept(b.bodyTriangles, 0);
  for (uint32_t id : tagged.ids)
    if (id < b.bodyTriangles)
      kept[id] = 1;
  std::vector<uint8_t> everSeen(b.bodyTriangles, 0);
  for (size_t f = 0; f < posed.size(); ++f) {
    if (frames[f].loop && frames[f].loop->outfit != oi)
      continue; // another outfit's garment moved: nothing this outfit wears
    const auto &p = posed[f];
    ++r.images;
    std::vector<uint64_t> differing(cameras.size(), 0);
    std::vector<std::vector<uint32_t>> seenIds(cameras.size()), leakedIds(cameras.size());
    parallelFor(cameras.size(), o.threads, [&](size_t j) {
      const auto a = raster::rasterize(p, full.indices, cameras[j], n, n, {false, 1});
      const auto c = raster::rasterize(p, tagged.indices, cameras[j], n, n, {false, 1});
      for (size_t i = 0; i < a.triangle.size(); ++i) {
        const int64_t x = a.triangle[i] < 0 ? -1 : int64_t(full.ids[size_t(a.triangle[i])]);
        const int64_t y = c.triangle[i] < 0 ? -1 : int64_t(tagged.ids[size_t(c.triangle[i])]);
        differing[j] += x != y;
        if (x >= 0 && x < b.bodyTriangles) {
          seenIds[j].push_back(uint32_t(x));
          if (x != y && !kept[size_t(x)])
            leakedIds[j].push_back(uint32_t(x));
        }
      }
    });
    for (size_t j = 0; j < cameras.size(); ++j) {
      r.differingPixels += differing[j];
      for (uint32_t id : seenIds[j])
        everSeen[id] = 1;
      if (differing[j] > r.worstPixels) { // the first of equals: independent of threads
        r.worstPixels = differing[j];
        r.worstFrame = describe(frames[f]);
        r.worstView = cams.views[j];
        auto &ids = leakedIds[j];
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        r.worstLeaked = ids;
      }
    }
  }
  r.images *= cameras.size();
  for (uint32_t t = 0; t < b.bodyTriangles; ++t) {
    r.removed += !kept[t];
    r.neverSeen += !everSeen[t];
    r.removedUnseen += !kept[t] && !everSeen[t];
    if (!kept[t] && everSeen[t])
      r.leaked.push_back(t);
  }
  return r;
}

} // namespace

HoleCheck checkHoles(const OutfitBakeResult &b, const HoleCheckOptions &o) {
  HoleCheck check;
  const auto frames = outfitPoses(b.merged, kFps, o.frameStep, b.loops, o.loopFrames);
  check.frames = uint32_t(frames.size());
  std::vector<std::vector<glm::vec3>> posed;
  for (const auto &pose : frames) {
    auto p = crowd::posed(b.merged, pose);
    posed.emplace_back(p.begin(), p.end());
  }
  // Framed on the exact poses it renders (not the pack's bounding sphere, which depends on how
  // the animation is stored): their box's centre and the farthest vertex from it.
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto &p : posed)
    for (const auto &q : p) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
  const glm::dvec3 centre((lo + hi) * 0.5f);
  double radius = 0;
  for (const auto &p : posed)
    for (const auto &q : p)
      radius = std::max(radius, glm::length(glm::dvec3(q) - centre));
  const Cameras cameras = checkCameras(o, centre, radius);
  check.views = uint32_t(cameras.cameras.size());
  for (size_t oi = 0; oi < b.anim.pack.outfits->outfits.size(); ++oi)
    check.outfits.push_back(checkOutfit(b, oi, frames, posed, cameras, o));
  return check;
}

} // namespace crowd
