// Outfit bake: garments joined to the body's skeleton, visibility per outfit, body sub-meshes
// marked visible / hidden / partial, outfit-specific copies, and the pack (see outfit_bake.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "crowd/bake/outfit_bake.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

// Appends outfit `g`'s mesh to `merged`, its joints matched to the body's by name, its vertex
// sources numbered as file `file`. Returns the indices of its parts in merged.mesh.parts.
std::vector<size_t> appendGarments(Character &merged, const OutfitInput &outfit, int32_t file,
                                   Reporter &reporter) {
  const Character &g = outfit.character;
  const std::string who = "outfit '" + outfit.name + "'";
  if (!g.skinned)
    throw Error(who + " has no skin: garments must be skinned to the body's skeleton");
  std::vector<bool> used(g.jointCount(), false);
  for (size_t v = 0; v < g.mesh.vertexCount(); ++v)
    for (int k = 0; k < 4; ++k)
      if (g.mesh.weights[v][k] > 0)
        used[g.mesh.joints[v][size_t(k)]] = true;
  std::vector<uint16_t> map(g.jointCount(), 0);
  for (size_t j = 0; j < g.jointCount(); ++j) {
    if (!used[j])
      continue;
    size_t b = 0;
    while (b < merged.jointCount() && merged.jointName(b) != g.jointName(j))
      ++b;
    if (b == merged.jointCount())
      throw Error(who + " is skinned to joint '" + g.jointName(j) +
                  "', which the body's skeleton does not have (outfits must share its skeleton)");
    const glm::dmat4 &mine = g.inverseBind[j], &theirs = merged.inverseBind[b];
    double diff = 0, scale = 1;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        diff = std::max(diff, std::abs(mine[c][r] - theirs[c][r]));
        scale = std::max(scale, std::abs(theirs[c][r]));
      }
    if (diff > 1e-4 * scale)
      throw Error(who + ": joint '" + g.jointName(j) +
                  "' has another inverse bind matrix than the body's (bound in another pose; "
                  "largest difference " +
                  std::to_string(diff) + ")");
    map[j] = uint16_t(b);
  }
  auto &m = merged.mesh;
  const auto base = uint32_t(m.vertexCount());
  for (size_t v = 0; v < g.mesh.vertexCount(); ++v) {
    m.positions.push_back(g.mesh.positions[v]);
    m.normals.push_back(g.mesh.normals[v]);
    if (!m.uvs.empty())
      m.uvs.push_back(g.mesh.uvs.empty() ? glm::vec2(0) : g.mesh.uvs[v]);
    auto ids = g.mesh.joints[v];
    for (int k = 0; k < 4; ++k)
      ids[size_t(k)] = g.mesh.weights[v][k] > 0 ? map[ids[size_t(k)]] : 0;
    m.joints.push_back(ids);
    m.weights.push_back(g.mesh.weights[v]);
    for (auto &target : m.morphs) { // the body's targets leave garments alone
      target.positions.push_back(glm::vec3(0));
      target.normals.push_back(glm::vec3(0));
    }
  }
  if (!g.mesh.morphs.empty())
    reporter.warn("garment_morphs_dropped",
                  who + ": its " + std::to_string(g.mesh.morphs.size()) +
                      " morph targets are not carried (garments follow the skeleton only)",
                  g.mesh.morphs.size());
  if (m.sources.size() + g.mesh.vertexCount() == m.vertexCount() &&
      g.mesh.sources.size() == g.mesh.vertexCount()) {
    for (auto source : g.mesh.sources) {
      source.file = file;
      m.sources.push_back(source);
    }
  } else {
    m.sources.clear(); // a part without sources: the merge has none
  }
  std::vector<size_t> parts;
  for (auto part : g.mesh.parts) {
    if (part.textured)
      reporter.warn("garment_texture_dropped",
                    who + ", garment '" + part.name +
                        "': its texture is not carried (the pack holds the body's diffuse "
                        "texture); drawn in its base colour");
    if (part.seeThrough)
      reporter.warn("see_through_garment", who + ", garment '" + part.name +
                                               "' is alpha-masked or blended: it hides nothing");
    part.textured = false;
    const uint32_t first = part.firstIndex;
    part.firstIndex = uint32_t(m.indices.size());
    for (uint32_t i = first; i < first + part.indexCount; ++i)
      m.indices.push_back(base + g.mesh.indices[i]);
    parts.push_back(m.parts.size());
    m.parts.push_back(part);
  }
  return parts;
}

