#include "crowd/bake/impostor_bake.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/parallel.h"
#include "crowd/bake/raster.h"
#include "crowd/formats/bc5.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/impostor_runtime.h"
#include "crowd/runtime/pose.h"
#include "impostor_pose.h"

namespace crowd {

using impostor::pose;
using impostor::Posed;

namespace {

struct Crop {
  uint32_t x0 = 0, y0 = 0, width = 0, height = 0;
  float planeOffset = 0, slopeX = 0, slopeY = 0;
  std::vector<float> oct;      // the normal, octahedral: 2 per texel
  std::vector<float> uv;       // u, v wrapped into 0..1: 2 per texel; empty without UVs
  std::vector<uint8_t> region; // region id + 1 (0: empty)
};

// The best plane of one rendered view (pack::ImpostorView's): z = offset + slopeX x + slopeY y
// in the view's frame, through the depths of the silhouette's texels (covered, with an empty
// 4-neighbour), where parallax moves the outline between views; least absolute distance, by
// reweighted least squares from the median depth. Too few texels to tilt it (a line, a dot): the
// view-facing plane at the median depth.
void fitPlane(const raster::Image &img, int n, double radius, Crop &cr) {
  // Orthographic: NDC depth maps linearly onto [near, far] = [0.5 r, 3.5 r] from the camera,
  // which sits 2 r from the centre.
  auto z = [&](size_t i) {
    return 2 * radius - (0.5 * radius + (img.depth[i] + 1.0) * 1.5 * radius);
  };
  std::vector<glm::dvec3> edge; // x, y, z of each silhouette texel
  std::vector<double> depths;
  for (int y = int(cr.y0); y < int(cr.y0 + cr.height); ++y)
    for (int x = int(cr.x0); x < int(cr.x0 + cr.width); ++x) {
      const size_t i = img.index(x, y);
      if (img.triangle[i] < 0)
        continue;
      depths.push_back(z(i));
      bool outline = false;
      for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int xx = x + dx, yy = y + dy;
        outline |= xx < 0 || yy < 0 || xx >= n || yy >= n || img.triangle[img.index(xx, yy)] < 0;
      }
      if (outline)
        edge.push_back({((x + 0.5) / n * 2 - 1) * radius, (1 - (y + 0.5) / n * 2) * radius, z(i)});
    }
  std::nth_element(depths.begin(), depths.begin() + long(depths.size() / 2), depths.end());
  cr.planeOffset = float(depths[depths.size() / 2]);
  glm::dvec3 plane(cr.planeOffset, 0, 0); // offset, slope x, slope y
  for (int iteration = 0; iteration < 10; ++iteration) {
    glm::dmat3 normal(0);
    glm::dvec3 right(0);
    for (const glm::dvec3 &p : edge) {
      const glm::dvec3 row(1, p.x, p.y);
      const double w = 1 / std::max(std::abs(p.z - glm::dot(row, plane)), 1e-3 * radius);
      normal += w * glm::outerProduct(row, row);
      right += w * p.z * row;
    }
    // At most the diagonal's product (positive semi-definite); near 0: every texel on a line.
    if (!(glm::determinant(normal) > 1e-9 * normal[0][0] * normal[1][1] * normal[2][2]))
      return;
    plane = glm::inverse(normal) * right;
  }
  if (!std::isfinite(plane.x + plane.y + plane.z))
    return;
  cr.planeOffset = float(plane.x);
  cr.slopeX = std::clamp(float(plane.y), -pack::kMaxPlaneSlope, pack::kMaxPlaneSlope);
  cr.slopeY = std::clamp(float(plane.z), -pack::kMaxPlaneSlope, pack::kMaxPlaneSlope);
}

// Encodes the frames' normals and UVs into BC5 blocks (frames in parallel: the bytes never depend
// on the threads) and measures what that costs over the covered texels.
ImpostorCompression compressAtlases(pack::Impostor &m, const std::vector<float> &oct,
                                    const std::vector<float> &uv, int threads) {
  const size_t texels = m.frameTexels(), blocks = pack::bc5Bytes(m.atlasWidth, m.atlasHeight);
  m.normals.assign(m.frames * blocks, 0);
  if (!uv.empty())
    m.uvs.assign(m.normals.size(), 0);
  std::vector<ImpostorCompression> per(m.frames);
  parallelFor(m.frames, threads, [&](size_t f) {
    const uint8_t *used = &m.regions[f * texels];
    auto n = pack::encodeBc5(&oct[f * texels * 2], used, m.atlasWidth, m.atlasHeight);
    std::copy(n.begin(), n.end(), m.normals.begin() + long(f * blocks));
    if (!uv.empty()) {
      auto u = pack::encodeBc5(&uv[f * texels * 2], used, m.atlasWidth, m.atlasHeight);
      std::copy(u.begin(), u.end(), m.uvs.begin() + long(f * blocks));
    }
    const pack::ImpostorTexels t = pack::decodeTexels(m, uint32_t(f));
    ImpostorCompression &c = per[f];
    for (size_t i = 0; i < texels; ++i) {
      if (used[i] == 0)
        continue;
      ++c.texels;
      const auto a = pack::octDecode(oct[(f * texels + i) * 2], oct[(f * texels + i) * 2 + 1]);
      const auto b = t.normal(i);
      double angle = glm::degrees(
          std::acos(std::clamp(double(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]), -1.0, 1.0)));
      c.normalMeanDeg += angle, c.normalMaxDeg = std::max(c.normalMaxDeg, angle);
      if (!uv.empty()) {
        double du = uv[(f * texels + i) * 2] - t.uv[i * 2];
        double dv = uv[(f * texels + i) * 2 + 1] - t.uv[i * 2 + 1];
        double d = std::sqrt(du * du + dv * dv);
        c.uvMean += d, c.uvMax = std::max(c.uvMax, d);
      }
    }
  });
  ImpostorCompression all;
  for (const auto &c : per) {
    all.texels += c.texels;
    all.normalMeanDeg += c.normalMeanDeg, all.uvMean += c.uvMean;
    all.normalMaxDeg = std::max(all.normalMaxDeg, c.normalMaxDeg);
    all.uvMax = std::max(all.uvMax, c.uvMax);
  }
  if (all.texels)
    all.normalMeanDeg /= double(all.texels), all.uvMean /= double(all.texels);
  return all;
}

