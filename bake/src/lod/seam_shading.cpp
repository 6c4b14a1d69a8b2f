#include "seam_shading.h"

#include <algorithm>

#include "crowd/formats/error.h"

namespace crowd::lod {

SeamShading::SeamShading(const LodAppearance &a, const std::vector<uint32_t> &source, double budget)
    : budget_(budget) {
  const size_t V = a.normals.size();
  if (a.colourScale.size() != V || a.key.size() != V)
    throw Error("lod: the appearance's normals, colours and keys differ in count");
  for (uint32_t v : source)
    if (v >= V)
      throw Error("lod: the appearance has fewer vertices than the mesh");
  normal_.reserve(source.size()), scale_.reserve(source.size()), key_.reserve(source.size());
  for (uint32_t v : source) {
    const float len = glm::length(a.normals[v]);
    normal_.push_back(len > 0 ? a.normals[v] / len : glm::vec3(0.0f));
    scale_.push_back(a.colourScale[v]);
    key_.push_back(a.key[v]);
  }
  moved_.assign(source.size(), 0.0f);
}

double SeamShading::jump(uint32_t r, uint32_t s) const {
  const bool faceR = normal_[r] == glm::vec3(0.0f), faceS = normal_[s] == glm::vec3(0.0f);
  if (faceR || faceS)
    return faceR && faceS ? 0.0 : 2.0;
  return glm::length(normal_[r] - normal_[s]);
}

double SeamShading::closed(uint32_t r, uint32_t s) {
  const double c = change(r, s);
  largest_ = std::max(largest_, c);
  moved_[s] = std::max(moved_[s], float(moved_[r] + jump(r, s)));
  ++closings_;
  return c;
}

void SeamShading::carried(uint32_t r, uint32_t s) { moved_[s] = std::max(moved_[s], moved_[r]); }

} // namespace crowd::lod
