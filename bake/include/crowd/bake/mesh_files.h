// Posed meshes as files other tools read: PLY (binary little-endian or ASCII: x y z, nx ny nz
// and the int source_file, source_node, source_mesh, source_primitive, source_vertex per
// vertex, triangles), binary glTF (GLB) and Wavefront OBJ (v, vn, f). Point caches (PC2) are
// point_cache.h's.
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

} // namespace crowd
