#include "crowd/bake/lod_bake.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <queue>
#include <set>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "crowd/bake/character.h"
#include "crowd/bake/evaluate.h"
#include "crowd/formats/error.h"

namespace crowd {
namespace {

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;
using Quadric = std::array<double, 10>; // symmetric 4x4: xx xy xz xw yy yz yw zz zw ww

void addPlane(Quadric &q, glm::dvec3 n, double d, double w) {
  const double p[4] = {n.x, n.y, n.z, d};
  int k = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i; j < 4; ++j)
      q[size_t(k++)] += w * p[i] * p[j];
}

double evaluate(const Quadric &a, const Quadric &b, glm::dvec3 v) {
  const double p[4] = {v.x, v.y, v.z, 1};
  double s = 0;
  int k = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i; j < 4; ++j, ++k)
      s += (i == j ? 1 : 2) * (a[size_t(k)] + b[size_t(k)]) * p[i] * p[j];
  return std::max(s, 0.0);
}

glm::dvec3 toGlm(const Mesh::Point &p) { return {p[0], p[1], p[2]}; }

struct Candidate {
  double cost;
  int halfedge;
  uint32_t fromStamp, toStamp;
  bool operator<(const Candidate &o) const { // the priority queue pops the cheapest, then the
    return cost != o.cost ? cost > o.cost : halfedge > o.halfedge; // lowest halfedge: no ties
  }
};

} // namespace

