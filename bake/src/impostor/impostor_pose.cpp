#include "impostor_pose.h"

#include "crowd/bake/evaluate.h"
#include "crowd/runtime/pose.h"

namespace crowd::impostor {

Posed pose(const Character &c, const AnimationClip *clip, double t) {
  auto joints = jointMatrices(c, clip, t);
  const auto morphs = morphWeights(c, clip, t);
  Posed p;
  for (const auto &q : skinPositions(c, joints, morphs))
    p.positions.push_back(glm::vec3(q));
  for (size_t v = 0; v < c.mesh.vertexCount(); ++v) {
    glm::dvec3 bind(c.mesh.normals[v]), n(0);
    for (size_t k = 0; k < morphs.size(); ++k)
      bind += morphs[k] * glm::dvec3(c.mesh.morphs[k].normals[v]);
    for (int k = 0; k < 4; ++k)
      n += double(c.mesh.weights[v][k]) *
           glm::dvec3(joints[c.mesh.joints[v][size_t(k)]] * glm::dvec4(bind, 0));
    p.normals.push_back(glm::vec3(glm::length(n) > 0 ? glm::normalize(n) : n));
  }
  // A flat-shaded vertex (its normal stored as zero by the LOD bake's weld) takes its posed
  // faces' normal, area-weighted, as the CPU mirror gives it.
  std::vector<uint8_t> flat(p.normals.size(), 0);
  for (size_t v = 0; v < flat.size(); ++v)
    flat[v] = c.mesh.normals[v] == glm::vec3(0.0f);
  runtime::faceNormals(p.positions, c.mesh.indices, flat, p.normals);
  for (size_t v = 0; v < flat.size(); ++v)
    if (flat[v] && glm::length(p.normals[v]) > 0)
      p.normals[v] = glm::normalize(p.normals[v]);
  return p;
}

} // namespace crowd::impostor
