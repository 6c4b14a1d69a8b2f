// measureImpostor (impostor_bake.h): the impostor as the player draws it against the skinned
// mesh, at the stored views, halfway between them, and along a slow orbit (popping).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "crowd/bake/impostor_bake.h"
#include "crowd/bake/parallel.h"
#include "crowd/bake/raster.h"
#include "crowd/runtime/impostor_runtime.h"
#include "impostor_pose.h"

namespace crowd {
namespace {

// One camera direction's figures.
struct ViewResult {
  double iou = 1, angleSum = 0, angleMax = 0, uvSum = 0, uvMax = 0;
  size_t angles = 0;
};

// The reference (the mesh posed at the impostor's first frame) against the impostor as the
// player draws it (runtime::sampleImpostor: the three stored views around the direction,
// blended), one camera direction at a time.
class ViewComparison {
public:
  ViewComparison(const Character &c, const pack::Impostor &m) : c_(c), m_(m) {
    const AnimationClip *clip = nullptr;
    for (const auto &cl : c.clips)
      if (cl.name == m.clip)
        clip = &cl;
    posed_ = impostor::pose(c, clip, m.startTime);
    // The frames drawn, decoded as the GPU samples them: frame 0, and the one its mirrored views
    // come from.
    layers_.resize(m.frames);
    layers_[0] = pack::decodeTexels(m, 0);
    if (m.mirrored)
      layers_[m.frames / 2] = pack::decodeTexels(m, m.frames / 2);
  }

  // The stored views' directions: azimuth `a`, elevation row `e` (fractional between rows).
  double sampledAz(uint32_t a) const { return 2 * std::numbers::pi * a / m_.azimuths; }
  double sampledEl(double e) const { return 0.5 * std::numbers::pi * (e + 0.5) / m_.elevations; }

  // The figures looking from azimuth `az` and elevation `el`; where `geometryGrey` is given, a
  // grey per pixel of the geometry and of the impostor too (popping).
  void look(double az, double el, ViewResult &r, std::vector<float> *geometryGrey,
            std::vector<float> *impostorGrey) const {
    const glm::dvec3 centre(m_.sphere[0], m_.sphere[1], m_.sphere[2]);
    const double radius = m_.sphere[3];
    const int n = int(m_.texels);
    const runtime::ImpostorFrame cam = runtime::impostorViewFrame(az, el);
    auto camera = raster::orthographic(centre + cam.dir * (2 * radius), centre, {0, 1, 0}, radius,
                                       radius, 0.5 * radius, 3.5 * radius);
    raster::Image reference =
        raster::rasterize(posed_.positions, c_.mesh.indices, camera, n, n, {true, 1});
    const runtime::ImpostorChoice choice =
        runtime::chooseImpostorViews(m_, cam.dir, 0.0, false); // frame 0
    size_t both = 0, either = 0;
    if (geometryGrey)
      geometryGrey->assign(size_t(n) * size_t(n), 0.0f), impostorGrey->assign(size_t(n) * n, 0.0f);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const glm::dvec3 p = centre + cam.right * (((x + 0.5) / n * 2 - 1) * radius) +
                             cam.up * ((1 - (y + 0.5) / n * 2) * radius);
        const runtime::ImpostorSample drawn =
            runtime::sampleImpostor(m_, layers_, choice, p, -cam.dir);
        const size_t ti = reference.index(x, y);
        const bool real = reference.triangle[ti] >= 0;
        both += real && drawn.covered;
        either += real || drawn.covered;
        if (geometryGrey && drawn.covered)
          (*impostorGrey)[ti] = grey(drawn.normal);
        if (!real)
          continue;
        const glm::dvec3 actual = glm::normalize(
            glm::dvec3(raster::interpolate(reference, ti, posed_.normals, c_.mesh.indices)));
        if (geometryGrey)
          (*geometryGrey)[ti] = grey(actual);
        if (!drawn.covered)
          continue;
        const double angle =
            glm::degrees(std::acos(std::clamp(glm::dot(drawn.normal, actual), -1.0, 1.0)));
        r.angleSum += angle;
        r.angleMax = std::max(r.angleMax, angle);
        ++r.angles;
        if (!layers_[0].uv.empty()) { // both wrapped into [0, 1): compare around the circle
          const glm::vec2 trueUv = raster::interpolate(reference, ti, c_.mesh.uvs, c_.mesh.indices);
          double d2 = 0;
          for (int k = 0; k < 2; ++k) {
            double d = std::abs(drawn.uv[k] - (trueUv[k] - std::floor(trueUv[k])));
            d = std::min(d, 1.0 - d);
            d2 += d * d;
          }
          r.uvSum += std::sqrt(d2);
          r.uvMax = std::max(r.uvMax, std::sqrt(d2));
        }
      }
    r.iou = either ? double(both) / double(either) : 1.0;
  }

private:
  // A grey per pixel, lit from a fixed object-space light (0 where empty, 0.2 to 1 covered), of
  // the geometry and of the impostor: what the popping measure compares between frames.
  static float grey(glm::dvec3 normal) {
    static const glm::dvec3 light = glm::normalize(glm::dvec3(0.3, 0.9, 0.3));
    return float(0.2 + 0.8 * std::max(0.0, glm::dot(normal, light)));
  }

