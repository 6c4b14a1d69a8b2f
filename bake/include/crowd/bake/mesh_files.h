// Posed meshes as files other tools read: PLY (binary little-endian or ASCII: x y z, nx ny nz
// and the int source_file, source_node, source_mesh, source_primitive, source_vertex per
// vertex, triangles), binary glTF (GLB), Wavefront OBJ (v, vn, f) and PC2 point caches (Blender's
// "POINTCACHE2": positions of a fixed vertex list at evenly spaced samples).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/chunks.h"

namespace crowd {

std::vector<uint8_t> plyBytes(const std::vector<glm::vec3> &positions,
                              const std::vector<glm::vec3> &normals,
                              const std::vector<uint32_t> &indices,
                              const std::vector<pack::VertexSource> &sources, bool ascii = false);
std::vector<uint8_t> objBytes(const std::vector<glm::vec3> &positions,
                              const std::vector<glm::vec3> &normals,
                              const std::vector<uint32_t> &indices);
// A binary glTF (GLB) of one static mesh: positions, unit normals, triangles.
std::vector<uint8_t> glbBytes(const std::vector<glm::vec3> &positions,
                              const std::vector<glm::vec3> &normals,
                              const std::vector<uint32_t> &indices);
// `samples` all hold the same number of points; the header's start and spacing are in the
// caller's unit (crowdbake pose: seconds).
std::vector<uint8_t> pc2Bytes(const std::vector<std::vector<glm::vec3>> &samples, float start,
                              float spacing);

} // namespace crowd
