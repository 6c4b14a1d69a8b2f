// Cloth loops in the outfit bake: a garment that plays a loop is where the loop has it, not
// where skinning puts it, so visibility and the hole check also pose every loop frame (see
// outfit_bake.h).
#include <algorithm>
#include <map>

#include "crowd/bake/cloth_input.h"
#include "crowd/bake/evaluate.h"
#include "crowd/bake/outfit_bake.h"
#include "crowd/formats/error.h"

namespace crowd {

std::vector<PlacedLoop> placeLoops(const Character &merged, const std::vector<OutfitInput> &outfits,
                                   const std::vector<uint32_t> &firstVertex) {
  std::vector<PlacedLoop> placed;
  for (size_t k = 0; k < outfits.size(); ++k) {
    const OutfitInput &o = outfits[k];
    std::map<pack::VertexSource, uint32_t> index; // the outfit glTF's vertices by source
    for (uint32_t v = 0; v < o.character.mesh.sources.size(); ++v)
      index.emplace(o.character.mesh.sources[v], v);
    for (const pack::ClothLoop &loop : o.loops) {
      const std::string who = "outfit '" + o.name + "', cloth loop of garment '" + loop.garment +
                              "' over clip '" + loop.clip + "'";
      PlacedLoop p;
      p.outfit = k;
      p.clip = &findClip(merged, loop.clip);
      p.loop = loop;
      for (const pack::VertexSource &s : loop.sources.expand()) {
        const auto it = index.find(s);
        if (it == index.end())
          throw Error(who + ": a loop vertex is not a vertex of the outfit's glTF");
        p.vertices.push_back(firstVertex[k] + it->second);
      }
      placed.push_back(std::move(p));
    }
  }
  return placed;
}

std::vector<glm::dvec3> loopPose(const Character &merged, const PlacedLoop &l, uint32_t frame) {
  const uint32_t cacheFrame = l.loop.cacheStart + frame;
  auto p = posedPositions(merged, l.clip, cacheFrameTime(*l.clip, cacheFrame, l.loop.fps));
  const glm::dmat4 toModel = glm::inverse(toRootFrame(merged, *l.clip, cacheFrame, l.loop.fps));
  for (uint32_t k = 0; k < l.vertices.size(); ++k) {
    const auto q = l.loop.position(frame, k);
    p[l.vertices[k]] = glm::dvec3(toModel * glm::dvec4(q[0], q[1], q[2], 1.0));
  }
  return p;
}

std::vector<OutfitPose> outfitPoses(const Character &merged, double fps, uint32_t step,
                                    const std::vector<PlacedLoop> &loops, uint32_t loopFrames) {
  std::vector<OutfitPose> poses;
  for (const auto &[clip, time] : outfitFrames(merged, fps, step))
    poses.push_back({clip, time, nullptr, 0});
  for (const PlacedLoop &l : loops) {
    const uint32_t frames = l.loop.frameCount();
    const uint32_t tested = loopFrames == 0 ? frames : std::min(frames, loopFrames);
    for (uint32_t i = 0; i < tested; ++i)
      poses.push_back({l.clip, 0.0, &l, uint32_t(uint64_t(i) * frames / tested)});
  }
  return poses;
}

std::vector<glm::dvec3> posed(const Character &merged, const OutfitPose &pose) {
  return pose.loop ? loopPose(merged, *pose.loop, pose.frame)
                   : posedPositions(merged, pose.clip, pose.time);
}

} // namespace crowd
