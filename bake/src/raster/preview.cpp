#include "crowd/bake/preview.h"

#include <algorithm>
#include <cmath>

#include "crowd/bake/raster.h"
#include "crowd/runtime/pack_joints.h"

namespace crowd {

std::vector<uint8_t> renderPreview(const pack::AnimationPack &p, size_t clip, uint32_t frame,
                                   int size) {
  const auto &m = p.mesh;
  const auto &c = p.clips.at(clip);
  std::vector<glm::vec3> pos(m.vertexCount()), nrm(m.vertexCount());
  const auto joints = runtime::sampleJoints(p, clip, frame, 0.0f);
  for (uint32_t v = 0; v < m.vertexCount(); ++v) {
    glm::vec3 bind(m.positions[v * 3], m.positions[v * 3 + 1], m.positions[v * 3 + 2]);
    glm::vec3 n(m.normals[v * 3], m.normals[v * 3 + 1], m.normals[v * 3 + 2]);
    if (p.morphs) {
      const auto morphed = runtime::morphVertex(*p.morphs, {&c, frame, 0.0f}, v, {bind, n});
      bind = morphed.position;
      n = morphed.normal;
    }
    pos[v] = runtime::skinVertex(joints, p.skin, v, bind);
    // Normals through the same blend (no translation): good enough for shading a preview.
    nrm[v] = runtime::skinVertex(joints, p.skin, v, bind + n) - pos[v];
  }
  const auto &s = m.boundingSphere;
  glm::dvec3 centre(s[0], s[1], s[2]);
  double r = std::max(double(s[3]), 1e-6);
  auto cam = raster::orthographic(centre + glm::dvec3(0, 0, 3 * r), centre, {0, 1, 0}, r, r,
                                  0.5 * r, 5 * r);
  raster::Image img = raster::rasterize(pos, m.indices, cam, size, size);
  std::vector<uint8_t> rgb(size_t(size) * size_t(size) * 3, 40);
  const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.5f, 1.0f));
  for (size_t i = 0; i < img.triangle.size(); ++i) {
    if (img.triangle[i] < 0)
      continue;
    uint32_t first = uint32_t(img.triangle[i]) * 3;
    size_t sub = 0;
    for (size_t k = 0; k < m.subMeshes.size(); ++k)
      if (first >= m.subMeshes[k].firstIndex &&
          first < m.subMeshes[k].firstIndex + m.subMeshes[k].indexCount)
        sub = k;
    float hue = float(sub) * 0.618f;
    glm::vec3 tint(0.6f + 0.4f * std::cos(6.283f * hue),
                   0.6f + 0.4f * std::cos(6.283f * (hue + 0.33f)),
                   0.6f + 0.4f * std::cos(6.283f * (hue + 0.67f)));
    glm::vec3 n = raster::interpolate(img, i, nrm, m.indices);
    float len = glm::length(n);
    float lambert = len > 0 ? std::abs(glm::dot(n / len, light)) : 0.5f;
    glm::vec3 colour = tint * (0.25f + 0.75f * lambert);
    for (int k = 0; k < 3; ++k)
      rgb[i * 3 + size_t(k)] = uint8_t(std::clamp(colour[k], 0.0f, 1.0f) * 255.0f + 0.5f);
  }
  return rgb;
}

} // namespace crowd