  const Character &c_;
  const pack::Impostor &m_;
  impostor::Posed posed_;
  std::vector<pack::ImpostorTexels> layers_;
};

// Popping: a slow orbit around the walker at the lowest row's elevation, kOrbitSteps a view
// apart; the mean per-pixel change of the grey between consecutive steps, for the geometry and
// for the impostor. The geometry changes a little every step; a nearest-view impostor would stand
// still, then jump where the nearest view changes (7.9 times the geometry's largest step on the
// sample walk at 32x8); the blend moves the weight over instead.
ImpostorAccuracy::Popping measurePopping(const ViewComparison &views, const pack::Impostor &m,
                                         int threads) {
  const size_t steps = size_t(m.azimuths) * kOrbitSteps;
  std::vector<std::vector<float>> geometry(steps), impostor(steps);
  parallelFor(steps, threads, [&](size_t s) {
    ViewResult unused;
    views.look(2 * std::numbers::pi * double(s) / double(steps), views.sampledEl(0), unused,
               &geometry[s], &impostor[s]);
  });
  ImpostorAccuracy::Popping pop;
  pop.steps = uint32_t(steps);
  pop.elevationDeg = glm::degrees(views.sampledEl(0));
  for (size_t s = 0; s < steps; ++s) {
    const size_t prev = (s + steps - 1) % steps;
    double g = 0, im = 0;
    for (size_t k = 0; k < geometry[s].size(); ++k) {
      g += std::abs(geometry[s][k] - geometry[prev][k]);
      im += std::abs(impostor[s][k] - impostor[prev][k]);
    }
    g *= 255.0 / double(geometry[s].size()), im *= 255.0 / double(geometry[s].size());
    pop.geometryMean += g / double(steps), pop.impostorMean += im / double(steps);
    pop.geometryMax = std::max(pop.geometryMax, g), pop.impostorMax = std::max(pop.impostorMax, im);
  }
  return pop;
}

// The directions' results (every stored view, then each halfway to the next azimuth and
// elevation) summed into the figures at and between the views, and the worst direction.
void summariseViews(const std::vector<ViewResult> &results, const ViewComparison &views,
                    const pack::Impostor &m, ImpostorAccuracy &acc) {
  const size_t count = size_t(m.azimuths) * m.elevations;
  for (int part = 0; part < 2; ++part) {
    ImpostorAccuracy::Figures &f = part ? acc.betweenViews : acc.atViews;
    double angleSum = 0, uvSum = 0;
    size_t angles = 0;
    f.iouMeanByElevation.assign(m.elevations, 0.0);
    for (size_t k = 0; k < count; ++k) {
      const ViewResult &r = results[size_t(part) * count + k];
      f.iouMeanByElevation[k / m.azimuths] += r.iou / double(m.azimuths);
      uvSum += r.uvSum;
      f.uvMax = std::max(f.uvMax, r.uvMax);
      f.iouMean += r.iou / double(count);
      f.iouMin = std::min(f.iouMin, r.iou);
      f.normalMaxDeg = std::max(f.normalMaxDeg, r.angleMax);
      angleSum += r.angleSum;
      angles += r.angles;
      if (r.iou < acc.worstIou) {
        acc.worstIou = r.iou;
        acc.worstAzimuthDeg = glm::degrees(views.sampledAz(uint32_t(k % m.azimuths))) +
                              (part ? 180.0 / m.azimuths : 0);
        size_t e = k / m.azimuths;
        acc.worstElevationDeg =
            glm::degrees(views.sampledEl(double(e) + (part && e + 1 < m.elevations ? 0.5 : 0)));
      }
    }
    f.normalMeanDeg = angles ? angleSum / double(angles) : 0;
    f.uvMean = angles ? uvSum / double(angles) : 0;
  }
}

} // namespace

ImpostorAccuracy measureImpostor(const Character &c, const pack::Impostor &m, int threads) {
  const ViewComparison views(c, m);
  // Directions: at every sampled view, then halfway to the next azimuth and elevation.
  const size_t count = size_t(m.azimuths) * m.elevations;
  std::vector<ViewResult> results(2 * count);
  parallelFor(results.size(), threads, [&](size_t i) {
    bool between = i >= count;
    size_t k = i % count, e = k / m.azimuths, a = k % m.azimuths;
    double half = between ? 0.5 : 0.0;
    // Halfway up too, except above the top row: there the views stop (and looking straight
    // down leaves the camera's "up" undefined).
    views.look(views.sampledAz(uint32_t(a)) + half * 2 * std::numbers::pi / m.azimuths,
               views.sampledEl(double(e) + (e + 1 < m.elevations ? half : 0.0)), results[i],
               nullptr, nullptr);
  });
  ImpostorAccuracy acc;
  summariseViews(results, views, m, acc);
  acc.popping = measurePopping(views, m, threads);
  return acc;
}

} // namespace crowd
