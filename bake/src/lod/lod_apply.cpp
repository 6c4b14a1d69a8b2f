// applyLod: a character's mesh through bakeLod (its triangles, welding groups and poses), and
// the mesh put back in the LOD order, sub-mesh by sub-mesh.
#include "crowd/bake/lod_bake.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

#include "crowd/bake/character.h"
#include "crowd/bake/evaluate.h"
#include "crowd/formats/error.h"
#include "float_key.h"

namespace crowd {

LodTriangles lodTriangles(const SkinnedMesh &in) {
  const std::vector<uint32_t> partOf = triangleParts(in);
  const uint32_t triangles = uint32_t(in.indices.size() / 3);
  LodTriangles lt;
  lt.group.assign(in.positions.size(), 0);
  std::map<std::array<uint32_t, 3>, uint32_t> first; // a triangle's vertices -> distinct index
  for (uint32_t t = 0; t < triangles; ++t) {
    std::array<uint32_t, 3> v = {in.indices[3 * t], in.indices[3 * t + 1], in.indices[3 * t + 2]};
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end()); // keeps the winding
    const auto it = first.find(v);
    // A repeat within one sub-mesh is a duplicate face: bakeLod drops it and says so.
    if (it != first.end() && partOf[lt.inputsOf[it->second][0]] != partOf[t]) {
      lt.inputsOf[it->second].push_back(t);
      continue;
    }
    first.emplace(v, uint32_t(lt.inputsOf.size()));
    lt.inputsOf.push_back({t});
    lt.indices.insert(lt.indices.end(), &in.indices[3 * t], &in.indices[3 * t] + 3);
    for (uint32_t k : v)
      lt.group[k] = partOf[t];
  }
  // Vertices weld only within a sub-mesh and a skin binding: two at one rest position bound to
  // other joints or weights part when the character moves (one mesh under several skins).
  std::map<std::vector<uint32_t>, uint32_t> groupOf;
  for (size_t k = 0; k < lt.group.size(); ++k) {
    std::vector<uint32_t> key{lt.group[k]};
    for (int i = 0; i < 4; ++i) {
      key.push_back(in.weights[k][i] > 0 ? in.joints[k][size_t(i)] : 0);
      lod::putBits(key, in.weights[k][i]);
    }
    lt.group[k] = groupOf.try_emplace(std::move(key), uint32_t(groupOf.size())).first->second;
  }
  return lt;
}

std::vector<uint32_t> triangleParts(const SkinnedMesh &m) {
  std::vector<uint32_t> part(m.indices.size() / 3, 0);
  for (uint32_t p = 0; p < m.parts.size(); ++p)
    for (uint32_t t = m.parts[p].firstIndex / 3;
         t < (m.parts[p].firstIndex + m.parts[p].indexCount) / 3 && t < part.size(); ++t)
      part[t] = p;
  return part;
}

std::vector<std::vector<glm::vec3>> samplePoses(const Character &c, uint32_t count) {
  std::vector<std::vector<glm::vec3>> poses;
  if (c.clips.empty())
    return poses;
  const uint32_t perClip = uint32_t((count + c.clips.size() - 1) / c.clips.size());
  for (uint32_t i = 0; i < count; ++i) { // round robin over the clips, mid-interval times
    const AnimationClip &clip = c.clips[i % c.clips.size()];
    double t = clip.start + (clip.end - clip.start) * (double(i / c.clips.size()) + 0.5) / perClip;
    auto skinned = posedPositions(c, &clip, t);
    poses.emplace_back(skinned.begin(), skinned.end());
  }
  return poses;
}

// The colour scale is crowd.frag's light (albedo x (0.25 + 0.75 max(n.l, 0)): a normal change d
// changes it by at most 0.75 |albedo| d; a texel is at most 1, so the material's colour bounds a
// textured sub-mesh's).
LodAppearance lodAppearance(const SkinnedMesh &in) {
  const std::vector<uint32_t> partOf = triangleParts(in);
  const size_t V = in.positions.size();
  LodAppearance a;
  a.normals = in.normals;
  a.colourScale.assign(V, 0.0f);
  a.key.assign(V, 0);
  std::map<std::pair<float, float>, uint32_t> uvKey;
  for (size_t i = 0; i < in.indices.size(); ++i) {
    const uint32_t v = in.indices[i];
    const SkinnedMesh::Part *part = in.parts.empty() ? nullptr : &in.parts[partOf[i / 3]];
    const glm::vec3 albedo = part ? glm::vec3(part->colour) : glm::vec3(1.0f);
    a.colourScale[v] = 255.0f * 0.75f * glm::length(albedo);
    if (part && part->textured && !in.uvs.empty()) {
      const std::pair<float, float> uv{in.uvs[v].x + 0.0f, in.uvs[v].y + 0.0f}; // -0 as +0
      a.key[v] = uvKey.try_emplace(uv, uint32_t(uvKey.size() + 1)).first->second;
    }
  }
  return a;
}