uint32_t faces(const SkinnedMesh::Part &p) { return p.indexCount / 3; }

// The region map "joint": each part split by the joint that weighs most on each face (summed
// over its vertices; ties to the lower joint), named "part/joint", in joint order.
Character splitByJoint(const Character &body) {
  Character c = body;
  auto &m = c.mesh;
  m.indices.clear();
  m.parts.clear();
  for (const auto &part : body.mesh.parts) {
    std::map<uint16_t, std::vector<uint32_t>> groups; // joint -> its faces' indices
    for (uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; i += 3) {
      std::map<uint16_t, double> weight;
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t v = body.mesh.indices[i + k];
        for (int w = 0; w < 4; ++w)
          weight[body.mesh.joints[v][size_t(w)]] += body.mesh.weights[v][w];
      }
      uint16_t best = weight.begin()->first;
      for (const auto &[joint, w] : weight)
        if (w > weight[best])
          best = joint;
      auto &g = groups[best];
      g.insert(g.end(), body.mesh.indices.begin() + i, body.mesh.indices.begin() + i + 3);
    }
    for (const auto &[joint, indices] : groups) {
      SkinnedMesh::Part sub = part;
      sub.name = part.name + "/" + body.jointName(joint);
      sub.firstIndex = uint32_t(m.indices.size());
      sub.indexCount = uint32_t(indices.size());
      m.indices.insert(m.indices.end(), indices.begin(), indices.end());
      m.parts.push_back(sub);
    }
  }
  return c;
}

} // namespace

Character dressCharacter(const Character &body, const OutfitInput &outfit,
                         const std::string &regions, Reporter &reporter) {
  Character dressed = regions == "joint" ? splitByJoint(body) : body;
  appendGarments(dressed, outfit, 1, reporter);
  return dressed;
}

