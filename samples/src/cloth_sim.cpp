// The sample cloth caches: the dress simulated over a clip repeated many times, by a small
// extended position-based dynamics solver (XPBD, Macklin et al. 2016, with substeps: Macklin
// et al. 2019). Written for the samples because no Debian package simulates cloth as a library;
// it only needs to be plausible and deterministic, not fast or general:
//   - particles: the garment's vertices, the UV-seam duplicates welded; the bodice and the
//     skirt's waistband follow the skin, the rest hang free (unit mass);
//   - stretch: every triangle edge keeps its bind length; bending: the two vertices opposite
//     each shared edge keep their bind distance (softer);
//   - gravity, velocity damping, and collisions against capsules on the legs and pelvis, which
//     the clip's skeleton drives.
// One Gauss-Seidel pass per substep, constraints in a fixed order: the same build gives the same
// bytes.
#include "crowd/samples/cloth_caches.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>

#include "crowd/support/point_cache.h"
#include "crowd/formats/container.h"
#include "rig.h"

namespace crowd::samples {

namespace {

struct Link {
  uint32_t a, b;
  float rest, compliance;
};

struct Capsule {
  glm::vec3 a, b;
  float radius;
};

glm::vec3 skinned(const rig::Garment &g, const rig::Pose &pose, size_t v) {
  glm::mat4 m(0);
  for (int k = 0; k < 4; ++k)
    m += g.weights[v][k] * pose.skin[g.joints[v][k]];
  return glm::vec3(m * glm::vec4(g.bind[v], 1));
}

// Legs (thigh, shin) and the pelvis, from the posed skeleton, fattened by the cloth's margin.
std::vector<Capsule> capsules(const rig::Pose &pose) {
  const auto at = [&](const char *j) { return glm::vec3(pose.world[size_t(rig::joint(j))][3]); };
  const float margin = 0.015f;
  std::vector<Capsule> out = {{at("thigh_l"), at("thigh_r"), 0.10f + margin}};
  for (const char *side : {"_l", "_r"}) {
    const std::string s = side;
    out.push_back({at(("thigh" + s).c_str()), at(("shin" + s).c_str()), 0.070f + margin});
    out.push_back({at(("shin" + s).c_str()), at(("foot" + s).c_str()), 0.055f + margin});
  }
  return out;
}

void collide(glm::vec3 &p, const Capsule &c) {
  const glm::vec3 ab = c.b - c.a;
  const float t = std::clamp(glm::dot(p - c.a, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
  const glm::vec3 q = c.a + t * ab, d = p - q;
  const float len = glm::length(d);
  if (len < c.radius && len > 1e-6f)
    p = q + d * (c.radius / len);
}

} // namespace

std::vector<std::vector<glm::vec3>> simulateDress(const ClothSettings &s) {
  const rig::Garment g = rig::dress();
  const size_t n = g.bind.size();
  // Weld the UV seam: each vertex simulates as the first vertex at its bind position.
  std::vector<uint32_t> rep(n);
  for (size_t v = 0; v < n; ++v) {
    rep[v] = uint32_t(v);
    for (size_t u = 0; u < v; ++u)
      if (glm::length(g.bind[u] - g.bind[v]) < 1e-5f) {
        rep[v] = rep[u];
        break;
      }
  }
  const auto pinned = [&](uint32_t v) { return v < g.pinned; };
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> opposite; // edge -> far corners
  for (size_t t = 0; t + 2 < g.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) {
      uint32_t a = rep[g.indices[t + e]], b = rep[g.indices[t + (e + 1) % 3]];
      opposite[{std::min(a, b), std::max(a, b)}].push_back(rep[g.indices[t + (e + 2) % 3]]);
    }
  std::vector<Link> links;
  const auto link = [&](uint32_t a, uint32_t b, float compliance) {
    if (a != b && !(pinned(a) && pinned(b)))
      links.push_back({a, b, glm::length(g.bind[a] - g.bind[b]), compliance});
  };
  for (const auto &[edge, far] : opposite) {
    link(edge.first, edge.second, s.stretchCompliance);
    if (far.size() == 2)
      link(far[0], far[1], s.bendCompliance);
  }

  const double frameTime = 1.0 / s.fps, h = frameTime / s.substeps;
  const uint32_t frames = uint32_t(std::lround(s.cycles * rig::clipPeriod(s.clip) * s.fps));
  std::vector<glm::vec3> x(n), p(n), v(n, glm::vec3(0));
  const rig::Pose start = rig::pose(s.clip, 0.0);
  for (size_t i = 0; i < n; ++i)
    x[i] = skinned(g, start, i);
  std::vector<std::vector<glm::vec3>> out;
  std::vector<float> lambda(links.size());
  const glm::vec3 gravity(0, -9.81f, 0);
  for (uint32_t f = 0; f < frames; ++f) {
    std::vector<glm::vec3> &frame = out.emplace_back(n);
    for (size_t i = 0; i < n; ++i)
      frame[i] = x[rep[i]];
    for (uint32_t step = 1; step <= s.substeps; ++step) {
      const rig::Pose pose = rig::pose(s.clip, f * frameTime + step * h);
      const std::vector<Capsule> bodies = capsules(pose);
      for (uint32_t i = 0; i < n; ++i) {
        if (rep[i] != i)
          continue;
        if (pinned(i)) {
          p[i] = skinned(g, pose, i);
          continue;
        }
        v[i] = (v[i] + gravity * float(h)) * float(1.0 - s.damping * h);
        p[i] = x[i] + v[i] * float(h);
      }
      std::fill(lambda.begin(), lambda.end(), 0.0f);
      for (size_t c = 0; c < links.size(); ++c) {
        const Link &l = links[c];
        const float wa = pinned(l.a) ? 0.0f : 1.0f, wb = pinned(l.b) ? 0.0f : 1.0f;
        const glm::vec3 d = p[l.a] - p[l.b];
        const float len = glm::length(d);
        if (len < 1e-9f)
          continue;
        const float alpha = l.compliance / float(h * h);
        const float dl = (-(len - l.rest) - alpha * lambda[c]) / (wa + wb + alpha);
        lambda[c] += dl;
        p[l.a] += wa * dl * d / len;
        p[l.b] -= wb * dl * d / len;
      }
      for (uint32_t i = 0; i < n; ++i) {
        if (rep[i] != i)
          continue;
        if (!pinned(i))
          for (const Capsule &c : bodies)
            collide(p[i], c);
        v[i] = (p[i] - x[i]) / float(h);
        x[i] = p[i];
      }
    }
  }
  return out;
}

std::vector<std::vector<glm::vec3>> noiseCache(uint32_t frames, uint32_t vertices) {
  std::mt19937 rng(13); // mt19937's sequence is fixed by the standard; the mapping below too
  const rig::Garment g = rig::dress();
  std::vector<std::vector<glm::vec3>> out(frames, std::vector<glm::vec3>(vertices));
  for (auto &frame : out)
    for (uint32_t v = 0; v < vertices; ++v) {
      const auto r = [&] { return float(rng() % 2001) / 1000.0f - 1.0f; };
      frame[v] = g.bind[v % g.bind.size()] + 0.05f * glm::vec3(r(), r(), r());
    }
  return out;
}

uint32_t dressVertexCount() { return uint32_t(rig::dress().bind.size()); }

const std::vector<uint32_t> &dressIndices() {
  static const std::vector<uint32_t> indices = rig::dress().indices;
  return indices;
}

const std::vector<CacheSample> &cacheSamples() {
  static const std::vector<CacheSample> samples = {
      {"skirt_walk.pc2", {"walk", 40, 30.0, 16, 1e-7f, 2e-4f, 0.3}},
      {"skirt_run.pc2", {"run", 40, 30.0, 16, 1e-7f, 2e-4f, 0.3}},
      {"skirt_stiff.pc2", {"walk", 8, 30.0, 16, 1e-8f, 1e-7f, 6.0}},
  };
  return samples;
}

void writeClothCaches(const std::string &dir) {
  for (const CacheSample &c : cacheSamples())
    pack::writeFileAtomic((std::filesystem::path(dir) / c.file).string(),
                          encodePointCache(PointCacheFormat::Pc2, simulateDress(c.settings), 30.0));
  pack::writeFileAtomic(
      (std::filesystem::path(dir) / kCacheFiles.back()).string(),
      encodePointCache(PointCacheFormat::Pc2, noiseCache(30 * 12, dressVertexCount()), 30.0));
}

} // namespace crowd::samples
