// Render queues of clothed characters (the WSCG 2009 clothed-crowds seed, sec. 4): each frame,
// for the visible instances only, one queue per sub-mesh holds the ids of the instances whose
// outfit draws that sub-mesh; the player draws each queue with one instanced draw, and the
// shader follows the indirection instance id -> per-instance data (transform, clip, palette).
// No GL here, so the tests and benchmarks run the very code the player runs.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "crowd/formats/chunks.h"

namespace crowd::runtime {

// The sub-meshes each outfit of `pack` draws, increasing. Tagged: the pack's outfit table.
// Whole body (the naive method, for comparison): every body sub-mesh, under the outfit's
// garments. A pack without outfits has one "outfit" that draws every sub-mesh.
std::vector<std::vector<uint32_t>> outfitSubMeshes(const pack::AnimationPack &pack, bool wholeBody);

class RenderQueues {
public:
  RenderQueues() = default;
  RenderQueues(std::vector<std::vector<uint32_t>> draws, uint32_t subMeshes);

  struct Queue {
    uint32_t subMesh = 0, level = 0, first = 0, count = 0; // ids[first, first + count)
  };
  // `ids`: visible instances sorted by level, level l ending at runEnds[l] (CrowdSelection);
  // `outfitOf[id]`: the instance's outfit. Fills `ids` and `queues` (non-empty ones, by
  // sub-mesh and then level; within a queue, instances by outfit and then as given).
  void build(std::span<const uint32_t> ids, std::span<const uint32_t> runEnds,
             std::span<const uint32_t> outfitOf);
  std::vector<uint32_t> queueIds;
  std::vector<Queue> queues;
  // The most ids build() can write for `instances` instances.
  size_t capacity(size_t instances) const { return instances * widest_; }
  const std::vector<uint32_t> &draws(uint32_t outfit) const { return draws_[outfit]; }

private:
  std::vector<std::vector<uint32_t>> draws_; // per outfit: its sub-meshes
  std::vector<std::vector<uint32_t>> users_; // per sub-mesh: the outfits that draw it
  size_t widest_ = 0;
  std::vector<uint32_t> sorted_, starts_, next_; // scratch: ids by outfit per level, run starts
};

} // namespace crowd::runtime
