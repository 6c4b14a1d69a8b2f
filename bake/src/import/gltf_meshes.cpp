#include "importer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base_colour_uv.h"
#include "crowd/formats/limits.h"
#include "gltf_schema.h"
#include "nearest_influences.h"
#include "triangle_list.h"

namespace crowd::gltf {
namespace {

int attributeOf(const tinygltf::Primitive &prim, const std::string &name) {
  auto it = prim.attributes.find(name);
  return it == prim.attributes.end() ? -1 : it->second;
}

// An index read from a file (vertex or joint) as a message shows it: any double, even one past
// every integer type (a float accessor may hold 1e24 or NaN), printed without a cast.
std::string indexText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// Whether v names one of count items: a whole number in [0, count).
bool indexesInto(double v, size_t count) {
  return v >= 0 && v < double(count) && v == std::floor(v);
}

} // namespace

// Every primitive of every mesh node chosen, its vertices once per distinct vertex set, its
// triangles into the sub-mesh of its material; then what was repaired, as warnings.
void Importer::readMeshes() {
  MeshState state;
  checkMeshSize();
  for (const auto &mn : meshNodes_) {
    const auto &gm = model_.meshes[size_t(model_.nodes[size_t(mn.node)].mesh)];
    const bool mirrored = mirrors(mn.node); // its triangles are wound clockwise (readPrimitive)
    for (size_t pi = 0; pi < gm.primitives.size(); ++pi)
      readPrimitive(mn, pi, mirrored, state);
  }
  auto &mesh = out_.mesh;
  for (size_t p = 0; p < state.partOrder.size(); ++p) {
    SkinnedMesh::Part part = state.partLooks[p];
    part.name = state.partOrder[p];
    part.firstIndex = uint32_t(mesh.indices.size());
    part.indexCount = uint32_t(state.partTriangles[p].size());
    mesh.parts.push_back(part);
    mesh.indices.insert(mesh.indices.end(), state.partTriangles[p].begin(),
                        state.partTriangles[p].end());
  }
  warnMeshRepairs(state);
}

void Importer::checkLikePosition(int acc, const std::string &ctx, const std::string &name, int type,
                                 size_t count) const {
  if (accessors_.type(acc, ctx + " " + name) != type || accessors_.count(acc) != count)
    fail(ctx + " " + name + ": type or count differs from POSITION");
}

void Importer::readPrimitive(const MeshNode &mn, size_t pi, bool mirrored, MeshState &state) {
  const int meshIndex = model_.nodes[size_t(mn.node)].mesh;
  const auto &gm = model_.meshes[size_t(meshIndex)];
  const auto &prim = gm.primitives[pi];
  const std::string ctx = "mesh '" + gm.name + "', primitive " + std::to_string(pi);
  if (prim.mode < -1 || prim.mode > kTriangleFan)
    fail(ctx + ": mode " + std::to_string(prim.mode) + " is not a glTF primitive mode");
  if (!drawsTriangles(prim.mode)) {
    ++state.pointsOrLines;
    return;
  }
  const int posAcc = attributeOf(prim, "POSITION");
  if (posAcc < 0)
    fail(ctx + ": no POSITION attribute");
  if (accessors_.type(posAcc, ctx + " POSITION") != TINYGLTF_TYPE_VEC3)
    fail(ctx + " POSITION: must be VEC3");
  const size_t vc = accessors_.count(posAcc);
  // Primitives repeating another's vertices share them; one repeating another's vertices,
  // indices and material too is dropped (some exporters write hundreds).
  const std::string vertexKey = vertexKeyOf(prim, mn);
  if (!state.seenPrimitives
           .insert(vertexKey + "|" + std::to_string(prim.indices) + "|" +
                   std::to_string(prim.material))
           .second) {
    ++state.duplicatePrimitives;
    return;
  }
  const auto [known, fresh] =
      state.vertexBases.try_emplace(vertexKey, uint32_t(out_.mesh.positions.size()));
  const auto posData = accessors_.read(posAcc, ctx + " POSITION");
  const std::vector<double> &pos = *posData;
  std::vector<double> nrm, uv;
  if (int a = attributeOf(prim, "NORMAL"); a >= 0) {
    checkLikePosition(a, ctx, "NORMAL", TINYGLTF_TYPE_VEC3, vc);
    nrm = *accessors_.read(a, ctx + " NORMAL");
  } else {
    state.missingNormals += fresh;
  }
  // The set the base-colour texture reads, through its KHR_texture_transform.
  const BaseColourUv uvMap = baseColourUv(model_, prim.material);
  const std::string uvName = "TEXCOORD_" + std::to_string(uvMap.set);
  if (int a = attributeOf(prim, uvName); a >= 0) {
    checkLikePosition(a, ctx, uvName, TINYGLTF_TYPE_VEC2, vc);
    uv = *accessors_.read(a, ctx + " " + uvName);
    for (size_t k = 0; !uvMap.identity && k + 1 < uv.size(); k += 2) {
      const glm::dvec3 t = uvMap.transform * glm::dvec3(uv[k], uv[k + 1], 1);
      if (!std::isfinite(t.x) || !std::isfinite(t.y))
        fail(ctx + " " + uvName + ": KHR_texture_transform takes vertex " + std::to_string(k / 2) +
             "'s UV past the range of a number");
      uv[k] = t.x, uv[k + 1] = t.y;
    }
  }
  const std::vector<uint32_t> idx = readIndices(prim, ctx, vc);
  Influences infl(vc);
  if (fresh && mn.rigid < 0)
    infl = readInfluences(prim, mn, ctx, vc, pos, state);
  const uint32_t base = known->second;
  if (fresh)
    appendVertices(mn, pi, ctx, vc, pos, nrm, uv, infl, state);
  if (nrm.empty() && fresh)
    computeNormals(base, idx);
  if (fresh)
    readMorphTargets(mn, gm, prim, ctx, base, vc);
  hasUvs_ = hasUvs_ || !uv.empty();
  if (int image = baseColorImage(prim.material); image >= 0 && !uv.empty())
    trianglesPerImage_[image] += idx.size() / 3;
  // Wound clockwise where the node's transform mirrors (glTF: its determinant sets the
  // winding): reversed, so that every triangle is counter-clockwise as drawn and the face
  // normals taken from the winding (flat shading, pose's files) face out. The normals computed
  // above read the file's winding in the node's own frame, where it is right.
  std::vector<uint32_t> &triangles = state.partTriangles[partOf(prim, !uv.empty(), state)];
  for (size_t t = 0; t < idx.size(); t += 3)
    triangles.insert(triangles.end(), {base + idx[t], base + idx[t + (mirrored ? 2 : 1)],
                                       base + idx[t + (mirrored ? 1 : 2)]});
  state.mirroredPrimitives += mirrored;
}

// The primitive's triangles as a list (strips and fans unrolled), each index checked.
std::vector<uint32_t> Importer::readIndices(const tinygltf::Primitive &prim, const std::string &ctx,
                                            size_t vc) {
  std::vector<uint32_t> idx;
  if (prim.indices >= 0) {
    const auto rawData = accessors_.read(prim.indices, ctx + " indices");
    const std::vector<double> &raw = *rawData;
    for (size_t k = 0; k < raw.size(); ++k) {
      if (!indexesInto(raw[k], vc))
        fail(ctx + " indices: index " + std::to_string(k) + " = " + indexText(raw[k]) +
             " names no vertex of " + std::to_string(vc));
      idx.push_back(uint32_t(raw[k]));
    }
  } else {
    for (size_t k = 0; k < vc; ++k)
      idx.push_back(uint32_t(k));
  }
  idx = asTriangleList(prim.mode, std::move(idx));
  if (idx.size() % 3 != 0)
    fail(ctx + ": index count " + std::to_string(idx.size()) + " is not a multiple of 3");
  return idx;
}

// Every JOINTS_n/WEIGHTS_n pair's nonzero influences, as skin entries; a vertex with none takes
// the nearest weighted vertex's.
Importer::Influences Importer::readInfluences(const tinygltf::Primitive &prim, const MeshNode &mn,
                                              const std::string &ctx, size_t vc,
                                              const std::vector<double> &pos, MeshState &state) {
  Influences infl(vc);
  const std::vector<size_t> &entries = skinEntries_.at(mn.skin);
  const size_t jointCount = entries.size();
  for (int set = 0;; ++set) {
    const std::string n = std::to_string(set);
    const int ja = attributeOf(prim, "JOINTS_" + n), wa = attributeOf(prim, "WEIGHTS_" + n);
    if (ja < 0 && wa < 0)
      break;
    if (ja < 0 || wa < 0)
      fail(ctx + ": JOINTS_" + n + " without WEIGHTS_" + n);
    checkLikePosition(ja, ctx, "JOINTS", TINYGLTF_TYPE_VEC4, vc);
    checkLikePosition(wa, ctx, "WEIGHTS", TINYGLTF_TYPE_VEC4, vc);
    const auto jData = accessors_.read(ja, ctx + " JOINTS_" + n);
    const auto wData = accessors_.read(wa, ctx + " WEIGHTS_" + n);
    const std::vector<double> &jv = *jData, &wv = *wData;
    for (size_t v = 0; v < vc; ++v)
      for (int k = 0; k < 4; ++k) {
        double w = wv[v * 4 + size_t(k)], j = jv[v * 4 + size_t(k)];
        if (w < 0)
          fail(ctx + " WEIGHTS_" + n + ": vertex " + std::to_string(v) + " has negative weight " +
               std::to_string(w));
        if (w == 0)
          continue;
        if (!indexesInto(j, jointCount))
          fail(ctx + " JOINTS_" + n + ": vertex " + std::to_string(v) + " uses joint " +
               indexText(j) + " but the skin has " + std::to_string(jointCount));
        infl[v].push_back({w, int(entries[size_t(j)])});
      }
  }
  if (attributeOf(prim, "JOINTS_0") < 0)
    fail(ctx + ": skinned node without JOINTS_0/WEIGHTS_0");
  state.unweighted += borrowNearestInfluences(infl, pos);
  return infl;
}

void Importer::appendVertices(const MeshNode &mn, size_t pi, const std::string &ctx, size_t vc,
                              const std::vector<double> &pos, const std::vector<double> &nrm,
                              const std::vector<double> &uv, Influences &infl, MeshState &state) {
  auto &mesh = out_.mesh;
  const int meshIndex = model_.nodes[size_t(mn.node)].mesh;
  for (size_t v = 0; v < vc; ++v) {
    mesh.sources.push_back({0, mn.node, meshIndex, int32_t(pi), int32_t(v)});
    mesh.positions.push_back(glm::vec3(pos[v * 3], pos[v * 3 + 1], pos[v * 3 + 2]));
    mesh.normals.push_back(nrm.empty() ? glm::vec3(0)
                                       : glm::vec3(nrm[v * 3], nrm[v * 3 + 1], nrm[v * 3 + 2]));
    mesh.uvs.push_back(uv.empty() ? glm::vec2(0) : glm::vec2(uv[v * 2], uv[v * 2 + 1]));
    std::array<uint16_t, 4> ids{0, 0, 0, 0};
    glm::vec4 ws(0);
    if (mn.rigid >= 0) {
      ids[0] = mn.rigidJoint;
      ws[0] = 1;
    } else {
      auto &list = infl[v];
      if (list.empty())
        fail(ctx + ": no vertex has a joint weight (vertex " + std::to_string(v) +
             " has all-zero weights)");
      std::sort(list.begin(), list.end(), [](auto &a, auto &b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
      });
      double total = 0; // of every influence: dropping past the 4th is counted apart
      for (auto &[w, j] : list)
        total += w;
      if (std::abs(total - 1.0) > 2e-3)
        ++state.renormalised;
      if (list.size() > 4) {
        ++state.moreThan4;
        list.resize(4);
      }
      double sum = 0;
      for (auto &[w, j] : list)
        sum += w;
      for (size_t k = 0; k < list.size(); ++k) {
        ids[k] = oldToNew_[size_t(list[k].second)];
        ws[int(k)] = float(list[k].first / sum);
      }
    }
    mesh.joints.push_back(ids);
    mesh.weights.push_back(ws);
  }
}

size_t Importer::partOf(const tinygltf::Primitive &prim, bool hasUv, MeshState &state) {
  const bool known = prim.material >= 0 && size_t(prim.material) < model_.materials.size();
  std::string name = known ? model_.materials[size_t(prim.material)].name : "";
  if (name.empty())
    name = prim.material >= 0 ? "material" + std::to_string(prim.material) : "default";
  const auto it = std::find(state.partOrder.begin(), state.partOrder.end(), name);
  const size_t part = size_t(it - state.partOrder.begin());
  if (it != state.partOrder.end())
    return part;
  state.partOrder.push_back(name);
  state.partTriangles.emplace_back();
  SkinnedMesh::Part look;
  if (known) {
    const auto &mat = model_.materials[size_t(prim.material)];
    const auto &f = mat.pbrMetallicRoughness.baseColorFactor;
    if (f.size() == 4)
      look.colour = glm::vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
    look.seeThrough = mat.alphaMode == "MASK" || mat.alphaMode == "BLEND";
  }
  look.textured = baseColorImage(prim.material) >= 0 && hasUv;
  state.partLooks.push_back(look);
  return part;
}

void Importer::warnMeshRepairs(const MeshState &state) {
  auto &mesh = out_.mesh;
  warnCount("unweighted_vertices", state.unweighted,
            "skinned vertices had all-zero weights: each takes the influences of the nearest "
            "weighted vertex of its primitive");
  warnCount("points_or_lines_skipped", state.pointsOrLines,
            "primitives draw points or lines, not triangles: skipped");
  if (mesh.indices.empty())
    fail(state.pointsOrLines ? "mesh has no triangles: its primitives draw points or lines"
                             : "mesh has no triangles");
  if (!hasUvs_)
    mesh.uvs.clear();
  warnCount("more_than_4_influences", state.moreThan4,
            "vertices had more than 4 joint influences: kept the 4 largest, renormalised");
  warnCount("weights_renormalised", state.renormalised,
            "vertices had weights not summing to 1: renormalised");
  warnCount("duplicate_primitives_dropped", state.duplicatePrimitives,
            "primitives repeated another's vertices, indices and material: dropped");
  warnCount("normals_computed", state.missingNormals,
            "primitives had no NORMAL: computed from faces");
  warnCount("mirrored_winding", state.mirroredPrimitives,
            "primitives sit under a mirroring transform (a negative scale): their triangles, "
            "clockwise in the file as glTF has it there, are stored counter-clockwise");
}

// What identifies a primitive's vertices: its vertex attributes' accessors, how its material
// maps their UVs (base_colour_uv.h), and its joint (a rigid part) or its skin (one mesh bound by
// two skins is two sets of vertices).
std::string Importer::vertexKeyOf(const tinygltf::Primitive &prim, const MeshNode &mn) const {
  // Appended, not "s" + to_string(...): GCC 12 warns of an overlap there (-Wrestrict, wrongly).
  std::string key = mn.rigid >= 0 ? "" : "s";
  key += std::to_string(mn.rigid >= 0 ? int(mn.rigidJoint) : mn.skin);
  for (const auto &[name, accessor] : prim.attributes)
    key += ";" + name + "=" + std::to_string(accessor);
  return key + ";uv=" + baseColourUv(model_, prim.material).key();
}

// Vertex and triangle totals from the accessors' declared counts (each distinct primitive
// once), checked against the limits before any primitive is read.
void Importer::checkMeshSize() const {
  std::set<std::string> vertexSets, primitives;
  uint64_t vertices = 0, triangles = 0;
  for (const auto &mn : meshNodes_)
    for (const auto &prim : model_.meshes[size_t(model_.nodes[size_t(mn.node)].mesh)].primitives) {
      auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end() || !drawsTriangles(prim.mode))
        continue; // the reading loop names it or skips it
      const std::string key = vertexKeyOf(prim, mn);
      const uint64_t vc = accessors_.count(pos->second);
      if (!primitives
               .insert(key + "|" + std::to_string(prim.indices) + "|" +
                       std::to_string(prim.material))
               .second)
        continue;
      if (vertexSets.insert(key).second)
        vertices += vc;
      triangles +=
          triangleCount(prim.mode, prim.indices >= 0 ? accessors_.count(prim.indices) : vc);
    }
  if (vertices > limits::kVertices)
    fail("the meshes hold " + std::to_string(vertices) + " vertices, over the limit of " +
         std::to_string(limits::kVertices));
  if (triangles > limits::kTriangles)
    fail("the meshes hold " + std::to_string(triangles) + " triangles, over the limit of " +
         std::to_string(limits::kTriangles));
}

void Importer::computeNormals(uint32_t base, const std::vector<uint32_t> &idx) {
  auto &m = out_.mesh;
  for (size_t t = 0; t + 2 < idx.size(); t += 3) {
    glm::vec3 a = m.positions[base + idx[t]], b = m.positions[base + idx[t + 1]],
              c = m.positions[base + idx[t + 2]];
    glm::vec3 n = glm::cross(b - a, c - a);
    for (int k = 0; k < 3; ++k)
      m.normals[base + idx[t + size_t(k)]] += n;
  }
  for (size_t v = base; v < m.normals.size(); ++v) {
    float len = glm::length(m.normals[v]);
    m.normals[v] = len > 0 ? m.normals[v] / len : glm::vec3(0, 1, 0);
  }
}

} // namespace crowd::gltf