LodResult bakeLod(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                  const LodOptions &o, Reporter &reporter, const std::vector<uint32_t> &group,
                  const std::vector<std::vector<glm::vec3>> &poses) {
  for (const auto &pose : poses)
    if (pose.size() != positions.size())
      throw Error("lod: a pose has another vertex count than the mesh");
  if (indices.size() % 3 != 0)
    throw Error("lod: the index count is not a multiple of 3");
  for (uint32_t i : indices)
    if (i >= positions.size())
      throw Error("lod: an index points past the vertices");
  omerr().disable(); // complex edges are expected: they are split and reported below
  LodResult r;
  r.inputTriangles = uint32_t(indices.size() / 3);

  // Weld by position (within a group): the copies of a seam vertex become one topological vertex.
  std::map<std::array<float, 4>, uint32_t> weldOf;
  std::vector<uint32_t> welded(positions.size());
  std::vector<glm::vec3> weldedPos;
  for (size_t v = 0; v < positions.size(); ++v) {
    float g = group.empty() ? 0.0f : float(group[v]);
    auto [it, fresh] =
        weldOf.try_emplace({g, positions[v].x, positions[v].y, positions[v].z}, weldOf.size());
    welded[v] = it->second;
    if (fresh)
      weldedPos.push_back(positions[v]);
  }

  // Render vertices: input vertices, plus copies where a non-manifold face is split off.
  std::vector<uint32_t> source(positions.size());
  for (uint32_t v = 0; v < source.size(); ++v)
    source[v] = v;
  Mesh mesh;
  std::vector<Mesh::VertexHandle> handle(weldedPos.size());
  for (size_t w = 0; w < weldedPos.size(); ++w)
    handle[w] = mesh.add_vertex({weldedPos[w].x, weldedPos[w].y, weldedPos[w].z});
  // Per OpenMesh face: its corners as (OpenMesh vertex, render vertex).
  std::vector<std::array<std::pair<int, uint32_t>, 3>> corner;
  std::vector<uint32_t> inputTriangle;
  std::set<std::array<uint32_t, 3>> seen;
  size_t degenerate = 0, duplicate = 0, split = 0;
  for (uint32_t t = 0; t < r.inputTriangles; ++t) {
    std::array<uint32_t, 3> rv = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
    std::array<uint32_t, 3> w = {welded[rv[0]], welded[rv[1]], welded[rv[2]]};
    glm::dvec3 a = weldedPos[w[0]], b = weldedPos[w[1]], c = weldedPos[w[2]];
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2] ||
        glm::length(glm::cross(b - a, c - a)) == 0) {
      ++degenerate;
      continue;
    }
    std::array<uint32_t, 3> key = w;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) {
      ++duplicate;
      continue;
    }
    std::array<Mesh::VertexHandle, 3> vh = {handle[w[0]], handle[w[1]], handle[w[2]]};
    auto f = mesh.add_face(vh[0], vh[1], vh[2]);
    if (!f.is_valid()) { // a complex edge or vertex: the face gets vertices of its own
      ++split;
      for (size_t k = 0; k < 3; ++k) {
        const Mesh::Point at = mesh.point(vh[k]); // a copy: add_vertex may move the points
        vh[k] = mesh.add_vertex(at);
        source.push_back(source[rv[k]]);
        rv[k] = uint32_t(source.size() - 1);
      }
      f = mesh.add_face(vh[0], vh[1], vh[2]);
    }
    if (size_t(f.idx()) != corner.size())
      throw Error("lod: OpenMesh numbered faces out of order");
    corner.push_back({{{vh[0].idx(), rv[0]}, {vh[1].idx(), rv[1]}, {vh[2].idx(), rv[2]}}});
    inputTriangle.push_back(t);
  }
  if (degenerate)
    reporter.warn("degenerate_triangles",
                  std::to_string(degenerate) + " zero-area triangles dropped from the LOD mesh");
  if (duplicate)
    reporter.warn("duplicate_triangles",
                  std::to_string(duplicate) + " duplicate triangles dropped from the LOD mesh");
  if (split)
    reporter.warn("non_manifold", std::to_string(split) +
                                      " triangles on non-manifold edges or vertices split off "
                                      "(their vertices duplicated)");
  if (corner.empty())
    throw Error("lod: the mesh has no triangle with an area");

  std::vector<std::array<uint32_t, 3>> initialCorner;
  for (const auto &c : corner)
    initialCorner.push_back({c[0].second, c[1].second, c[2].second});
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();

  const size_t V = source.size(), F = corner.size();
  std::vector<glm::dvec3> originalNormal(F);
  // One quadric per vertex per pose (the bind pose first): a collapse costs what it moves the
  // surface in every pose, each measured where the vertex is in that pose.
  const size_t P = 1 + poses.size();
  std::vector<uint32_t> inputOf(mesh.n_vertices()); // an input vertex at each OpenMesh vertex
  for (const auto &c : corner)
    for (const auto &[vh, rv] : c)
      inputOf[size_t(vh)] = source[rv];
  auto posed = [&](Mesh::VertexHandle v, size_t p) {
    return p == 0 ? toGlm(mesh.point(v)) : glm::dvec3(poses[p - 1][inputOf[size_t(v.idx())]]);
  };
  std::vector<Quadric> quadric(mesh.n_vertices() * P, Quadric{});
  auto Q = [&](Mesh::VertexHandle v, size_t p) -> Quadric & {
    return quadric[size_t(v.idx()) * P + p];
  };
  auto faceNormal = [&](Mesh::FaceHandle f, Mesh::VertexHandle moved, glm::dvec3 to) {
    glm::dvec3 p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f))
      p[k++] = v == moved ? to : toGlm(mesh.point(v));
    return glm::cross(p[1] - p[0], p[2] - p[0]);
  };
  for (auto f : mesh.faces()) {
    originalNormal[size_t(f.idx())] = glm::normalize(faceNormal(f, Mesh::VertexHandle(), {}));
    for (size_t p = 0; p < P; ++p) {
      glm::dvec3 c[3];
      int k = 0;
      for (auto v : mesh.fv_range(f))
        c[k++] = posed(v, p);
      glm::dvec3 n = glm::cross(c[1] - c[0], c[2] - c[0]);
      double area = glm::length(n) * 0.5;
      if (area == 0)
        continue;
      n /= 2 * area;
      for (auto v : mesh.fv_range(f))
        addPlane(Q(v, p), n, -glm::dot(n, c[0]), area);
    }
  }
  auto renderOf = [&](Mesh::FaceHandle f, Mesh::VertexHandle v) -> uint32_t & {
    for (auto &c : corner[size_t(f.idx())])
      if (c.first == v.idx())
        return c.second;
    throw Error("lod: internal error, a face lost its corner");
  };
  // An edge is special when it is on the boundary or a seam (the faces on its two sides use
  // different render vertices for an end).
  auto special = [&](Mesh::EdgeHandle e) {
    if (mesh.is_boundary(e))
      return true;
    auto h = mesh.halfedge_handle(e, 0);
    auto f0 = mesh.face_handle(h), f1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
    auto a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
    return renderOf(f0, a) != renderOf(f1, a) || renderOf(f0, b) != renderOf(f1, b);
  };
  // Boundaries and seams also hold their shape: each special edge adds, to both ends, a heavily
  // weighted plane through it, perpendicular to its face, so moving a corner or cutting across
  // the line costs what moving off the surface would.
  for (auto e : mesh.edges()) {
    if (!special(e))
      continue;
    auto h = mesh.halfedge_handle(e, 0);
    if (!mesh.face_handle(h).is_valid())
      h = mesh.opposite_halfedge_handle(h);
    auto a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
    auto third = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
    for (size_t p = 0; p < P; ++p) {
      glm::dvec3 pa = posed(a, p), pb = posed(b, p);
      glm::dvec3 m = glm::cross(pb - pa, glm::cross(pb - pa, posed(third, p) - pa));
      if (glm::length(m) == 0)
        continue;
      m = glm::normalize(m);
      double w = 100.0 * glm::dot(pb - pa, pb - pa);
      for (auto v : {a, b})
        addPlane(Q(v, p), m, -glm::dot(m, pa), w);
    }
  }
  const double cosLimit = std::cos(o.maxNormalDeviationDeg * 3.14159265358979323846 / 180);
  auto legal = [&](Mesh::HalfedgeHandle h) {
    if (!mesh.is_collapse_ok(h))
      return false;
    auto from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
    // A seam or boundary vertex slides only along its line: exactly two special edges, and
    // this one of them.
    int specials = 0;
    bool along = false;
    for (auto oh : mesh.voh_range(from))
      if (special(mesh.edge_handle(oh))) {
        ++specials;
        along |= oh == h;
      }
    if (specials != 0 && !(specials == 2 && along))
      return false;
    const glm::dvec3 target = toGlm(mesh.point(to));
    for (auto f : mesh.vf_range(from)) {
      bool hasTo = false;
      for (auto v : mesh.fv_range(f))
        hasTo |= v == to;
      if (hasTo)
        continue; // this face disappears
      glm::dvec3 n = faceNormal(f, from, target);
      double len = glm::length(n);
      if (len <= 1e-12 * glm::dot(target, target) + 1e-30)
        return false;
      if (glm::dot(n / len, originalNormal[size_t(f.idx())]) < cosLimit ||
          glm::dot(n, faceNormal(f, Mesh::VertexHandle(), {})) <= 0)
        return false;
    }
    return true;
  };

  std::vector<uint32_t> stamp(mesh.n_vertices(), 0);
  std::priority_queue<Candidate> queue;
  auto push = [&](Mesh::HalfedgeHandle h) {
    auto from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
    double cost = 0;
    for (size_t p = 0; p < P; ++p)
      cost += evaluate(Q(from, p), Q(to, p), posed(to, p));
    queue.push({cost / double(P), h.idx(), stamp[size_t(from.idx())], stamp[size_t(to.idx())]});
  };

  // Removal record, in render vertices: who goes, into whom, at what cost; and for each face,
  // the render vertex whose removal deletes it.
  std::vector<uint32_t> removed, target(V, UINT32_MAX);
  std::vector<float> cost(V, 0.0f);
  std::vector<int64_t> killer(F, -1);
  size_t alive = F;
  const size_t floorFaces = size_t(std::ceil(o.floorFraction * double(F)));
  bool progress = true;
  while (alive > floorFaces && progress) {
    // Costs change only around a collapse, but legality can change one ring further out: when
    // the queue runs dry, every remaining edge gets another chance until none is legal.
    progress = false;
    for (auto h : mesh.halfedges())
      if (!mesh.status(h).deleted())
        push(h);
    while (!queue.empty() && alive > floorFaces) {
      Candidate c = queue.top();
      queue.pop();
      Mesh::HalfedgeHandle h(c.halfedge);
      if (mesh.status(h).deleted())
        continue;
      auto from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
      if (mesh.status(from).deleted() || stamp[size_t(from.idx())] != c.fromStamp ||
          stamp[size_t(to.idx())] != c.toStamp || !legal(h))
        continue;
      // Pair each render vertex of `from` with the render vertex of `to` on the same side.
      std::vector<std::pair<uint32_t, uint32_t>> pairs;
      for (auto side : {h, mesh.opposite_halfedge_handle(h)}) {
        auto f = mesh.face_handle(side);
        if (!f.is_valid())
          continue;
        uint32_t a = renderOf(f, from), b = renderOf(f, to);
        if (std::find_if(pairs.begin(), pairs.end(), [&](auto &p) { return p.first == a; }) ==
            pairs.end())
          pairs.push_back({a, b});
        killer[size_t(f.idx())] = a;
        --alive;
      }
      std::vector<Mesh::FaceHandle> around(mesh.vf_begin(from), mesh.vf_end(from));
      for (auto f : around) {
        uint32_t &rv = renderOf(f, from);
        auto p = std::find_if(pairs.begin(), pairs.end(), [&](auto &q) { return q.first == rv; });
        if (p == pairs.end()) // cannot happen: legal() keeps seams to their lines
          throw Error("lod: internal error, a render vertex has no partner");
        if (killer[size_t(f.idx())] < 0)
          for (auto &cn : corner[size_t(f.idx())])
            if (cn.first == from.idx())
              cn = {to.idx(), p->second};
      }
      for (auto [a, b] : pairs) {
        removed.push_back(a);
        target[a] = b;
        cost[a] = float(c.cost);
      }
      for (size_t p = 0; p < P; ++p)
        for (size_t k = 0; k < 10; ++k)
          Q(to, p)[k] += Q(from, p)[k];
      mesh.collapse(h);
      progress = true;
      ++stamp[size_t(to.idx())];
      for (auto oh : mesh.voh_range(to)) {
        push(oh);
        push(mesh.opposite_halfedge_handle(oh));
      }
    }
    queue = {};
  }

  // Numbering: vertices never removed first (input order), then the removed ones, last removed
  // first; render vertices no face uses (isolated) go last, into vertex 0.
  std::vector<uint8_t> used(V, 0);
  for (const auto &c : corner)
    for (const auto &cn : c)
      used[cn.second] = 1;
  for (uint32_t t = 0; t < r.inputTriangles; ++t)
    for (int k = 0; k < 3; ++k)
      used[indices[3 * t + size_t(k)]] |= 2; // referenced by the input at all
  std::vector<uint32_t> newIndex(V, UINT32_MAX);
  for (uint32_t v = 0; v < V; ++v)
    if (used[v] & 1 && target[v] == UINT32_MAX)
      newIndex[v] = uint32_t(r.order.size()), r.order.push_back(source[v]);
  r.floorVertices = uint32_t(r.order.size());
  for (auto it = removed.rbegin(); it != removed.rend(); ++it)
    newIndex[*it] = uint32_t(r.order.size()), r.order.push_back(source[*it]);
  size_t isolated = 0;
  for (uint32_t v = 0; v < V; ++v)
    if (newIndex[v] == UINT32_MAX) {
      newIndex[v] = uint32_t(r.order.size()), r.order.push_back(source[v]);
      isolated += !(used[v] & 2);
    }
  if (isolated)
    reporter.warn("isolated_vertices",
                  std::to_string(isolated) + " vertices no triangle uses: last in the LOD order");
  r.collapse.resize(r.order.size());
  r.error.assign(r.order.size(), 0.0f);
  for (uint32_t v = 0; v < V; ++v) {
    uint32_t k = newIndex[v];
    r.collapse[k] = target[v] != UINT32_MAX ? newIndex[target[v]] : (k < r.floorVertices ? k : 0);
    r.error[k] = cost[v];
  }

  // Triangles: those that survive to the floor first, then the rest, last deleted first (the
  // lower its killer's new index, the later a triangle goes).
  std::vector<uint32_t> faces(F);
  for (uint32_t f = 0; f < F; ++f)
    faces[f] = f;
  auto death = [&](uint32_t f) {
    return killer[f] < 0 ? uint32_t(UINT32_MAX) : newIndex[size_t(killer[f])];
  };
  auto rank = [&](uint32_t f) { return killer[f] < 0 ? 0 : uint64_t(death(f)) + 1; };
  std::stable_sort(faces.begin(), faces.end(),
                   [&](uint32_t a, uint32_t b) { return rank(a) < rank(b); });
  // A face is alive at v vertices while its killer (new index d) is < v.
  r.triangleCount.assign(r.order.size() + 1, 0);
  for (uint32_t f : faces) {
    for (int k = 0; k < 3; ++k) // the input triangle's corners and winding
      r.indices.push_back(newIndex[initialCorner[f][size_t(k)]]);
    uint32_t d = death(f);
    ++r.triangleCount[d == UINT32_MAX ? 0 : d + 1];
    r.source.push_back(inputTriangle[f]);
    r.killedBy.push_back(d);
  }
  for (size_t v = 1; v < r.triangleCount.size(); ++v)
    r.triangleCount[v] += r.triangleCount[v - 1];
  return r;
}

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

void LodOptions::validate() const {
  if (!(floorFraction >= 0 && floorFraction <= 1))
    throw Error("floor: must be in [0, 1]");
  if (poses > 1024)
    throw Error("poses: must be an integer in [0, 1024]");
  if (!(maxNormalDeviationDeg > 0 && maxNormalDeviationDeg <= 180))
    throw Error("max normal deviation: must be in (0, 180] degrees");
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
  LodResult r = bakeLod(in.positions, lt.indices, o, reporter, lt.group, samplePoses(c, o.poses));
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

pack::Lod applyLod(Character &c, const LodOptions &o, Reporter &reporter, LodResult *details) {
  o.validate();
  SkinnedMesh &in = c.mesh;
  const std::vector<uint32_t> partOf = triangleParts(in);
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
  if (details)
    *details = std::move(r);
  return lod;
}

} // namespace crowd
