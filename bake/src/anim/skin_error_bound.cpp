#include "skin_error_bound.h"

#include <algorithm>
#include <cmath>

namespace crowd {
namespace {

constexpr double kRoundingOfTheBound = 1 + 1e-9; // the bound's own sums round too
constexpr double kUlps = 16 * 0x1p-24;           // the skinning's rounding, relative

} // namespace

SkinErrorBound::SkinErrorBound(const SkinnedMesh &m, const pack::SkinTexture &skin,
                               size_t jointCount)
    : skin_(skin), centre_(jointCount, glm::dvec3(0.0)) {
  const size_t vertices = m.vertexCount();
  auto id = [&](size_t v, size_t k) { return size_t(skin.texels[v * 8 + k]); };
  auto weight = [&](size_t v, size_t k) { return std::abs(double(skin.texels[v * 8 + 4 + k])); };
  std::vector<double> mass(jointCount, 0.0);
  for (size_t v = 0; v < vertices; ++v)
    for (size_t k = 0; k < 4; ++k)
      centre_[id(v, k)] += weight(v, k) * glm::dvec3(m.positions[v]),
          mass[id(v, k)] += weight(v, k);
  for (size_t j = 0; j < jointCount; ++j)
    centre_[j] = mass[j] > 0 ? centre_[j] / mass[j] : glm::dvec3(0.0);
  apart_.resize(4 * vertices);
  reach_.resize(vertices);
  for (size_t v = 0; v < vertices; ++v) {
    const glm::dvec3 p(m.positions[v]);
    reach_[v] = glm::length(p);
    for (size_t k = 0; k < 4; ++k)
      apart_[4 * v + k] = glm::length(p - centre_[id(v, k)]);
  }
  if (!m.morphs.empty())
    return; // the caller bounds vertex by vertex
  blockStart_.push_back(0);
  for (size_t first = 0; first < vertices; first += kBlock) {
    const auto begin = std::ptrdiff_t(blockTerms_.size());
    for (size_t v = first; v < std::min(vertices, first + kBlock); ++v)
      for (size_t k = 0; k < 4; ++k) {
        const uint32_t j = uint32_t(id(v, k));
        double w = 0, d = 0; // the vertex's weights on j, and times their distances
        for (size_t r = 0; r < 4; ++r)
          if (id(v, r) == j)
            w += weight(v, r), d += weight(v, r) * apart_[4 * v + r];
        if (w == 0)
          continue;
        auto it = std::find_if(blockTerms_.begin() + begin, blockTerms_.end(),
                               [&](const BlockTerm &t) { return t.joint == j; });
        if (it == blockTerms_.end())
          it = blockTerms_.insert(it, {j, 0, 0, 0});
        it->apart = std::max(it->apart, d), it->weight = std::max(it->weight, w);
        it->reach = std::max(it->reach, w * reach_[v]);
      }
    blockStart_.push_back(blockTerms_.size());
  }
}

SkinErrorBound::Terms SkinErrorBound::terms(const std::vector<runtime::JointRows> &rows,
                                            const std::vector<glm::dmat4> &exact) const {
  Terms out(centre_.size());
  for (size_t j = 0; j < out.size(); ++j) {
    double turn = 0, size = 0, shift = 0, exactSize = 0;
    glm::dvec3 atCentre(0.0);
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 4; ++col) {
        const double value = rows[j][size_t(r)][col], off = value - exact[j][col][r];
        atCentre[r] += off * (col < 3 ? centre_[j][col] : 1.0);
        if (col < 3)
          turn += off * off, size += value * value,
              exactSize += exact[j][col][r] * exact[j][col][r];
        else
          shift += value * value;
      }
    out[j] = {std::sqrt(turn), glm::length(atCentre) + kUlps * std::sqrt(shift),
              kUlps * std::sqrt(size), std::sqrt(exactSize)};
  }
  return out;
}

double SkinErrorBound::sum(uint32_t v, const Terms &t, const double *apart, double reach,
                           double morphOff) const {
  const float *ids = &skin_.texels[size_t(v) * 8], *w = ids + 4;
  double most = 0;
  for (size_t k = 0; k < 4; ++k)
    if (w[k] != 0) { // as the skinning skips it
      const auto &[turn, atCentre, rounding, exactSize] = t[size_t(ids[k])];
      most += std::abs(double(w[k])) *
              (turn * apart[k] + atCentre + rounding * reach + exactSize * morphOff);
    }
  most *= kRoundingOfTheBound;
  return most * most;
}

double SkinErrorBound::vertex(uint32_t v, const Terms &t) const {
  return sum(v, t, &apart_[4 * size_t(v)], reach_[v], 0.0);
}

double SkinErrorBound::morphedVertex(uint32_t v, const Terms &t, const glm::dvec3 &drawn,
                                     const glm::dvec3 &exact) const {
  std::array<double, 4> apart;
  for (size_t k = 0; k < 4; ++k)
    apart[k] = glm::length(drawn - centre_[size_t(skin_.texels[size_t(v) * 8 + k])]);
  return sum(v, t, apart.data(), glm::length(drawn), glm::length(drawn - exact));
}

double SkinErrorBound::block(uint32_t b, const Terms &t) const {
  double most = 0;
  for (size_t i = blockStart_[b]; i < blockStart_[b + 1]; ++i) {
    const BlockTerm &bt = blockTerms_[i];
    const auto &[turn, atCentre, rounding, exactSize] = t[bt.joint];
    most += turn * bt.apart + atCentre * bt.weight + rounding * bt.reach;
  }
  most *= kRoundingOfTheBound;
  return most * most;
}

} // namespace crowd
