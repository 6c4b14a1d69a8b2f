#include "crowd/runtime/render_queues.h"

#include <algorithm>

namespace crowd::runtime {

std::vector<std::vector<uint32_t>> outfitSubMeshes(const pack::AnimationPack &pack,
                                                   bool wholeBody) {
  const auto &mesh = pack.mesh;
  if (!pack.outfits) {
    std::vector<uint32_t> all(mesh.subMeshes.size());
    for (uint32_t s = 0; s < all.size(); ++s)
      all[s] = s;
    return {all};
  }
  const auto &table = *pack.outfits;
  // An outfit-specific copy of a body sub-mesh indexes body vertices only; a garment has
  // vertices of its own. (The bake appends garments after the body's vertices, but the LOD
  // renumbers vertices in collapse order, so it is the set that tells, not the index.)
  std::vector<bool> bodyVertex(mesh.vertexCount());
  auto indicesOf = [&](uint32_t s) {
    const auto &sub = mesh.subMeshes[s];
    return std::span<const uint32_t>(mesh.indices).subspan(sub.firstIndex, sub.indexCount);
  };
  for (uint32_t s = 0; s < table.bodySubMeshes; ++s)
    for (uint32_t i : indicesOf(s))
      bodyVertex[i] = true;
  std::vector<std::vector<uint32_t>> draws;
  for (const auto &outfit : table.outfits) {
    if (!wholeBody) {
      draws.push_back(outfit.subMeshes);
      continue;
    }
    std::vector<uint32_t> d;
    for (uint32_t s = 0; s < table.bodySubMeshes; ++s)
      d.push_back(s);
    for (uint32_t s : outfit.subMeshes) {
      auto idx = indicesOf(s);
      if (s >= table.bodySubMeshes &&
          (idx.empty() ||
           !std::all_of(idx.begin(), idx.end(), [&](uint32_t i) { return bodyVertex[i]; })))
        d.push_back(s);
    }
    draws.push_back(d);
  }
  return draws;
}

RenderQueues::RenderQueues(std::vector<std::vector<uint32_t>> draws, uint32_t subMeshes)
    : draws_(std::move(draws)), users_(subMeshes) {
  for (uint32_t o = 0; o < draws_.size(); ++o) {
    widest_ = std::max(widest_, draws_[o].size());
    for (uint32_t s : draws_[o])
      users_[s].push_back(o);
  }
}

void RenderQueues::build(std::span<const uint32_t> ids, std::span<const uint32_t> runEnds,
                         std::span<const uint32_t> outfitOf) {
  const size_t outfits = draws_.size(), levels = runEnds.size();
  // Counting sort of each level's run by outfit: starts_[l * (outfits + 1) + o] is where
  // outfit o's instances of level l begin in sorted_.
  sorted_.resize(ids.size());
  starts_.assign(levels * (outfits + 1), 0);
  for (size_t l = 0; l < levels; ++l) {
    const uint32_t begin = l ? runEnds[l - 1] : 0, end = runEnds[l];
    uint32_t *start = &starts_[l * (outfits + 1)];
    for (uint32_t k = begin; k < end; ++k)
      ++start[outfitOf[ids[k]] + 1];
    start[0] = begin;
    for (size_t o = 1; o <= outfits; ++o)
      start[o] += start[o - 1];
    next_.assign(start, start + outfits);
    for (uint32_t k = begin; k < end; ++k)
      sorted_[next_[outfitOf[ids[k]]]++] = ids[k];
  }
  queueIds.clear();
  queues.clear();
  for (uint32_t s = 0; s < users_.size(); ++s)
    for (uint32_t l = 0; l < levels; ++l) {
      Queue q{s, l, uint32_t(queueIds.size()), 0};
      const uint32_t *start = &starts_[l * (outfits + 1)];
      for (uint32_t o : users_[s])
        queueIds.insert(queueIds.end(), sorted_.begin() + start[o], sorted_.begin() + start[o + 1]);
      q.count = uint32_t(queueIds.size()) - q.first;
      if (q.count)
        queues.push_back(q);
    }
}

} // namespace crowd::runtime