namespace {
// A hole the check found, as one error: the outfit, the body parts seen through (in its worst
// image, then over all), the frame and the view of that image.
std::string partsOf(const std::vector<uint32_t> &faces, const Character &body) {
  std::map<std::string, int> where; // faces per body sub-mesh
  for (uint32_t t : faces)
    for (const auto &part : body.mesh.parts)
      if (t * 3 >= part.firstIndex && t * 3 < part.firstIndex + part.indexCount)
        ++where[part.name];
  std::string list;
  for (const auto &[part, count] : where)
    list += (list.empty() ? "" : ", ") + part + " " + std::to_string(count);
  return list.empty() ? "none" : list;
}

void failOnHoles(const HoleCheck &holes, const Character &body) {
  for (const auto &o : holes.outfits) {
    if (o.differingPixels == 0)
      continue;
    throw Error("hole check failed: outfit '" + o.name + "' shows body faces (" +
                partsOf(o.worstLeaked, body) + ") through a hole in " +
                std::to_string(o.worstPixels) + " pixels at " + o.worstFrame + ", " + o.worstView +
                "; in all " + std::to_string(o.differingPixels) + " pixels of " +
                std::to_string(o.images) +
                " images, removed faces seen: " + partsOf(o.leaked, body) +
                " (a finer visibility sees it: more rays, 48 pass the sample outfits; 4 points;"
                " a frame step of 1)");
  }
}
// The pack's mesh as it is assembled: body parts first, then per outfit its copies and its
// garments, each triangle remembering its source (a body triangle, or itself).
struct PackMesh {
  Character &out;
  const Character &joined;
  OutfitBakeResult &r;
  uint32_t appendPart(SkinnedMesh::Part part, const std::vector<uint32_t> &triangles) {
    part.firstIndex = uint32_t(out.mesh.indices.size());
    part.indexCount = uint32_t(triangles.size() * 3);
    for (uint32_t t : triangles) {
      for (int k = 0; k < 3; ++k)
        out.mesh.indices.push_back(joined.mesh.indices[3 * t + k]);
      r.sourceTriangle.push_back(t < r.bodyTriangles ? t : uint32_t(r.sourceTriangle.size()));
    }
    out.mesh.parts.push_back(part);
    return uint32_t(out.mesh.parts.size() - 1);
  }
};

// One outfit's table entry and figures: each body sub-mesh visible, hidden or partly hidden (a
// copy of its visible faces, shared by outfits that leave the same ones), then its garments.
void bakeOneOutfit(size_t oi, const std::vector<OutfitInput> &outfits, const Character &body,
                   const std::vector<size_t> &garmentParts, const OutfitOptions &options,
                   PackMesh &mesh,
                   std::map<std::pair<size_t, std::vector<uint32_t>>, uint32_t> &copies,
                   pack::Outfits &table, Reporter &reporter) {
  OutfitBakeResult &r = mesh.r;
  const auto &bodyMesh = body.mesh;
  reporter.step("visibility: outfit " + std::to_string(oi + 1) + " of " +
                std::to_string(outfits.size()) + " (" + outfits[oi].name + ")");
  const auto start = std::chrono::steady_clock::now();
  std::vector<PlacedLoop> worn;
  for (const PlacedLoop &l : r.loops)
    if (l.outfit == oi)
      worn.push_back(l);
  const auto hidden =
      hiddenBodyFaces(mesh.joined, r.bodyTriangles, garmentParts, options.visibility, worn);
  OutfitFigures fig;
  fig.name = outfits[oi].name;
  pack::Outfits::Outfit entry;
  entry.name = outfits[oi].name;
  for (size_t s = 0; s < bodyMesh.parts.size(); ++s) {
    const auto &part = bodyMesh.parts[s];
    std::vector<uint32_t> visible;
    for (uint32_t t = part.firstIndex / 3; t < (part.firstIndex + part.indexCount) / 3; ++t)
      if (!hidden[t])
        visible.push_back(t);
    SubMeshCoverage sc{part.name, faces(part), uint32_t(faces(part) - visible.size()), "", false};
    fig.hiddenFaces += sc.hidden;
    pack::Coverage c = pack::Coverage::Visible;
    if (visible.empty()) {
      c = pack::Coverage::Hidden;
    } else if (sc.hidden > 0 && double(sc.hidden) >= options.minSaving * double(sc.faces)) {
      c = pack::Coverage::Partial;
      auto [it, fresh] = copies.try_emplace({s, visible}, 0);
      if (fresh) {
        SkinnedMesh::Part copy = part;
        copy.name = part.name + "@" + outfits[oi].name;
        it->second = mesh.appendPart(copy, visible);
      }
      entry.subMeshes.push_back(it->second);
    } else {
      sc.keptWhole = sc.hidden > 0;
      entry.subMeshes.push_back(uint32_t(s));
    }
    if (c != pack::Coverage::Visible)
      fig.removedFaces += sc.hidden;
    sc.coverage = pack::name(c);
    entry.coverage.push_back(c);
    fig.subMeshes.push_back(sc);
  }
  for (size_t p : garmentParts) {
    const auto &part = mesh.joined.mesh.parts[p];
    std::vector<uint32_t> triangles;
    for (uint32_t t = part.firstIndex / 3; t < (part.firstIndex + part.indexCount) / 3; ++t)
      triangles.push_back(t);
    entry.subMeshes.push_back(mesh.appendPart(part, triangles));
    fig.garmentFaces += faces(part);
  }
  std::sort(entry.subMeshes.begin(), entry.subMeshes.end());
  if (fig.hiddenFaces <= r.bareHiddenFaces)
    reporter.warn("outfit_hides_nothing", "outfit '" + fig.name +
                                              "' hides no body face the body does not hide by "
                                              "itself");
  fig.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.naiveFaces += fig.garmentFaces;
  r.prefittedFaces += r.bodyTriangles - fig.removedFaces + fig.garmentFaces;
  r.taggedFaces += fig.garmentFaces;
  table.outfits.push_back(std::move(entry));
  r.outfits.push_back(std::move(fig));
}

// The merged mesh in LOD order (options.lod): triangles reorder within each sub-mesh, so the
// outfit table stays valid; the triangles' sources and the loops' vertices follow.
pack::Lod applyOutfitLod(OutfitBakeResult &r, const Character &joined, const OutfitOptions &options,
                         Reporter &reporter) {
  Character &out = r.merged;
  const std::vector<uint32_t> partOf = triangleParts(out.mesh);
  LodResult details;
  std::vector<uint32_t> looped; // the pack places a loop's vertices by their glTF source
  for (const PlacedLoop &l : r.loops)
    looped.insert(looped.end(), l.vertices.begin(), l.vertices.end());
  pack::Lod lod = applyLod(out, *options.lod, reporter, &details, looped);
  std::vector<uint32_t> source; // applyLod's output order: per part, the kept triangles
  for (uint32_t p = 0; p < out.mesh.parts.size(); ++p)
    for (uint32_t t : details.source)
      if (partOf[t] == p)
        source.push_back(r.sourceTriangle[t]);
  r.sourceTriangle = std::move(source);
  r.lodColourChange = details.colourChange;
  // The loops' vertices follow the LOD's order (and its flat-shading weld), or the hole check
  // would pose the loops onto other vertices of the reordered mesh.
  std::vector<uint32_t> newOf(joined.mesh.vertexCount(), UINT32_MAX);
  for (uint32_t k = 0; k < details.order.size(); ++k)
    newOf[details.order[k]] = k;
  for (PlacedLoop &l : r.loops)
    for (uint32_t &v : l.vertices)
      v = newOf[v];
  return lod;
}

} // namespace

