#include "crowd/runtime/lod_select.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <utility>

#include "crowd/runtime/impostor_runtime.h"

namespace crowd::runtime {

Frustum::Frustum(const glm::mat4 &m) {
  // Gribb and Hartmann: a clip-space plane is a row of the matrix plus or minus the w row.
  auto row = [&](int r) { return glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
  for (int k = 0; k < 3; ++k) {
    planes_[size_t(2 * k)] = row(3) + row(k);
    planes_[size_t(2 * k + 1)] = row(3) - row(k);
  }
  for (auto &p : planes_)
    p /= glm::length(glm::vec3(p));
}

namespace {

void tabulate(LodLevels &l) {
  l.finestWithin.assign(size_t(l.triangles.back()) + 1, 0);
  for (size_t k = 1; k < l.triangles.size(); ++k)
    std::fill(l.finestWithin.begin() + ptrdiff_t(l.triangles[k]), l.finestWithin.end(),
              uint32_t(k));
}

} // namespace

LodLevels lodLevels(const pack::AnimationPack &pack, double step) {
  const auto &mesh = pack.mesh;
  const auto V = uint32_t(mesh.vertexCount());
  LodLevels l;
  if (!pack.lod) {
    l.vertices = {V};
    l.triangles = {mesh.indices.size() / 3};
    tabulate(l);
    return l;
  }
  const auto &lod = *pack.lod;
  for (uint32_t v = lod.floorVertices; v <= V; ++v) {
    uint64_t t = lod.totalTriangles(v);
    if (l.vertices.empty() || double(t) >= double(l.triangles.back()) * (1 + step)) {
      l.vertices.push_back(v);
      l.triangles.push_back(t);
    }
  }
  if (l.vertices.back() != V) { // the full mesh is always a level
    if (l.triangles.back() == lod.totalTriangles(V))
      l.vertices.pop_back(), l.triangles.pop_back();
    l.vertices.push_back(V);
    l.triangles.push_back(lod.totalTriangles(V));
  }
  tabulate(l);
  return l;
}

std::vector<uint32_t> lodIndices(const pack::AnimationPack &pack, uint32_t vertices,
                                 std::vector<uint32_t> &starts) {
  const auto &mesh = pack.mesh;
  std::vector<uint32_t> out;
  starts.clear();
  for (size_t s = 0; s < mesh.subMeshes.size(); ++s) {
    const auto &sub = mesh.subMeshes[s];
    starts.push_back(uint32_t(out.size()));
    if (!pack.lod || vertices >= mesh.vertexCount()) {
      out.insert(out.end(), mesh.indices.begin() + sub.firstIndex,
                 mesh.indices.begin() + sub.firstIndex + sub.indexCount);
      continue;
    }
    const auto &collapse = pack.lod->collapse;
    const uint32_t n = 3 * pack.lod->triangleCount(s, vertices);
    for (uint32_t k = 0; k < n; ++k) {
      uint32_t i = mesh.indices[sub.firstIndex + k];
      while (i >= vertices) // the reader checked collapse[i] < i, so this ends
        i = collapse[i];
      out.push_back(i);
    }
  }
  starts.push_back(uint32_t(out.size()));
  return out;
}

namespace {

// Cube root of x > 0 to ~1e-6 relative: a guess from the float's bits (the exponent divided by
// 3), then two Newton steps. libm's cbrtf was a third of the selection's time.
float cubeRoot(float x) {
  float y = std::bit_cast<float>(std::bit_cast<uint32_t>(x) / 3 + 709921077u);
  for (int k = 0; k < 2; ++k)
    y -= (y * y * y - x) / (3 * y * y);
  return y;
}

} // namespace

float lodWeight(float distanceSquared, float radius, float pixelsPerUnit) {
  const float d2 = std::max({distanceSquared, radius * radius, 1e-12f});
  const float r = radius * pixelsPerUnit;
  const float area = 3.14159265f * r * r / d2; // pixels
  return cubeRoot(area) / std::sqrt(d2);
}

uint64_t chooseLevels(std::span<Visible> visible, std::span<const LodLevels> ladders,
                      uint64_t budget) {
  uint64_t total = 0;
  if (budget == 0) {
    for (auto &v : visible) {
      v.level = uint32_t(ladders[v.character].vertices.size() - 1);
      total += ladders[v.character].triangles[v.level];
    }
    return total;
  }
  double weights = 0;
  for (auto &v : visible) {
    v.level = 0;
    total += ladders[v.character].triangles[0];
    weights += v.weight;
  }
  if (total >= budget)
    return total;
  // Each pass shares what is left in proportion to the weights of those below their finest
  // level; an instance climbs to the finest rung its share reaches, so no pass overspends.
  double left = double(budget - total);
  for (int pass = 0; pass < 4 && weights > 0 && left >= 1; ++pass) {
    const double scale = left / weights;
    double spent = 0, still = 0;
    for (auto &v : visible) {
      const auto &ladder = ladders[v.character];
      const auto &tri = ladder.triangles;
      if (v.level + 1 == tri.size())
        continue;
      const double target = std::min(double(tri[v.level]) + v.weight * scale, double(tri.back()));
      const uint32_t level = std::max(v.level, ladder.finestWithin[size_t(target)]);
      spent += double(tri[level] - tri[v.level]);
      v.level = level;
      if (level + 1 < tri.size())
        still += v.weight;
    }
    left -= spent;
    total += uint64_t(spent);
    weights = still;
  }
  return total;
}

void CrowdSelection::addCharacter(const pack::AnimationPack &pack, const pack::Impostor *impostor,
                                  const std::array<float, 4> *sphere) {
  Character c;
  const auto &b = sphere ? *sphere : pack.mesh.boundingSphere;
  c.radius = b[3];
  c.boundLocal = {b[0], b[1], b[2]};
  c.impostor = impostor;
  if (impostor)
    c.impostorLocal = {impostor->sphere[0], impostor->sphere[1], impostor->sphere[2]};
  characters.push_back(std::move(c));
  ladders.push_back(lodLevels(pack));
  characters.back().runEnds.resize(ladders.back().vertices.size());
}

void CrowdSelection::addInstance(const glm::vec3 &position, float yaw, bool eligible) {
  Character &c = characters.back();
  c.bounds.emplace_back();
  c.centres.emplace_back();
  c.eligible.push_back(eligible && c.impostor);
  c.far.push_back(0);
  moveInstance(characters.size() - 1, c.bounds.size() - 1, position, yaw);
}

void CrowdSelection::moveInstance(size_t ci, size_t i, const glm::vec3 &position, float yaw) {
  Character &c = characters[ci];
  const float cy = std::cos(yaw), sy = std::sin(yaw);
  auto place = [&](const glm::vec3 &p) {
    return position + glm::vec3(cy * p.x + sy * p.z, p.y, -sy * p.x + cy * p.z);
  };
  c.bounds[i] = place(c.boundLocal);
  c.centres[i] = place(c.impostorLocal);
}

CrowdSelection::Result CrowdSelection::select(const FrameView &view, const DrawOptions &options) {
  const auto t0 = std::chrono::steady_clock::now();
  Result r;
  const bool naive = options.path == DrawPath::Naive;
  const Frustum frustum(view.viewProjection);
  const float pixelsPerUnit =
      float(view.viewportHeight / (2 * std::tan(std::max(view.fovY, 1e-6) / 2)));
  visible_.clear();
  instance_.clear();
  for (uint32_t ci = 0; ci < characters.size(); ++ci) {
    Character &c = characters[ci];
    c.impostorIds.clear();
    impostorOrder_.clear();
    // Past the one-texel-per-pixel distance an eligible instance becomes an impostor, with
    // hysteresis.
    const bool hybrid = options.path == DrawPath::Hybrid && c.impostor;
    const double switchAt =
        hybrid ? oneToOneDistance(*c.impostor, view.fovY, view.viewportHeight) : 0.0;
    const double out = (1 + kImpostorHysteresis) * switchAt,
                 in = (1 - kImpostorHysteresis) * switchAt;
    const double out2 = out * out, in2 = in * in;
    const bool cull = options.cull && !naive;
    for (uint32_t i = 0; i < uint32_t(c.bounds.size()); ++i) {
      if (cull && !frustum.sees(c.bounds[i], c.radius))
        continue; // `far` keeps its state: the instance is not drawn either way
      float d2 = 0;
      if (hybrid && c.eligible[i]) {
        const glm::vec3 e = view.eye - c.centres[i];
        d2 = glm::dot(e, e);
        c.far[i] = options.allImpostors || (c.far[i] ? d2 > in2 : d2 > out2);
      } else {
        c.far[i] = 0;
      }
      if (c.far[i]) {
        impostorOrder_.push_back({d2, i});
        continue;
      }
      const glm::vec3 d = c.bounds[i] - view.eye;
      visible_.push_back({lodWeight(glm::dot(d, d), c.radius, pixelsPerUnit), ci, 0});
      instance_.push_back(i);
    }
    // Nearest first: the depth test then rejects the pixels of impostors hidden behind nearer
    // ones before shading them (llvmpipe tests depth early though the shader discards, and
    // writes it late).
    std::sort(impostorOrder_.begin(), impostorOrder_.end());
    for (const auto &[d2, i] : impostorOrder_)
      c.impostorIds.push_back(i);
    r.impostors += uint32_t(c.impostorIds.size());
  }
  // The geometry's budget: what the impostors' two triangles each leave (at least 1).
  uint64_t budget = 0;
  if (options.budget && !naive)
    budget = options.budget > 2 * uint64_t(r.impostors) + 1
                 ? options.budget - 2 * uint64_t(r.impostors)
                 : 1;
  r.triangles = chooseLevels(visible_, ladders, budget) + 2 * uint64_t(r.impostors);
  if (options.detail > 0 && !naive) {
    r.triangles = 2 * uint64_t(r.impostors);
    for (auto &v : visible_) {
      const auto &ladder = ladders[v.character];
      const double share = std::min(options.detail, 1.0) * double(ladder.triangles.back());
      v.level = ladder.finestWithin[size_t(share)];
      r.triangles += ladder.triangles[v.level];
    }
  }
  // Counting sort by level: runEnds counts, then holds where each run starts, then where it ends.
  for (auto &c : characters)
    std::fill(c.runEnds.begin(), c.runEnds.end(), 0u);
  for (const auto &v : visible_)
    ++characters[v.character].runEnds[v.level];
  for (auto &c : characters) {
    uint32_t start = 0;
    for (auto &n : c.runEnds)
      start += std::exchange(n, start);
    c.ids.resize(start);
  }
  for (size_t k = 0; k < visible_.size(); ++k) {
    Character &c = characters[visible_[k].character];
    c.ids[c.runEnds[visible_[k].level]++] = instance_[k];
  }
  r.visible = uint32_t(visible_.size()) + r.impostors;
  r.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

} // namespace crowd::runtime