// The clip shown: the named one, else the first; none is the rest pose, said.
const AnimationClip *chosenClip(const Character &c, const ImpostorOptions &o, Reporter &reporter) {
  const AnimationClip *clip = nullptr;
  for (const auto &cl : c.clips)
    if (o.clip.empty() ? !clip : cl.name == o.clip)
      clip = &cl;
  if (!o.clip.empty() && !clip)
    throw unknownName("clip", o.clip, c.clipNames());
  if (!clip)
    reporter.warn("no_animation", "no animation: the impostor shows the rest pose");
  return clip;
}

// The sphere around every posed frame, a texel of margin around the silhouette.
struct Sphere {
  glm::dvec3 centre;
  double radius;
};
Sphere sphereOf(const std::vector<Posed> &posed) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto &p : posed)
    for (const auto &q : p.positions) {
      lo = glm::min(lo, glm::dvec3(q));
      hi = glm::max(hi, glm::dvec3(q));
    }
  glm::dvec3 centre = (lo + hi) * 0.5;
  double radius = 0;
  for (const auto &p : posed)
    for (const auto &q : p.positions)
      radius = std::max(radius, glm::length(glm::dvec3(q) - centre));
  return {centre, std::max(radius * 1.02, 1e-6)};
}

// Each triangle's region id: its sub-mesh + 1, clamped to 255.
std::vector<uint8_t> triangleRegions(const Character &c) {
  std::vector<uint8_t> region(c.mesh.indices.size() / 3, 0);
  for (size_t p = 0; p < c.mesh.parts.size(); ++p)
    for (uint32_t t = c.mesh.parts[p].firstIndex / 3;
         t < (c.mesh.parts[p].firstIndex + c.mesh.parts[p].indexCount) / 3; ++t)
      region[t] = uint8_t(std::min<size_t>(p + 1, 255));
  return region;
}

