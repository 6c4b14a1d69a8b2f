// The mesh bakeLod collapses, built from an indexed triangle list as flat arrays: input vertices
// weld by position (within a group) into topological vertices, zero-area and duplicate triangles
// are dropped, and every edge that is not shared by exactly two consistently wound triangles is
// cut open. A vertex where several fans of triangles meet (two tubes sharing a cap's rim, a fin,
// two cones touching at their tips) becomes one topological vertex per fan, so each fan then
// simplifies on its own; a render vertex used by two fans is copied for the second.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace crowd::lod {

struct FanMesh {
  std::vector<std::array<uint32_t, 3>> vertex; // per face: its topological vertices
  std::vector<std::array<uint32_t, 3>> render; // per face: its render vertices
  std::vector<uint32_t> inputTriangle;         // per face: the input triangle it came from
  std::vector<glm::dvec3> position;            // per topological vertex (bind pose)
  std::vector<uint32_t> inputOf;               // per topological vertex: an input vertex at it
  std::vector<uint32_t> source;                // per render vertex: its input vertex
  size_t degenerate = 0, duplicate = 0;        // triangles dropped
  size_t splitVertices = 0, extraFans = 0;     // welded vertices cut into fans, fans added
  size_t cutEdges = 0;                         // edges with more than two faces, or mis-wound
};

// `group` (per input vertex, optional): vertices of different groups never weld.
FanMesh buildFanMesh(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                     const std::vector<uint32_t> &group);

} // namespace crowd::lod