namespace {

// Each repeat goes with its first: the same new indices, the same vertex removal deleting it, so
// an outfit's copy simplifies exactly as the part it copies (see lodTriangles). Returns bakeLod's
// result with the repeats listed after their first (r.source: input triangles).
LodResult bakeWithRepeats(const Character &c, const LodOptions &o, Reporter &reporter) {
  const SkinnedMesh &in = c.mesh;
  const uint32_t triangles = uint32_t(in.indices.size() / 3);
  const LodTriangles lt = lodTriangles(in);
  const auto &inputsOf = lt.inputsOf;
  // The rest pose as drawn, not the mesh's own coordinates: those are in another unit where the
  // armature carries a scale (a trooper modelled in cm under a 0.01 armature: its bind-pose cost
  // outweighed every other pose's 10^7 times), and a rigid part's sit in its node's frame.
  const std::vector<glm::dvec3> rest = posedPositions(c, nullptr, 0);
  const LodAppearance appearance = lodAppearance(in);
  LodResult r = bakeLod(std::vector<glm::vec3>(rest.begin(), rest.end()), lt.indices, o, reporter,
                        lt.group, samplePoses(c, o.poses), &appearance);
  if (r.seamClosings) {
    char text[128];
    std::snprintf(text, sizeof text, "%.1f of 255 under the player's light (--seam-budget %g)",
                  r.seamColourChange, o.seamBudget);
    reporter.warn("hard_edges_closed",
                  std::to_string(r.seamClosings) +
                      " render vertices are drawn across a hard edge by the floor (a collapse "
                      "closed it): the drawn colour changes by at most " +
                      text,
                  r.seamClosings);
  }
  const std::vector<uint32_t> source = std::move(r.source), killedBy = std::move(r.killedBy),
                              indices = std::move(r.indices);
  r.source.clear(), r.killedBy.clear(), r.indices.clear();
  std::vector<uint32_t> listed(source.size() + 1, 0); // input triangles of the first t kept
  for (size_t t = 0; t < source.size(); ++t) {
    for (uint32_t input : inputsOf[source[t]]) {
      r.source.push_back(input);
      r.killedBy.push_back(killedBy[t]);
      r.indices.insert(r.indices.end(), &indices[3 * t], &indices[3 * t] + 3);
    }
    listed[t + 1] = uint32_t(r.source.size());
  }
  for (uint32_t &count : r.triangleCount)
    count = listed[count];
  r.inputTriangles = triangles;
  return r;
}

} // namespace

pack::Lod applyLod(Character &c, const LodOptions &o, Reporter &reporter, LodResult *details,
                   const std::vector<uint32_t> &keep) {
  o.validate();
  std::vector<uint32_t> newOf(c.mesh.positions.size(), UINT32_MAX), keepNow;
  const std::vector<uint32_t> copyWas = weldExactCopies(c.mesh, reporter, keep);
  for (uint32_t k = 0; k < copyWas.size(); ++k)
    newOf[copyWas[k]] = k;
  for (uint32_t v : keep) // renumbered past the copies' weld, which keeps them all
    if (v < newOf.size() && newOf[v] != UINT32_MAX)
      keepNow.push_back(newOf[v]);
  std::vector<uint32_t> was = weldFlatShading(c.mesh, reporter, 1, keepNow);
  for (uint32_t &v : was)
    v = copyWas[v];
  SkinnedMesh &in = c.mesh;
  const std::vector<uint32_t> partOf = triangleParts(in);
  reporter.step("LOD: collapse order of " + std::to_string(in.indices.size() / 3) + " triangles");
  LodResult r = bakeWithRepeats(c, o, reporter);
  SkinnedMesh out;
  out.morphDefaults = in.morphDefaults;
  for (const auto &target : in.morphs)
    out.morphs.push_back({target.name, {}, {}});
  for (uint32_t v : r.order) {
    for (size_t t = 0; t < in.morphs.size(); ++t) {
      out.morphs[t].positions.push_back(in.morphs[t].positions[v]);
      out.morphs[t].normals.push_back(in.morphs[t].normals[v]);
    }
    out.positions.push_back(in.positions[v]);
    out.normals.push_back(in.normals[v]);
    if (!in.uvs.empty())
      out.uvs.push_back(in.uvs[v]);
    out.joints.push_back(in.joints[v]);
    out.weights.push_back(in.weights[v]);
    if (!in.sources.empty())
      out.sources.push_back(in.sources[v]);
  }
  // Each part keeps its triangles, in the LOD order; its counts follow from when each goes.
  const uint32_t n = uint32_t(r.order.size());
  pack::Lod lod;
  lod.floorVertices = r.floorVertices;
  lod.collapse = r.collapse;
  lod.error = r.error;
  lod.triangleCounts.assign(in.parts.size() * (size_t(n) + 1), 0);
  for (uint32_t p = 0; p < in.parts.size(); ++p) {
    SkinnedMesh::Part part = in.parts[p]; // keeps its material
    part.firstIndex = uint32_t(out.indices.size());
    uint32_t *counts = &lod.triangleCounts[size_t(p) * (n + 1)];
    for (size_t t = 0; t < r.source.size(); ++t) {
      if (partOf[r.source[t]] != p)
        continue;
      out.indices.insert(out.indices.end(), &r.indices[3 * t], &r.indices[3 * t] + 3);
      ++counts[r.killedBy[t] == UINT32_MAX ? 0 : r.killedBy[t] + 1];
    }
    for (uint32_t v = 1; v <= n; ++v)
      counts[v] += counts[v - 1];
    part.indexCount = uint32_t(out.indices.size()) - part.firstIndex;
    out.parts.push_back(part);
  }
  c.mesh = std::move(out);
  if (details) {
    for (uint32_t &v : r.order) // the caller's vertices, before the welds
      v = was[v];
    *details = std::move(r);
  }
  return lod;
}

} // namespace crowd
