#include "crowd/bake/morph_frames.h"

#include <algorithm>
#include <cmath>

namespace crowd {

std::optional<pack::Morphs> buildMorphs(const SkinnedMesh &mesh,
                                        const std::vector<std::vector<double>> &frameWeights,
                                        MorphOverflow *overflow) {
  if (mesh.morphs.empty())
    return std::nullopt;
  pack::Morphs m;
  m.vertexCount = uint32_t(mesh.vertexCount());
  std::vector<double> reach; // per target: its largest position offset, model units
  for (const auto &target : mesh.morphs) {
    uint32_t first = m.vertexCount, last = 0;
    double longest = 0;
    for (uint32_t v = 0; v < m.vertexCount; ++v)
      if (target.positions[v] != glm::vec3(0) || target.normals[v] != glm::vec3(0)) {
        first = std::min(first, v);
        last = v;
        longest = std::max(longest, double(glm::length(target.positions[v])));
      }
    pack::Morphs::Target t{target.name, first < m.vertexCount ? first : 0,
                           first < m.vertexCount ? last + 1 - first : 0, m.offsets.size()};
    for (uint32_t v = t.firstVertex; v < t.firstVertex + t.vertexCount; ++v) {
      const glm::vec3 p = target.positions[v], n = target.normals[v];
      m.offsets.insert(m.offsets.end(), {p.x, p.y, p.z, 0.0f, n.x, n.y, n.z, 0.0f});
    }
    m.targets.push_back(std::move(t));
    reach.push_back(longest);
  }
  MorphOverflow o;
  std::vector<std::pair<double, uint32_t>> active; // (how far it moves the mesh, target)
  for (const auto &weights : frameWeights) {
    active.clear();
    for (uint32_t t = 0; t < weights.size(); ++t)
      if (weights[t] != 0)
        active.push_back({std::abs(weights[t]) * reach[t], t});
    o.mostActive = std::max(o.mostActive, uint32_t(active.size()));
    std::sort(active.begin(), active.end(), [](const auto &a, const auto &b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    if (active.size() > pack::kMorphSlots) {
      ++o.frames;
      o.largestDropped = std::max(o.largestDropped, active[pack::kMorphSlots].first);
      active.resize(pack::kMorphSlots);
    }
    for (uint32_t s = 0; s < pack::kMorphSlots; ++s)
      m.slots.push_back(s < active.size() ? pack::Morphs::Slot{float(active[s].second),
                                                               float(weights[active[s].second])}
                                          : pack::Morphs::Slot{});
  }
  if (overflow)
    *overflow = o;
  return m;
}

glm::vec3 morphedBind(const SkinnedMesh &mesh, const std::optional<pack::Morphs> &morphs,
                      const runtime::ClipTime &at, uint32_t v) {
  if (!morphs)
    return mesh.positions[v];
  return runtime::morphVertex(*morphs, at, v, {mesh.positions[v], mesh.normals[v]}).position;
}

} // namespace crowd