// The stages: every garment joined onto the body, the faces the body hides by itself, each
// outfit's table entry, the totals, the LOD, the animation bake, the hole check.
OutfitBakeResult bakeOutfits(const Character &template_, const std::vector<OutfitInput> &outfits,
                             const OutfitOptions &options, Reporter &reporter) {
  options.validate();
  const Character body = options.regions == "joint" ? splitByJoint(template_) : template_;
  if (outfits.empty())
    throw Error("outfits: no outfit given (--outfit FILE)");
  if (!body.skinned)
    throw Error("the body has no skin: outfits need a skinned body template");
  OutfitBakeResult r;
  const auto &bodyMesh = body.mesh;
  r.bodyTriangles = uint32_t(bodyMesh.indices.size() / 3);

  // Every garment on the body's skeleton, for visibility (body first, then each outfit's).
  Character joined = body;
  std::vector<std::vector<size_t>> garmentParts;
  std::vector<uint32_t> firstVertex;
  for (size_t k = 0; k < outfits.size(); ++k) {
    firstVertex.push_back(uint32_t(joined.mesh.vertexCount()));
    garmentParts.push_back(appendGarments(joined, outfits[k], int32_t(k + 1), reporter));
  }
  r.loops = placeLoops(joined, outfits, firstVertex);

  Character &out = r.merged;
  out = joined;
  out.mesh.indices.assign(bodyMesh.indices.begin(), bodyMesh.indices.end());
  out.mesh.parts.assign(bodyMesh.parts.begin(), bodyMesh.parts.end());
  for (uint32_t t = 0; t < r.bodyTriangles; ++t)
    r.sourceTriangle.push_back(t);
  PackMesh mesh{out, joined, r};

  // Faces the body hides by itself (and the ground): no outfit is needed to drop them.
  reporter.step("visibility: the body alone");
  const auto bare = hiddenBodyFaces(joined, r.bodyTriangles, {}, options.visibility);
  for (uint8_t h : bare)
    r.bareHiddenFaces += h;

  pack::Outfits table;
  table.bodySubMeshes = uint32_t(bodyMesh.parts.size());
  std::map<std::pair<size_t, std::vector<uint32_t>>, uint32_t> copies; // shared when identical
  for (size_t oi = 0; oi < outfits.size(); ++oi)
    bakeOneOutfit(oi, outfits, body, garmentParts[oi], options, mesh, copies, table, reporter);
  for (const auto &[key, sub] : copies)
    r.specificFaces += key.second.size();
  r.naiveFaces += r.bodyTriangles;
  r.taggedFaces += r.bodyTriangles + r.specificFaces;
  r.framesTested =
      uint32_t(outfitFrames(body, options.visibility.fps, options.visibility.frameStep).size());
  r.loopFramesTested =
      uint32_t(outfitPoses(body, options.visibility.fps, options.visibility.frameStep, r.loops,
                           options.visibility.loopFrames)
                   .size()) -
      r.framesTested;

  for (const auto &part : out.mesh.parts) {
    table.colours.insert(table.colours.end(),
                         {part.colour.r, part.colour.g, part.colour.b, part.colour.a});
    table.textured.push_back(part.textured && out.diffuse ? 1 : 0);
  }
  std::optional<pack::Lod> lod;
  if (options.lod)
    lod = applyOutfitLod(r, joined, options, reporter);
  r.anim = bakeAnimation(out, options.anim, reporter);
  r.anim.pack.lod = std::move(lod);
  r.anim.pack.outfits = std::move(table);
  r.anim.pack.looks.reset(); // a clothed pack's looks are its outfit table's
  if (options.check > 0) {
    HoleCheckOptions ho;
    ho.frameStep = options.check;
    ho.loopFrames = options.visibility.loopFrames;
    ho.threads = options.visibility.threads;
    reporter.step("hole check: every outfit drawn whole and culled");
    r.holes = checkHoles(r, ho);
    failOnHoles(r.holes, body);
  }
  return r;
}

} // namespace crowd
