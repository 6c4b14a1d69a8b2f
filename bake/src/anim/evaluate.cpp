#include "crowd/bake/evaluate.h"

#include <algorithm>
#include <cmath>

namespace crowd {
namespace {

glm::dquat quatAt(const std::vector<double> &v, size_t offset) {
  return glm::dquat(v[offset + 3], v[offset], v[offset + 1], v[offset + 2]);
}

// Spherical interpolation along the shorter arc, as the glTF specification describes.
glm::dquat slerp(glm::dquat a, glm::dquat b, double s) {
  double d = glm::dot(a, b);
  if (d < 0) {
    b = -b;
    d = -d;
  }
  if (d > 1.0 - 1e-12)
    return glm::normalize(a * (1 - s) + b * s);
  double theta = std::acos(std::min(d, 1.0));
  double sn = std::sin(theta);
  return a * (std::sin((1 - s) * theta) / sn) + b * (std::sin(s * theta) / sn);
}

} // namespace

void sampleChannel(const Channel &ch, double t, double *out, bool fromLeft) {
  const bool rotation = ch.path == ChannelPath::Rotation;
  const size_t n = ch.components;
  const bool cubic = ch.interpolation == Interpolation::CubicSpline;
  const size_t stride = cubic ? 3 * n : n;
  const size_t valueOffset = cubic ? n : 0; // cubic keys are (in-tangent, value, out-tangent)
  const auto &times = ch.times;
  // From the left, a cut's first key ends the interval before it; otherwise its second key holds.
  size_t k1 = size_t((fromLeft ? std::lower_bound(times.begin(), times.end(), t)
                               : std::upper_bound(times.begin(), times.end(), t)) -
                     times.begin());
  if (k1 == 0 || k1 == times.size()) {
    size_t k = k1 == 0 ? 0 : times.size() - 1;
    for (size_t c = 0; c < n; ++c)
      out[c] = ch.values[k * stride + valueOffset + c];
  } else {
    size_t k0 = k1 - 1;
    double td = times[k1] - times[k0];
    double s = (t - times[k0]) / td;
    const double *v0 = &ch.values[k0 * stride + valueOffset];
    const double *v1 = &ch.values[k1 * stride + valueOffset];
    switch (ch.interpolation) {
    case Interpolation::Step:
      for (size_t c = 0; c < n; ++c)
        out[c] = v0[c];
      break;
    case Interpolation::Linear:
      if (rotation) {
        glm::dquat q = slerp(quatAt(ch.values, k0 * stride), quatAt(ch.values, k1 * stride), s);
        out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
      } else {
        for (size_t c = 0; c < n; ++c)
          out[c] = v0[c] + (v1[c] - v0[c]) * s;
      }
      break;
    case Interpolation::CubicSpline: {
      const double *outTangent0 = &ch.values[k0 * stride + 2 * n];
      const double *inTangent1 = &ch.values[k1 * stride];
      double s2 = s * s, s3 = s2 * s;
      double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
             h11 = s3 - s2;
      for (size_t c = 0; c < n; ++c)
        out[c] = h00 * v0[c] + h10 * td * outTangent0[c] + h01 * v1[c] + h11 * td * inTangent1[c];
      break;
    }
    }
  }
  if (rotation) {
    double len = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
    if (len > 0)
      for (size_t c = 0; c < 4; ++c)
        out[c] /= len;
  }
}

NodeLocals nodeLocals(const Character &c, const AnimationClip *clip, double t) {
  NodeLocals l;
  auto &[tr, rot, sc] = l;
  tr.resize(c.nodes.size()), rot.resize(c.nodes.size()), sc.resize(c.nodes.size());
  for (size_t i = 0; i < c.nodes.size(); ++i) {
    tr[i] = c.nodes[i].translation;
    rot[i] = c.nodes[i].rotation;
    sc[i] = c.nodes[i].scale;
  }
  if (clip)
    for (const auto &ch : clip->channels) {
      if (ch.path == ChannelPath::Weights)
        continue;
      double v[4];
      sampleChannel(ch, t, v);
      size_t n = size_t(ch.node);
      if (ch.path == ChannelPath::Translation)
        tr[n] = {v[0], v[1], v[2]};
      else if (ch.path == ChannelPath::Scale)
        sc[n] = {v[0], v[1], v[2]};
      else
        rot[n] = glm::dquat(v[3], v[0], v[1], v[2]);
    }
  return l;
}

NodeLocals blendLocals(const NodeLocals &from, const NodeLocals &to, double weight) {
  NodeLocals out = from;
  for (size_t i = 0; i < from.rotation.size(); ++i) {
    const glm::dquat b =
        glm::dot(from.rotation[i], to.rotation[i]) < 0 ? -to.rotation[i] : to.rotation[i];
    out.rotation[i] = glm::normalize(glm::slerp(from.rotation[i], b, weight));
    out.translation[i] = glm::mix(from.translation[i], to.translation[i], weight);
    out.scale[i] = glm::mix(from.scale[i], to.scale[i], weight);
  }
  return out;
}

std::vector<glm::dmat4> nodeGlobals(const Character &c, const AnimationClip *clip, double t) {
  return nodeGlobals(c, nodeLocals(c, clip, t));
}

std::vector<glm::dmat4> nodeGlobals(const Character &c, const NodeLocals &locals) {
  const auto &[tr, rot, sc] = locals;
  std::vector<glm::dmat4> global(c.nodes.size());
  for (int i : c.nodeOrder) {
    const Node &node = c.nodes[size_t(i)];
    glm::dmat4 local;
    if (node.hasMatrix) {
      local = node.matrix;
    } else {
      glm::dmat4 r = glm::mat4_cast(rot[size_t(i)]);
      local = r;
      for (int col = 0; col < 3; ++col)
        local[col] *= sc[size_t(i)][col];
      local[3] = glm::dvec4(tr[size_t(i)], 1.0);
    }
    global[size_t(i)] = node.parent >= 0 ? global[size_t(node.parent)] * local : local;
  }
  return global;
}

std::vector<glm::dmat4> jointMatrices(const Character &c, const AnimationClip *clip, double t) {
  return jointMatrices(c, nodeLocals(c, clip, t));
}

std::vector<glm::dmat4> jointMatrices(const Character &c, const NodeLocals &locals) {
  auto global = nodeGlobals(c, locals);
  std::vector<glm::dmat4> out(c.jointCount());
  for (size_t j = 0; j < c.jointCount(); ++j)
    out[j] = global[size_t(c.jointNodes[j])] * c.inverseBind[j];
  return out;
}

std::vector<double> morphWeights(const Character &c, const AnimationClip *clip, double t) {
  std::vector<double> weights = c.mesh.morphDefaults;
  if (clip)
    for (const auto &ch : clip->channels) {
      if (ch.path != ChannelPath::Weights)
        continue;
      if (const MorphGroup *g = c.morphGroupOf(ch.node))
        sampleChannel(ch, t, &weights[g->first]);
    }
  return weights;
}

glm::dvec3 morphedPosition(const SkinnedMesh &m, const std::vector<double> &morphWeights,
                           size_t v) {
  glm::dvec3 morphed(m.positions[v]);
  for (size_t k = 0; k < m.morphs.size(); ++k)
    morphed += morphWeights[k] * glm::dvec3(m.morphs[k].positions[v]);
  return morphed;
}

glm::dvec3 skinPosition(const SkinnedMesh &m, const std::vector<glm::dmat4> &joints,
                        const std::vector<double> &morphWeights, size_t v) {
  glm::dvec4 p(morphedPosition(m, morphWeights, v), 1.0);
  glm::dvec3 acc(0.0);
  for (int k = 0; k < 4; ++k)
    if (m.weights[v][k] != 0)
      acc += double(m.weights[v][k]) * glm::dvec3(joints[m.joints[v][size_t(k)]] * p);
  return acc;
}

std::vector<glm::dvec3> skinPositions(const Character &c, const std::vector<glm::dmat4> &joints,
                                      const std::vector<double> &morphWeights) {
  std::vector<glm::dvec3> out(c.mesh.vertexCount());
  for (size_t v = 0; v < out.size(); ++v)
    out[v] = skinPosition(c.mesh, joints, morphWeights, v);
  return out;
}

std::vector<glm::dvec3> posedPositions(const Character &c, const AnimationClip *clip, double t) {
  return skinPositions(c, jointMatrices(c, clip, t), morphWeights(c, clip, t));
}

std::vector<double> outwardSides(const Character &c) {
  const auto joints = jointMatrices(c, nullptr, 0);
  const auto &m = c.mesh;
  // Whether the rest pose mirrors vertex v: its blended joint matrix has a negative determinant.
  auto mirrored = [&](uint32_t v) {
    glm::dmat3 blend(0.0);
    for (int k = 0; k < 4; ++k)
      if (m.weights[v][k] != 0)
        blend += double(m.weights[v][k]) * glm::dmat3(joints[m.joints[v][size_t(k)]]);
    return glm::determinant(blend) < 0;
  };
  std::vector<double> out(m.indices.size() / 3, 1.0);
  for (size_t t = 0; t < out.size(); ++t) {
    const uint32_t *f = &m.indices[3 * t];
    const glm::dvec3 a(m.positions[f[0]]), b(m.positions[f[1]]), c3(m.positions[f[2]]);
    const glm::dvec3 n(m.normals[f[0]] + m.normals[f[1]] + m.normals[f[2]]);
    if ((glm::dot(glm::cross(b - a, c3 - a), n) < 0) != mirrored(f[0]))
      out[t] = -1.0;
  }
  return out;
}

glm::dvec3 restExtent(const Character &c) {
  auto p = posedPositions(c, nullptr, 0);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto &q : p) {
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  return p.empty() ? glm::dvec3(0.0) : hi - lo;
}

double restDiagonal(const Character &c) { return glm::length(restExtent(c)); }

} // namespace crowd