// One view of one posed frame rendered at n x n texels from (az, el) and cropped to what it
// covers: its plane, normals, regions and (with UVs) texture coordinates.
Crop renderView(const Character &c, const Posed &posed, const std::vector<uint8_t> &region,
                glm::dvec3 centre, double radius, double az, double el, int n, bool hasUvs) {
  const glm::dvec3 dir = runtime::impostorViewFrame(az, el).dir;
  auto cam = raster::orthographic(centre + dir * (2 * radius), centre, {0, 1, 0}, radius, radius,
                                  0.5 * radius, 3.5 * radius);
  raster::Image img = raster::rasterize(posed.positions, c.mesh.indices, cam, n, n, {true, 1});
  int x0 = n, y0 = n, x1 = -1, y1 = -1;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (img.triangle[img.index(x, y)] >= 0) {
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
      }
  Crop cr;
  if (x1 < 0)
    return cr; // nothing in view
  cr.x0 = uint32_t(x0), cr.y0 = uint32_t(y0);
  cr.width = uint32_t(x1 - x0 + 1), cr.height = uint32_t(y1 - y0 + 1);
  fitPlane(img, n, radius, cr);
  cr.oct.assign(size_t(cr.width) * cr.height * 2, 0.5f);
  cr.region.assign(size_t(cr.width) * cr.height, 0);
  if (hasUvs)
    cr.uv.assign(size_t(cr.width) * cr.height * 2, 0);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      size_t pi = img.index(x, y);
      if (img.triangle[pi] < 0)
        continue;
      glm::vec3 nn = raster::interpolate(img, pi, posed.normals, c.mesh.indices);
      float len = glm::length(nn);
      nn = len > 0 ? nn / len : glm::vec3(0, 1, 0);
      const size_t t = size_t(y - y0) * cr.width + size_t(x - x0);
      const auto oct = pack::octEncode({nn.x, nn.y, nn.z});
      cr.oct[t * 2] = oct[0], cr.oct[t * 2 + 1] = oct[1];
      cr.region[t] = region[size_t(img.triangle[pi])];
      if (hasUvs) {
        glm::vec2 uv = raster::interpolate(img, pi, c.mesh.uvs, c.mesh.indices);
        for (int k = 0; k < 2; ++k) // wrapped into [0, 1): textures repeat
          cr.uv[t * 2 + size_t(k)] = uv[k] - std::floor(uv[k]);
      }
    }
  return cr;
}

// Mirroring, measured: a walk's frame t + T/2 is close to frame t mirrored left-right, and the
// mirror of the view from azimuth a is the view from -a flipped horizontally. Silhouette IoU
// over every view says how close (1: mirroring half the azimuths would lose nothing).
void measureMirror(const std::vector<Crop> &crops, const ImpostorOptions &o, int n,
                   ImpostorBakeResult &r) {
  const size_t views = size_t(o.azimuths) * o.elevations;
  auto covered = [&](const Crop &cr, int x, int y) {
    if (x < int(cr.x0) || y < int(cr.y0) || x >= int(cr.x0 + cr.width) ||
        y >= int(cr.y0 + cr.height))
      return false;
    return cr.region[size_t(y - int(cr.y0)) * cr.width + size_t(x - int(cr.x0))] > 0;
  };
  std::vector<double> iou(crops.size(), 1.0);
  parallelFor(crops.size(), o.threads, [&](size_t i) {
    size_t f = i / views, e = (i % views) / o.azimuths, a = i % o.azimuths;
    size_t j =
        ((f + o.frames / 2) % o.frames) * views + e * o.azimuths + (o.azimuths - a) % o.azimuths;
    size_t both = 0, either = 0;
    const Crop &ci = crops[i], &cj = crops[j]; // only the union of the two boxes can differ
    int xs = std::min(int(ci.x0), n - int(cj.x0 + cj.width)),
        xe = std::max(int(ci.x0 + ci.width), n - int(cj.x0));
    int ys = std::min(ci.y0, cj.y0), ye = std::max(ci.y0 + ci.height, cj.y0 + cj.height);
    for (int y = ys; y < ye; ++y)
      for (int x = std::max(xs, 0); x < std::min(xe, n); ++x) {
        bool p = covered(crops[i], x, y), q = covered(crops[j], n - 1 - x, y);
        both += p && q;
        either += p || q;
      }
    if (either)
      iou[i] = double(both) / double(either);
  });
  r.mirrorIouMin = *std::min_element(iou.begin(), iou.end());
  r.mirrorIouMean = std::accumulate(iou.begin(), iou.end(), 0.0) / double(iou.size());
}

// Where each stored view goes in its frame's atlas plane.
struct Layout {
  uint32_t width = 0, height = 0;
  std::vector<std::array<uint32_t, 2>> place; // per crop
  uint64_t area = 0;                          // texels the stored crops cover
};

