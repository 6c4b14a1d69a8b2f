#include "crowd/runtime/pose.h"

#include <algorithm>

#include "crowd/formats/error.h"
#include "crowd/runtime/lod_select.h"
#include "crowd/runtime/pack_joints.h"
#include "crowd/runtime/render_queues.h"

namespace crowd::runtime {

namespace {

template <class List, class Name> std::vector<std::string> names(const List &list, Name name) {
  std::vector<std::string> out;
  for (const auto &item : list)
    out.push_back(name(item));
  return out;
}

} // namespace

PoseMesh poseMesh(const pack::AnimationPack &pack, const PoseOptions &o, ClothLoops cloths) {
  PoseMesh m;
  m.cloth = clothBuffers(pack, cloths);
  if (!o.clip.empty() || !pack.clips.empty()) {
    auto it = o.clip.empty() ? pack.clips.begin()
                             : std::find_if(pack.clips.begin(), pack.clips.end(),
                                            [&](const pack::Clip &c) { return c.name == o.clip; });
    if (it == pack.clips.end())
      throw unknownName("clip", o.clip,
                        names(pack.clips, [](const pack::Clip &c) { return c.name; }));
    m.clip = &*it;
  }
  const auto draws = outfitSubMeshes(pack, false);
  size_t outfit = 0;
  if (pack.outfits) {
    const auto &list = pack.outfits->outfits;
    auto it = o.outfit.empty() ? list.begin()
                               : std::find_if(list.begin(), list.end(),
                                              [&](const auto &f) { return f.name == o.outfit; });
    if (it == list.end())
      throw unknownName("outfit", o.outfit, names(list, [](const auto &f) { return f.name; }));
    outfit = size_t(it - list.begin());
    m.outfit = it->name;
  } else if (!o.outfit.empty()) {
    throw Error("no outfit named '" + o.outfit + "' (the pack has no outfits)");
  }
  const uint32_t n = uint32_t(pack.mesh.vertexCount());
  uint32_t cut = n;
  if (o.lodVertices != 0) {
    const uint32_t floor = pack.lod ? pack.lod->floorVertices : n;
    if (o.lodVertices < floor || o.lodVertices > n)
      throw Error("LOD cut at " + std::to_string(o.lodVertices) + " vertices: the pack has " +
                  (pack.lod ? std::to_string(floor) + ".." + std::to_string(n)
                            : "no LOD, only " + std::to_string(n)));
    cut = o.lodVertices;
  }
  std::vector<uint32_t> starts;
  const std::vector<uint32_t> all = lodIndices(pack, cut, starts);
  std::vector<uint32_t> drawn;
  for (uint32_t s : draws.at(outfit)) {
    m.subMeshes.push_back(s);
    m.subMeshStarts.push_back(uint32_t(drawn.size()));
    drawn.insert(drawn.end(), all.begin() + starts[s], all.begin() + starts[s + 1]);
  }
  m.subMeshStarts.push_back(uint32_t(drawn.size()));
  std::vector<uint32_t> slot(n, UINT32_MAX);
  for (uint32_t i : drawn)
    slot[i] = 0;
  for (uint32_t v = 0; v < n; ++v)
    if (slot[v] == 0) {
      slot[v] = uint32_t(m.vertices.size());
      m.vertices.push_back(v);
    }
  m.indices.reserve(drawn.size());
  for (uint32_t i : drawn)
    m.indices.push_back(slot[i]);
  return m;
}

void poseAt(const pack::AnimationPack &pack, const PoseMesh &mesh, float seconds,
            std::vector<glm::vec3> &positions, std::vector<glm::vec3> &normals) {
  const auto &p = pack.mesh.positions, &nr = pack.mesh.normals;
  positions.resize(mesh.vertices.size());
  normals.resize(mesh.vertices.size());
  uint32_t frame = 0;
  float alpha = 0;
  std::vector<JointRows> joints;
  if (mesh.clip) {
    frameAt(*mesh.clip, seconds, frame, alpha);
    joints = sampleJoints(pack, size_t(mesh.clip - pack.clips.data()), frame, alpha);
  }
  const auto clip = mesh.clip ? uint32_t(mesh.clip - pack.clips.data()) : 0;
  // Cloth loop vertices and flat-shaded ones (a zero normal) get the normal of their faces.
  std::vector<uint8_t> faceted(mesh.vertices.size(), 0);
  for (size_t k = 0; k < mesh.vertices.size(); ++k) {
    const uint32_t v = mesh.vertices[k];
    const glm::vec3 position(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
    const glm::vec3 normal = nr.size() == p.size()
                                 ? glm::vec3(nr[3 * v], nr[3 * v + 1], nr[3 * v + 2])
                                 : glm::vec3(0.0f);
    faceted[k] = normal == glm::vec3(0.0f);
    if (!mesh.clip) {
      positions[k] = position;
      normals[k] = normal;
      continue;
    }
    if (clothVertexAt(pack, mesh.cloth, clip, seconds, v, positions[k])) {
      faceted[k] = 1;
      continue;
    }
    SkinnedVertex bind{position, normal};
    if (pack.morphs)
      bind = morphVertex(*pack.morphs, {mesh.clip, frame, alpha}, v, bind);
    const auto s = skinVertex(joints, pack.skin, v, bind.position, bind.normal);
    positions[k] = s.position;
    normals[k] = s.normal;
  }
  faceNormals(positions, mesh.indices, faceted, normals);
}

void faceNormals(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                 const std::vector<uint8_t> &faceted, std::vector<glm::vec3> &normals) {
  if (std::find(faceted.begin(), faceted.end(), 1) == faceted.end())
    return;
  for (size_t k = 0; k < faceted.size(); ++k)
    if (faceted[k])
      normals[k] = glm::vec3(0.0f);
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    const uint32_t a = indices[i], b = indices[i + 1], c = indices[i + 2];
    const glm::vec3 face = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
    for (uint32_t k : {a, b, c})
      if (faceted[k])
        normals[k] += face;
  }
}

} // namespace crowd::runtime