// Each frame's views shelf-packed, tallest first (ties by view index: the same layout at any
// thread count), into rows `width` wide; the atlas is as tall as the tallest frame. The width is
// the one of a range around the square's that wastes least.
Layout packViews(const std::vector<Crop> &crops, const std::vector<size_t> &stored, uint32_t frames,
                 Reporter &reporter) {
  Layout l;
  uint32_t widest = 1;
  size_t empty = 0;
  for (size_t i : stored) {
    l.area += uint64_t(crops[i].width) * crops[i].height;
    widest = std::max(widest, crops[i].width);
    empty += crops[i].width == 0;
  }
  if (l.area == 0)
    throw Error("the character covers no texel in any view: its mesh is empty, degenerate "
                "(every triangle has zero area) or thinner than a texel everywhere (raise "
                "--texels)");
  if (empty)
    reporter.warn("empty_views", std::to_string(empty) + " of " + std::to_string(stored.size()) +
                                     " views show nothing (a flat mesh seen edge-on?): they "
                                     "are stored empty and draw nothing");
  const size_t storedPerFrame = stored.size() / frames;
  std::vector<std::vector<size_t>> orders(frames);
  for (uint32_t f = 0; f < frames; ++f) {
    orders[f].assign(stored.begin() + long(f * storedPerFrame),
                     stored.begin() + long((f + 1) * storedPerFrame));
    std::stable_sort(orders[f].begin(), orders[f].end(),
                     [&](size_t a, size_t b) { return crops[a].height > crops[b].height; });
  }
  l.place.resize(crops.size());
  auto shelve = [&](uint32_t width) {
    uint32_t height = 1;
    for (const auto &order : orders) {
      uint32_t x = 0, y = 0, shelf = 0;
      for (size_t i : order) {
        if (x + crops[i].width > width)
          x = 0, y += shelf, shelf = 0;
        l.place[i] = {x, y};
        x += crops[i].width;
        shelf = std::max(shelf, crops[i].height);
      }
      height = std::max(height, y + shelf);
    }
    return (height + 3) / 4 * 4; // whole blocks
  };
  const double side = std::sqrt(double(l.area) / frames);
  const uint32_t first = (std::max(widest, uint32_t(side * 0.9)) + 3) / 4 * 4;
  for (uint32_t trial = first; trial <= std::max(first, uint32_t(side * 1.5)); trial += 4) {
    const uint32_t h = shelve(trial);
    if (l.width == 0 || uint64_t(trial) * h < uint64_t(l.width) * l.height)
      l.width = trial, l.height = h;
  }
  shelve(l.width);
  if (l.width > 16384 || l.height > 16384)
    throw Error("impostor atlas would be " + std::to_string(l.width) + "x" +
                std::to_string(l.height) + ", larger than 16384: lower --texels or --views");
  return l;
}

// The stored crops copied into the atlas planes at their places, and their views' records.
void fillAtlas(const std::vector<Crop> &crops, const std::vector<size_t> &stored, const Layout &l,
               size_t views, int n, pack::Impostor &m, std::vector<float> &oct,
               std::vector<float> &uv) {
  const bool hasUvs = !uv.empty();
  m.views.resize(stored.size());
  for (size_t k = 0; k < stored.size(); ++k) {
    size_t i = stored[k];
    const Crop &cr = crops[i];
    size_t f = i / views;
    m.views[k] = {uint16_t(l.place[i][0]),
                  uint16_t(l.place[i][1]),
                  uint16_t(cr.width),
                  uint16_t(cr.height),
                  float(n) * 0.5f - float(cr.x0),
                  float(n) * 0.5f - float(cr.y0),
                  cr.planeOffset,
                  cr.slopeX,
                  cr.slopeY};
    for (uint32_t y = 0; y < cr.height; ++y) {
      size_t to = (f * l.height + l.place[i][1] + y) * l.width + l.place[i][0],
             from = size_t(y) * cr.width;
      std::copy_n(&cr.oct[from * 2], size_t(cr.width) * 2, &oct[to * 2]);
      std::copy_n(&cr.region[from], cr.width, &m.regions[to]);
      if (hasUvs)
        std::copy_n(&cr.uv[from * 2], size_t(cr.width) * 2, &uv[to * 2]);
    }
  }
}

} // namespace

uint32_t texelsAtSwitchDistance(double radius, const ImpostorOptions &o) {
  // The player's one-texel-per-pixel distance, 2 r / texels * H / (2 tan(fov / 2)), solved for
  // texels and rounded up: at the switch distance a texel is at most a pixel.
  const double t =
      radius * o.screenHeight / (o.switchDistance * std::tan(glm::radians(o.fovDegrees) / 2));
  const double rounded = std::ceil(std::min(t, 1e6) / 4) * 4; // past the cap: bakeImpostor warns
  return uint32_t(std::clamp(rounded, 4.0, 1e6));
}

// The stages: the clip's frames posed and their sphere, the texels, every view of every frame
// rendered and cropped, mirroring measured, the stored views shelf-packed and copied into the
// atlas, then compressed.
ImpostorBakeResult bakeImpostor(const Character &c, const ImpostorOptions &options,
                                Reporter &reporter) {
  options.validate();
  ImpostorOptions o = options; // texels set from the switch distance once the sphere is known
  const uint64_t views = uint64_t(o.azimuths) * o.elevations;
  const AnimationClip *clip = chosenClip(c, o, reporter);
  if (c.mesh.parts.size() > 255)
    reporter.warn("too_many_regions", std::to_string(c.mesh.parts.size()) +
                                          " sub-meshes: region ids above 254 are clamped");
  pack::Impostor m;
  m.clip = clip ? clip->name : "rest";
  m.frames = o.frames;
  m.azimuths = o.azimuths;
  m.elevations = o.elevations;
  m.texels = o.texels;
  m.mirrored = o.mirror;
  m.startTime = clip ? float(clip->start) : 0.0f;
  // A looping clip's end pose repeats its start, so frames split [start, end) evenly.
  m.frameStep = clip ? float((clip->end - clip->start) / o.frames) : 0.0f;
  std::vector<Posed> posed(o.frames);
  parallelFor(o.frames, o.threads, [&](size_t f) {
    posed[f] = pose(c, clip, double(m.startTime) + double(f) * double(m.frameStep));
  });
  const auto [centre, radius] = sphereOf(posed);
  m.sphere = {float(centre.x), float(centre.y), float(centre.z), float(radius)};
  if (o.switchDistance > 0) {
    const uint32_t needed = texelsAtSwitchDistance(radius, o);
    m.texels = o.texels = std::min(needed, limits::kAutoImpostorTexels);
    if (needed > o.texels)
      reporter.warn("texels_clamped",
                    "the switch distance needs " + std::to_string(needed) +
                        " texels a view (a texel a pixel there); clamped to " +
                        std::to_string(o.texels) +
                        ": a texel covers more than a pixel at the switch (switch farther away)");
  }
  const uint64_t naive = uint64_t(o.frames) * views * o.texels * o.texels * 4;
  if (naive > o.maxBytes)
    throw Error("impostor would need " + std::to_string(naive >> 20) +
                " MiB of uncropped views (limit " + std::to_string(o.maxBytes >> 20) +
                " MiB): lower --frames, --views or --texels");
  const std::vector<uint8_t> region = triangleRegions(c);
  const bool hasUvs = !c.mesh.uvs.empty();
  if (!hasUvs)
    reporter.warn("no_uvs", "the mesh has no UVs: the impostor's UV map is left out");

  reporter.step("impostor: " + std::to_string(views) + " views of " + std::to_string(o.frames) +
                " frames at " + std::to_string(o.texels) + " texels");
  const int n = int(o.texels);
  std::vector<Crop> crops(size_t(o.frames) * views);
  parallelFor(crops.size(), o.threads, [&](size_t i) {
    size_t f = i / views, e = (i % views) / o.azimuths, a = i % o.azimuths;
    double az = 2 * std::numbers::pi * double(a) / o.azimuths,
           el = 0.5 * std::numbers::pi * (double(e) + 0.5) / o.elevations;
    crops[i] = renderView(c, posed[f], region, centre, radius, az, el, n, hasUvs);
  });
  ImpostorBakeResult r;
  if (o.frames % 2 == 0 && clip)
    measureMirror(crops, o, n, r);
  if (o.mirror && !clip)
    throw Error("--mirror needs a clip (a walk's frame t + T/2 mirrors frame t)");
  // The views the pack keeps, in pack order: all, or azimuths 0..A/2 when mirrored.
  std::vector<size_t> stored;
  for (size_t i = 0; i < crops.size(); ++i)
    if (i % o.azimuths < m.storedAzimuths())
      stored.push_back(i);
  const Layout layout = packViews(crops, stored, o.frames, reporter);
  m.atlasWidth = layout.width;
  m.atlasHeight = layout.height;
  const size_t texels = size_t(layout.width) * layout.height;
  std::vector<float> oct(size_t(o.frames) * texels * 2, 0.5f), uv;
  m.regions.assign(size_t(o.frames) * texels, 0);
  if (hasUvs)
    uv.assign(oct.size(), 0);
  fillAtlas(crops, stored, layout, views, n, m, oct, uv);
  r.compression = compressAtlases(m, oct, uv, o.threads);
  r.compression.textureWidth = c.diffuse ? uint32_t(c.diffuse->width) : 0;
  r.compression.regionBits = m.regionBits();
  r.occupancy = double(layout.area) / (double(o.frames) * layout.width * layout.height);
  r.bytesPerFrame = m.bytesPerFrame();
  r.naiveBytesPerFrame = views * o.texels * o.texels * (hasUvs ? 3 : 2);
  r.impostor = std::move(m);
  return r;
}

} // namespace crowd
